// npf_write_synthetic_materials OUTDIR: writes the synthetic RGL test materials (every kind the
// reader supports) to OUTDIR, one line per file on stdout: "<path> <rgb|spectral>". Used by the
// opt-in Mitsuba 3 cross-check, which needs the same files outside the C++ tests.
#include "synthetic_rgl.h"

#include <npf/core/error.h>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUTDIR\n", argv[0]);
        return 2;
    }
    struct Kind {
        const char* name;
        int phi_count, reduction;
        bool spectral, jacobian;
        float alpha_x, alpha_y;
    };
    const Kind kinds[] = {
        {"iso_rgb", 1, 1, false, true, 0.25f, 0.25f},
        {"iso_spectral", 1, 1, true, true, 0.25f, 0.25f},
        {"aniso_k1_rgb", 9, 1, false, true, 0.12f, 0.45f},
        {"aniso_k1_spectral", 9, 1, true, true, 0.45f, 0.12f},
        {"aniso_k2_spectral", 5, 2, true, true, 0.2f, 0.5f},
        {"aniso_k4_rgb", 3, 4, false, true, 0.5f, 0.2f},
        {"aniso_k4_spectral", 3, 4, true, true, 0.15f, 0.35f},
        {"iso_rgb_no_jacobian", 1, 1, false, false, 0.3f, 0.3f},
    };
    try {
        for (const Kind& k : kinds) {
            npf::testing::SyntheticRglSpec spec;
            spec.phi_count = k.phi_count;
            spec.reduction = k.reduction;
            spec.spectral = k.spectral;
            spec.jacobian = k.jacobian;
            spec.alpha_x = k.alpha_x;
            spec.alpha_y = k.alpha_y;
            spec.description = std::string("synthetic ") + k.name;
            const std::string path = std::string(argv[1]) + "/" + k.name + ".bsdf";
            npf::testing::write_synthetic_rgl(spec, path);
            std::printf("%s %s\n", path.c_str(), k.spectral ? "spectral" : "rgb");
        }
    } catch (const npf::Error& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
    return 0;
}
