// The portable angle kernels: the scalar closure's own code (pair_angles) pair by pair.
#include "batch_angles.h"

namespace npf::batch_detail {

void angles_portable(std::size_t n, const float* const view[3], const float* const light[3], AngleNeeds needs,
                     BlockAngles& out, std::size_t first) {
    for (std::size_t i = first; i < first + n; ++i) {
        PairAngles a;
        pair_angles(view[0][i], view[1][i], view[2][i], light[0][i], light[1][i], light[2][i], needs, a);
        store_angles(out, i, a, [](double* p, double v) { *p = v; });
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
