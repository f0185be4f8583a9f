#include "cli_materials.h"

#include "synthetic_rgl.h"

namespace npf::testing {

const std::string& cli_folder() {
    static const std::string dir = temporary_folder("cli");
    return dir;
}

const CliMaterials& cli_materials() {
    static const CliMaterials m = [] {
        CliMaterials r;
        SyntheticRglSpec s;
        s.description = "cli rgb";
        r.rgb = write_synthetic_rgl(s, cli_folder() + "/iso_rgb.bsdf");
        s = SyntheticRglSpec();
        s.phi_count = 5;
        s.reduction = 2;
        s.spectral = true;
        s.alpha_x = 0.2f;
        s.alpha_y = 0.5f;
        s.ndf_size = 32;
        s.description = "cli spectral";
        r.spectral = write_synthetic_rgl(s, cli_folder() + "/aniso_spectral.bsdf");
        s.spectral = false;
        s.reduction = 1;
        s.description = "cli rgb aniso";
        r.rgb_aniso = write_synthetic_rgl(s, cli_folder() + "/aniso_rgb.bsdf");
        return r;
    }();
    return m;
}

}  // namespace npf::testing
