#include "cli_materials.h"

#include "synthetic_rgl.h"

namespace npf::testing {

const std::string& cli_folder() {
    static const std::string dir = temporary_folder("cli");
    return dir;
}

namespace {

// The anisotropic files: five azimuths over 2 pi / reduction and a lobe wider along the
// bitangent, with a coarser NDF table than the default.
SyntheticRglSpec anisotropic(int reduction, bool spectral, const char* description) {
    SyntheticRglSpec s;
    s.phi_count = 5;
    s.reduction = reduction;
    s.spectral = spectral;
    s.alpha_x = 0.2f;
    s.alpha_y = 0.5f;
    s.ndf_size = 32;
    s.description = description;
    return s;
}

}  // namespace

const CliMaterials& cli_materials() {
    static const CliMaterials m = [] {
        CliMaterials r;
        SyntheticRglSpec rgb;
        rgb.description = "cli rgb";
        r.rgb = write_synthetic_rgl(rgb, cli_folder() + "/iso_rgb.bsdf");
        r.spectral = write_synthetic_rgl(anisotropic(2, true, "cli spectral"), cli_folder() + "/aniso_spectral.bsdf");
        r.rgb_aniso = write_synthetic_rgl(anisotropic(1, false, "cli rgb aniso"), cli_folder() + "/aniso_rgb.bsdf");
        return r;
    }();
    return m;
}

}  // namespace npf::testing
