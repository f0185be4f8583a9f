// The RGL reader against files with missing fields, wrong dtypes and disagreeing shapes: both
// loaders reject them with an npf::Error naming the file and the problem.

#include "rgl_bad_input.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/core/error.h>
#include <npf/materials/open_material.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/materials/tensor_file.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <sys/stat.h>

namespace {

using namespace npf::testing::rgl_bad_input;
using npf::DType, npf::testing::find_field, npf::testing::remove_field, npf::testing::synthetic_rgl_fields,
      npf::testing::SyntheticField, npf::testing::SyntheticRglSpec;

// ---- Required fields, dtypes and shapes ---------------------------------------------------

TEST(RglBadInputFields, MissingRequiredField) {
    for (const char* name : {"phi_i", "theta_i", "ndf", "sigma", "vndf", "luminance"}) {
        Fields f = synthetic_rgl_fields(small_spec());
        ASSERT_TRUE(remove_field(f, name));
        expect_rejected_fields(std::string("missing_") + name + ".bsdf", f,
                               std::string("missing required field '") + name + "'");
    }
}

TEST(RglBadInputFields, MissingRgbAndSpectra) {
    Fields f = synthetic_rgl_fields(small_spec());
    ASSERT_TRUE(remove_field(f, "rgb"));
    expect_rejected_fields("missing_data.bsdf", f, "missing required field 'rgb' or 'spectra'");
    f = synthetic_rgl_fields(small_spec(true));
    ASSERT_TRUE(remove_field(f, "spectra"));
    expect_rejected_fields("missing_spectra.bsdf", f, "missing required field 'rgb' or 'spectra'");
}

TEST(RglBadInputFields, SpectraWithoutWavelengths) {
    Fields f = synthetic_rgl_fields(small_spec(true));
    ASSERT_TRUE(remove_field(f, "wavelengths"));
    expect_rejected_fields("no_wavelengths.bsdf", f, "missing required field 'wavelengths'");
}

TEST(RglBadInputFields, WrongDtype) {
    {  // f64 ndf with the right values and shape.
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& ndf = *find_field(f, "ndf");
        std::vector<double> d;
        for (float v : ndf.floats()) d.push_back(v);
        ndf.dtype = DType::F64;
        ndf.bytes.resize(d.size() * 8);
        std::memcpy(ndf.bytes.data(), d.data(), ndf.bytes.size());
        expect_rejected_fields("ndf_f64.bsdf", f, "field 'ndf' has dtype f64, expected f32");
    }
    {  // f16 theta_i: two bytes per element.
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& theta = *find_field(f, "theta_i");
        theta.dtype = DType::F16;
        theta.bytes.resize(theta.bytes.size() / 2);
        expect_rejected_fields("theta_f16.bsdf", f, "field 'theta_i' has dtype f16, expected f32");
    }
    {  // u8 luminance.
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& lum = *find_field(f, "luminance");
        lum.dtype = DType::U8;
        lum.bytes.resize(lum.bytes.size() / 4, 1);
        expect_rejected_fields("luminance_u8.bsdf", f, "field 'luminance' has dtype u8, expected f32");
    }
    {  // f32 jacobian.
        Fields f = synthetic_rgl_fields(small_spec());
        find_field(f, "jacobian")->set_floats({1.f});
        expect_rejected_fields("jacobian_f32.bsdf", f, "field 'jacobian' has dtype f32, expected u8");
    }
    {  // f32 description.
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& d = *find_field(f, "description");
        d.shape = {2};
        d.set_floats({1.f, 2.f});
        expect_rejected_fields("description_f32.bsdf", f, "field 'description' must be u8 text");
    }
}

TEST(RglBadInputFields, WrongRank) {
    Fields f = synthetic_rgl_fields(small_spec());
    SyntheticField& ndf = *find_field(f, "ndf");
    ndf.shape.insert(ndf.shape.begin(), 1);
    expect_rejected_fields("ndf_rank3.bsdf", f, "field 'ndf' has shape [1, 2, 8], expected 2 dimensions");
    f = synthetic_rgl_fields(small_spec());
    SyntheticField& vndf = *find_field(f, "vndf");
    vndf.shape = {vndf.shape[1], vndf.shape[2], vndf.shape[3]};
    expect_rejected_fields("vndf_rank3.bsdf", f, "field 'vndf' has shape [3, 6, 6], expected 4 dimensions");
    f = synthetic_rgl_fields(small_spec());
    SyntheticField& theta = *find_field(f, "theta_i");
    theta.shape = {1, theta.shape[0]};
    expect_rejected_fields("theta_rank2.bsdf", f, "field 'theta_i' has shape [1, 3], expected 1 dimensions");
}

TEST(RglBadInputFields, JacobianNotOneByte) {
    Fields f = synthetic_rgl_fields(small_spec());
    SyntheticField& j = *find_field(f, "jacobian");
    j.shape = {2};
    j.bytes = {1, 1};
    expect_rejected_fields("jacobian_2.bsdf", f, "field 'jacobian' must hold exactly one u8");
    j.shape = {0};
    j.bytes = {};
    expect_rejected_fields("jacobian_0.bsdf", f, "field 'jacobian' must hold exactly one u8");
}

// Drops the last theta_i slice of a [nP, nT, ...] field, so its leading dims disagree.
void drop_last_theta_slice(SyntheticField& f) {
    std::uint64_t per_slice = 4;
    for (std::size_t d = 2; d < f.shape.size(); ++d) per_slice *= f.shape[d];
    f.shape[1] -= 1;
    f.bytes.resize(std::size_t(f.bytes.size() - per_slice));
}

TEST(RglBadInputFields, LeadingDimensionsDisagree) {
    for (const char* name : {"vndf", "luminance", "rgb"}) {
        Fields f = synthetic_rgl_fields(small_spec());
        drop_last_theta_slice(*find_field(f, name));
        expect_rejected_fields(std::string("leading_") + name + ".bsdf", f,
                               std::string("field '") + name + "' has shape [1, 2, ");
        expect_rejected_fields(std::string("leading2_") + name + ".bsdf", f,
                               "whose leading dimensions must be [phi_i, theta_i] = [1, 3]");
    }
    {  // The same bytes with the two leading dims swapped.
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& v = *find_field(f, "vndf");
        std::swap(v.shape[0], v.shape[1]);
        expect_rejected_fields("leading_swapped.bsdf", f, "field 'vndf' has shape [3, 1, 6, 6], whose leading");
    }
    {  // Spectral data.
        Fields f = synthetic_rgl_fields(small_spec(true));
        drop_last_theta_slice(*find_field(f, "spectra"));
        expect_rejected_fields("leading_spectra.bsdf", f, "field 'spectra' has shape [1, 2, 4, 4, 4], whose leading");
    }
}

TEST(RglBadInputFields, LuminanceGridDiffersFromData) {
    Fields f = synthetic_rgl_fields(small_spec());
    SyntheticRglSpec other = small_spec();
    other.data_size = 5;
    Fields g = synthetic_rgl_fields(other);
    *find_field(f, "luminance") = *find_field(g, "luminance");
    expect_rejected_fields("luminance_grid.bsdf", f,
                           "field 'luminance' has shape [1, 3, 5, 5], whose inner dimensions must equal the "
                           "data grid of 'rgb' [1, 3, 3, 4, 4]");
}

TEST(RglBadInputFields, RgbThirdDimensionNotThree) {
    Fields f = synthetic_rgl_fields(small_spec());
    SyntheticField& rgb = *find_field(f, "rgb");
    std::vector<float> v = rgb.floats(), four;
    const std::size_t plane = 16;
    for (std::size_t s = 0; s < 3; ++s) {  // per theta slice: R G B plus a copy of B
        four.insert(four.end(), v.begin() + long(s * 3 * plane), v.begin() + long((s + 1) * 3 * plane));
        four.insert(four.end(), v.begin() + long((s * 3 + 2) * plane), v.begin() + long((s * 3 + 3) * plane));
    }
    rgb.shape[2] = 4;
    rgb.set_floats(four);
    expect_rejected_fields("rgb_4.bsdf", f, "field 'rgb' has shape [1, 3, 4, 4, 4]; its third dimension must be 3");
}

TEST(RglBadInputFields, NonSquareData) {
    Fields f = synthetic_rgl_fields(small_spec());
    SyntheticField& rgb = *find_field(f, "rgb");
    rgb.shape[3] = 8;
    rgb.shape[4] = 2;
    expect_rejected_fields("nonsquare.bsdf", f, "field 'rgb' data grid [1, 3, 3, 8, 2] is not square");
    f = synthetic_rgl_fields(small_spec(true));
    SyntheticField& sp = *find_field(f, "spectra");
    sp.shape[3] = 2;
    sp.shape[4] = 8;
    expect_rejected_fields("nonsquare_spectra.bsdf", f, "field 'spectra' data grid [1, 3, 4, 2, 8] is not square");
}

TEST(RglBadInputFields, SpectraDisagreeWithWavelengths) {
    Fields f = synthetic_rgl_fields(small_spec(true));
    SyntheticField& wl = *find_field(f, "wavelengths");
    wl.shape = {3};
    wl.set_floats({400.f, 550.f, 700.f});
    expect_rejected_fields("wavelengths_3.bsdf", f,
                           "field 'spectra' has shape [1, 3, 4, 4, 4] but there are 3 wavelengths");
    wl.shape = {5};
    wl.set_floats({400.f, 450.f, 550.f, 600.f, 700.f});
    expect_rejected_fields("wavelengths_5.bsdf", f, "but there are 5 wavelengths");
}

TEST(RglBadInputFields, TableDimensionOfOne) {
    SyntheticRglSpec s = small_spec();
    s.ndf_size = 1;
    expect_rejected_fields("ndf_1.bsdf", synthetic_rgl_fields(s),
                           "field 'ndf': table is 2 x 1; every table dimension must be at least 2");
    {  // one ndf row
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& ndf = *find_field(f, "ndf");
        ndf.shape[0] = 1;
        ndf.bytes.resize(ndf.bytes.size() / 2);
        expect_rejected_fields("ndf_row.bsdf", f, "field 'ndf': table is 1 x 8; every table dimension");
        SyntheticField& sigma = *find_field(f, "sigma");
        sigma.shape[0] = 1;
        sigma.bytes.resize(sigma.bytes.size() / 2);
        expect_rejected_fields("ndf_sigma_row.bsdf", f, "field 'ndf': table is 1 x 8");
        Fields fresh = synthetic_rgl_fields(small_spec());
        *find_field(f, "ndf") = *find_field(fresh, "ndf");
        expect_rejected_fields("sigma_row.bsdf", f, "field 'sigma': table is 1 x 8");
    }
    s = small_spec();
    s.vndf_size = 1;
    expect_rejected_fields("vndf_1.bsdf", synthetic_rgl_fields(s), "field 'vndf': table is 1 x 1");
    s = small_spec();
    s.data_size = 1;
    // The luminance table shares the data grid and is checked first.
    expect_rejected_fields("data_1.bsdf", synthetic_rgl_fields(s), "field 'luminance': table is 1 x 1");
    s.spectral = true;
    expect_rejected_fields("data_1_spectral.bsdf", synthetic_rgl_fields(s), "table is 1 x 1");
}

TEST(RglBadInputFields, EmptyGrids) {
    for (const char* name : {"phi_i", "theta_i"}) {
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& g = *find_field(f, name);
        g.shape = {0};
        g.bytes.clear();
        expect_rejected_fields(std::string("empty_") + name + ".bsdf", f, std::string("field '") + name + "' is empty");
    }
    Fields f = synthetic_rgl_fields(small_spec(true));
    SyntheticField& wl = *find_field(f, "wavelengths");
    wl.shape = {0};
    wl.bytes.clear();
    expect_rejected_fields("empty_wavelengths.bsdf", f, "field 'wavelengths' is empty");
}

}  // namespace
