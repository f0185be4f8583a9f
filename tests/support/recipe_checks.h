// Shared by the material recipe tests (test_material_recipe*.cpp): parsing a recipe from text,
// the expectation on its error message ("file:line: key '...': problem"), and comparisons of
// the spectra and Fresnel terms a recipe gives with ones built directly.
#pragma once

#include "run_tool.h"

#include <npf/color/spectrum.h>
#include <npf/core/error.h>
#include <npf/materials/analytic/fresnel.h>
#include <npf/materials/data_files.h>
#include <npf/materials/material_recipe.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace npf::testing::recipe {

using npf::Fresnel, npf::MaterialRecipe, npf::MicrofacetDistribution, npf::color::SampledSpectrum,
      npf::testing::contains;

inline constexpr double kPi = npf::kPiD;
inline const std::string kShipped = std::string(NPF_SOURCE_DIR) + "/configs/materials";

inline MaterialRecipe parse(const std::string& yaml, const std::string& base_dir = "/recipes") {
    return npf::parse_material_recipe(yaml, "r.yaml", base_dir);
}

// The message of the npf::Error that parsing `yaml` throws ("" if none, with a test failure).
inline std::string error_of(const std::string& yaml) {
    try {
        parse(yaml);
    } catch (const npf::Error& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not an npf::Error: " << e.what() << "\nrecipe:\n" << yaml;
        return e.what();
    }
    ADD_FAILURE() << "no error for the recipe:\n" << yaml;
    return "";
}

// Expects the error message of `yaml` to start with `prefix` (e.g. "r.yaml:3: key 'alpha': ")
// and to contain `problem`.
inline void expect_error(const std::string& yaml, const std::string& prefix, const std::string& problem) {
    const std::string e = error_of(yaml);
    EXPECT_EQ(e.rfind(prefix, 0), 0u) << "message: " << e << "\nexpected it to start with: " << prefix
                                      << "\nrecipe:\n" << yaml;
    EXPECT_TRUE(contains(e, problem)) << "message: " << e << "\nexpected it to contain: " << problem << "\nrecipe:\n"
                                      << yaml;
}

inline void write_file(const std::string& path, const std::string& text) {
    ASSERT_TRUE(write_text(path, text)) << "cannot write " << path;
}

inline const std::vector<double> kTestWavelengths = {380.0, 450.0, 532.0, 610.0, 700.0, 780.0};
inline const std::vector<double> kTestCosines = {0.05, 0.3, 0.7, 1.0};

// Both Fresnel terms agree at a few angles and wavelengths (relative 1e-9).
inline void expect_same_fresnel(const Fresnel& got, const Fresnel& want, const std::string& what) {
    EXPECT_EQ(int(got.kind()), int(want.kind())) << what;
    for (double l : kTestWavelengths) {
        for (double c : kTestCosines) {
            const double g = got.eval(c, l), w = want.eval(c, l);
            EXPECT_NEAR(g, w, 1e-9 * std::fabs(w) + 1e-12) << what << " at cos " << c << ", " << l << " nm";
        }
    }
}

inline void expect_same_spectrum(const SampledSpectrum& got, const SampledSpectrum& want, const std::string& what) {
    ASSERT_FALSE(got.empty()) << what;
    for (double l : {360.0, 380.0, 450.0, 500.0, 532.0, 610.0, 700.0, 780.0, 830.0}) {
        EXPECT_NEAR(got(l), want(l), 1e-12 + 1e-9 * std::fabs(want(l))) << what << " at " << l << " nm";
    }
}

inline SampledSpectrum constant(double v) { return SampledSpectrum::constant(v); }

inline SampledSpectrum srgb(double r, double g, double b) {
    using namespace npf::color;
    return linear_srgb_to_spectrum({srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b)});
}

inline SampledSpectrum shipped_ior(const std::string& metal, const std::string& part) {
    const std::string path = npf::find_data_file("ior/" + metal + "." + part + ".spd");
    EXPECT_FALSE(path.empty()) << "ior/" << metal << "." << part << ".spd not found";
    return path.empty() ? constant(1.0) : npf::color::read_spd(path);
}

inline Fresnel metal(const std::string& name) { return Fresnel::conductor(shipped_ior(name, "eta"), shipped_ior(name, "k")); }

inline void expect_grid(const npf::RglWriterOptions& w, int phi, int theta, int ndf, int ndf_rows, int vndf, int data) {
    EXPECT_EQ(w.phi_count, phi);
    EXPECT_EQ(w.theta_count, theta);
    EXPECT_EQ(w.ndf_size, ndf);
    EXPECT_EQ(w.ndf_rows, ndf_rows);
    EXPECT_EQ(w.vndf_size, vndf);
    EXPECT_EQ(w.data_size, data);
}

inline void expect_spectral_range(const MaterialRecipe& r, std::size_t count, float first, float last) {
    ASSERT_FALSE(r.writer.channels.is_rgb());
    const std::vector<float>& w = r.writer.channels.wavelengths();
    ASSERT_EQ(w.size(), count);
    EXPECT_FLOAT_EQ(w.front(), first);
    EXPECT_FLOAT_EQ(w.back(), last);
    EXPECT_EQ(r.material.wavelengths, w);  // the material reports the file's wavelengths
}

}  // namespace npf::testing::recipe
