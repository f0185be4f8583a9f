// The RGL reader against files whose values are wrong (non-finite, negative, not ascending,
// grids that miss the folded interval): both loaders reject them, naming the file and problem.

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
using npf::testing::find_field, npf::testing::synthetic_rgl_fields, npf::testing::SyntheticField,
      npf::testing::SyntheticRglSpec;

// ---- Values -------------------------------------------------------------------------------

TEST(RglBadInputValues, NonFiniteValues) {
    struct Case {
        const char* field;
        bool spectral;
    };
    const Case cases[] = {{"ndf", false},       {"sigma", false},   {"vndf", false},        {"luminance", false},
                          {"rgb", false},       {"theta_i", false}, {"phi_i", false},       {"spectra", true},
                          {"wavelengths", true}, {"luminance", true}, {"vndf", true}};
    const float bad_values[] = {kNaN, kInf, -kInf};
    for (const Case& c : cases) {
        for (int which = 0; which < 3; ++which) {
            for (int where = 0; where < 2; ++where) {  // first element, then a middle one
                Fields f = synthetic_rgl_fields(small_spec(c.spectral));
                SyntheticField& field = *find_field(f, c.field);
                std::vector<float> v = field.floats();
                const std::size_t index = where == 0 ? 0 : v.size() / 2 + 1;
                if (index >= v.size()) continue;
                v[index] = bad_values[which];
                field.set_floats(v);
                const std::string name = std::string("nonfinite_") + c.field + (c.spectral ? "_spec_" : "_") +
                                         std::to_string(which) + "_" + std::to_string(index) + ".bsdf";
                const std::string path = write_fields(name, f);
                SCOPED_TRACE(name);
                expect_rejected(path, std::string("field '") + c.field + "'");
                expect_rejected(path, "non-finite value");
            }
        }
    }
}

TEST(RglBadInputValues, NegativeDensity) {
    for (const char* name : {"vndf", "luminance"}) {
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& field = *find_field(f, name);
        std::vector<float> v = field.floats();
        v[v.size() / 2] = -1e-3f;
        field.set_floats(v);
        expect_rejected_fields(std::string("negative_") + name + ".bsdf", f,
                               std::string("field '") + name + "': negative density");
    }
}

TEST(RglBadInputValues, NegativeNdfOrSigma) {
    // Unchecked by the reference readers, but a negative D or sigma would make eval_cos
    // negative after the channel clamp.
    for (const char* name : {"ndf", "sigma"}) {
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& field = *find_field(f, name);
        std::vector<float> v = field.floats();
        v[3] = -0.25f;
        field.set_floats(v);
        expect_rejected_fields(std::string("negative_") + name + ".bsdf", f,
                               std::string("field '") + name + "' holds a negative value");
    }
}

TEST(RglBadInputValues, AnisotropicGridMissesTheFoldedInterval) {
    // Right span, wrong place: folded queries have phi_i in [-pi, -pi + 2 pi / k].
    struct Case {
        int reduction;
        float shift;
    };
    for (const Case c : {Case{1, npf::kPi}, Case{2, npf::kPi}, Case{4, npf::kPi / 2}, Case{4, 0.3f}}) {
        Fields f = synthetic_rgl_fields(small_aniso_spec(c.reduction));
        SyntheticField& phi = *find_field(f, "phi_i");
        std::vector<float> v = phi.floats();
        for (float& x : v) x += c.shift;
        phi.set_floats(v);
        expect_rejected_fields("phi_shifted_k" + std::to_string(c.reduction) + ".bsdf", f,
                               "needs it to cover [-pi, ");
    }
}

TEST(RglBadInputValues, AllZeroSlice) {
    for (const char* name : {"luminance", "vndf"}) {
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& field = *find_field(f, name);
        std::vector<float> v = field.floats();
        const std::size_t plane = v.size() / 3;  // three theta slices
        std::fill(v.begin() + long(plane), v.begin() + long(2 * plane), 0.f);
        field.set_floats(v);
        expect_rejected_fields(std::string("zero_slice_") + name + ".bsdf", f,
                               std::string("field '") + name + "': slice 1 has zero total density");
    }
}

TEST(RglBadInputValues, PhiNotAscending) {
    {  // anisotropic: two entries swapped
        Fields f = synthetic_rgl_fields(small_aniso_spec(1));
        SyntheticField& phi = *find_field(f, "phi_i");
        std::vector<float> v = phi.floats();
        std::swap(v[1], v[2]);
        phi.set_floats(v);
        expect_rejected_fields("phi_swapped.bsdf", f, "field 'phi_i' is not strictly ascending at index 2");
        Fields fresh = synthetic_rgl_fields(small_aniso_spec(1));
        v = find_field(fresh, "phi_i")->floats();
        v[3] = v[2];
        phi.set_floats(v);
        expect_rejected_fields("phi_repeated.bsdf", f, "field 'phi_i' is not strictly ascending at index 3");
    }
    {  // two entries (isotropic by count), descending
        SyntheticRglSpec s = small_spec();
        s.phi_count = 2;
        Fields f = synthetic_rgl_fields(s);
        find_field(f, "phi_i")->set_floats({1.f, -1.f});
        expect_rejected_fields("phi_descending.bsdf", f, "field 'phi_i' is not strictly ascending at index 1");
    }
}

TEST(RglBadInputValues, ThetaNotAscending) {
    Fields f = synthetic_rgl_fields(small_spec());
    find_field(f, "theta_i")->set_floats({0.f, 1.f, 0.5f});
    expect_rejected_fields("theta_descending.bsdf", f, "field 'theta_i' is not strictly ascending at index 2");
}

TEST(RglBadInputValues, ThetaOutsideQuarterCircle) {
    Fields f = synthetic_rgl_fields(small_spec());
    find_field(f, "theta_i")->set_floats({0.f, 0.8f, 1.6f});
    expect_rejected_fields("theta_beyond.bsdf", f, "field 'theta_i' leaves [0, pi/2]");
    find_field(f, "theta_i")->set_floats({-0.1f, 0.8f, 1.5f});
    expect_rejected_fields("theta_negative.bsdf", f, "field 'theta_i' leaves [0, pi/2]");
    find_field(f, "theta_i")->set_floats({0.f, 2.f, 3.f});
    expect_rejected_fields("theta_far.bsdf", f, "field 'theta_i' leaves [0, pi/2]");
}

TEST(RglBadInputValues, AnisotropicSpanNotAFractionOfTheCircle) {
    for (int reduction : {3, 5, 8}) {
        expect_rejected_fields("span_k" + std::to_string(reduction) + ".bsdf",
                               synthetic_rgl_fields(small_aniso_spec(reduction)),
                               "only the full circle, a half or a quarter (reductions 1, 2, 4) are supported");
    }
    for (double factor : {0.9, 1.05, 2.0, 0.55}) {  // spans of 0.9, 1.05, 2 and 0.55 full circles
        Fields f = synthetic_rgl_fields(small_aniso_spec(1));
        SyntheticField& phi = *find_field(f, "phi_i");
        std::vector<float> v = phi.floats();
        for (float& x : v) x = float(double(x) * factor);
        phi.set_floats(v);
        expect_rejected_fields("span_factor_" + std::to_string(factor) + ".bsdf", f,
                               "field 'phi_i' spans ");
    }
}

TEST(RglBadInputValues, WavelengthsNotPositiveOrNotAscending) {
    Fields f = synthetic_rgl_fields(small_spec(true));
    find_field(f, "wavelengths")->set_floats({-100.f, 500.f, 600.f, 700.f});
    expect_rejected_fields("wavelengths_negative.bsdf", f, "field 'wavelengths' must be positive (nm)");
    find_field(f, "wavelengths")->set_floats({0.f, 500.f, 600.f, 700.f});
    expect_rejected_fields("wavelengths_zero.bsdf", f, "field 'wavelengths' must be positive (nm)");
    find_field(f, "wavelengths")->set_floats({400.f, 600.f, 500.f, 700.f});
    expect_rejected_fields("wavelengths_order.bsdf", f, "field 'wavelengths' is not strictly ascending at index 2");
}

}  // namespace
