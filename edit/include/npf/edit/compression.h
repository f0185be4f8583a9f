// Re-compression of a fitted material's D and G across wavelengths at another rank or PCA
// ratio, without refitting: the per-channel tables are rebuilt from the stored bases and their
// SVD truncated again (spectral_compression.h). From a losslessly stored file (`--pca 1,1`) this
// gives exactly what `npf convert --rank` or `--pca` would have written from the same fit, in a
// second instead of a refit; from an already compressed file it can only lower the rank.
#pragma once

#include <npf/fit/spectral_compression.h>
#include <npf/edit/edit_record.h>
#include <npf/shading/npf_model.h>

namespace npf::edit {

// Throws npf::Error for options out of range. rho_d, rho_s and F are kept as they are.
NpfModel compress_model(const NpfModel& model, const CompressionOptions& options, EditRecord* record = nullptr);

}  // namespace npf::edit
