// A conversion is a value (issue 36): npf::convert returns the model and its report and writes
// nothing; convert_material is convert and one write, byte for byte, so a caller (the batch, the
// Python package) may edit or shade the model without a round trip through a file.
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/converter/convert.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/shading/npf_texture_file.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

namespace {

std::string bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(ConversionValue, ConvertWritesNothingAndItsModelIsWhatConvertMaterialWrites) {
    const std::string dir = npf::testing::temporary_folder("conversion-value");
    const std::string source_path = npf::testing::write_synthetic_rgl(npf::testing::SyntheticRglSpec{}, dir + "/lobe.bsdf");
    const std::unique_ptr<npf::RglBrdf> source = npf::RglBrdf::load(source_path);
    npf::ConvertSettings s = npf::preset_settings(npf::ConvertPreset::Preview, source->info().isotropic);
    s.predict_psnr = false;
    s.fit.threads = 2;

    const npf::Conversion c = npf::convert(*source, s);
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()), 1)
        << "convert wrote a file";
    EXPECT_EQ(c.report.output_bytes, 0u);
    EXPECT_FALSE(c.model.metadata.empty());
    EXPECT_GT(c.report.held_out.used, 0u);

    const npf::ConvertReport written = npf::convert_material(*source, dir + "/written.exr", s);
    npf::write_npf_texture(c.model, dir + "/from_value.exr");
    EXPECT_EQ(bytes_of(dir + "/from_value.exr"), bytes_of(dir + "/written.exr"));
    EXPECT_EQ(written.output_bytes, std::filesystem::file_size(dir + "/written.exr"));
    EXPECT_EQ(written.held_out.relative_rms, c.report.held_out.relative_rms);
}

}  // namespace
