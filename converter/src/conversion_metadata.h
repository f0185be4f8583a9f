// What convert() records in the model's metadata (docs/format.md sec. 4): the source, the
// settings as fitted (their rows' lines, sorted by key), then the results in the order the
// conversion measures them.
#pragma once

#include <npf/converter/convert.h>

namespace npf {

// `fit`: the fitter's options as run (after isotropy); `compression`: as applied (after the RGB
// rule); the model's detail grid is the one written.
void record_conversion(NpfModel& model, const BrdfInfo& info, const ConvertSettings& settings, const AwlsOptions& fit,
                       const CompressionOptions& compression, const ConvertReport& report);

}  // namespace npf
