// The portable angle kernels: the scalar closure's own code (pair_angles) pair by pair.
#include "batch_angles.h"

namespace npf::batch_detail {

void angles_portable(std::size_t n, const float* const view[3], const float* const light[3], AngleNeeds needs,
                     BlockAngles& out, std::size_t first) {
    for (std::size_t i = first; i < first + n; ++i) {
        PairAngles a;
        pair_angles(view[0][i], view[1][i], view[2][i], light[0][i], light[1][i], light[2][i], needs, a);
        out.cos_i[i] = a.cos_i;
        out.cos_o[i] = a.cos_o;
        out.inv_cos_product[i] = a.inv_cos_product;
        out.theta_h[i] = a.theta_h;
        out.u_h[i] = a.u_h;
        out.phi_h[i] = a.phi_h;
        out.cos_d[i] = a.cos_d;
        out.theta_d[i] = a.theta_d;
        out.theta_gi[i] = a.theta_gi;
        out.phi_gi[i] = a.phi_gi;
        out.theta_go[i] = a.theta_go;
        out.phi_go[i] = a.phi_go;
        out.phi_d[i] = a.phi_d;
    }
}

void half_vectors_portable(std::size_t n, const float* const view[3], const float* const light[3], bool d_azimuth,
                           BlockHalfVectors& out, std::size_t first) {
    for (std::size_t i = first; i < first + n; ++i) {
        half_vector_angles(view[0][i], view[1][i], view[2][i], light[0][i], light[1][i], light[2][i], d_azimuth,
                           out.theta_h[i], out.u_h[i], out.phi_h[i], out.cos_d[i]);
    }
}

}  // namespace npf::batch_detail
