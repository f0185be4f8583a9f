// Opt-in (Slow*): each edit on a material of the paper's size (D and G 90 x 180, F 90, 195
// wavelengths, SVD ranks 8 and 6), timed, with the invariants checked at that size.
#include "npf_test_factors.h"

#include <npf/fit/spectral_compression.h>
#include <npf/shading/npf_albedo.h>
#include <npf/edit/colour_edits.h>
#include <npf/edit/ndf_transform.h>
#include <npf/edit/thin_film.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

TEST(SlowEditTiming, PaperSizedMaterial) {
    npf::testing::MicrofacetSpec s;
    s.spectral = true;
    s.channels = 195;
    s.alpha_x = 0.08;
    s.alpha_y = 0.35;
    s.rho_d = 0.02;
    s.rho_s = 0.2;
    s.set_grid(90, 180, 90, 90, 180);
    npf::CompressionOptions o;
    o.d_rank = 8;
    o.g_rank = 6;
    const npf::NpfModel m = npf::compress_factors(npf::testing::make_microfacet_factors(s), o);

    auto t = std::chrono::steady_clock::now();
    npf::edit::EditRecord r;
    const npf::NpfModel stretched = npf::edit::transform_ndf(m, npf::edit::stretch_matrix(2.0, 0.7), {}, &r);
    const double t_ndf = seconds_since(t);
    for (double a : npf::edit::projected_area(stretched)) EXPECT_NEAR(a, 1.0, 1e-3);
    EXPECT_EQ(stretched.D.rank, 8);

    t = std::chrono::steady_clock::now();
    const npf::NpfModel back = npf::edit::transform_ndf(stretched, npf::edit::stretch_matrix(0.5, 1.0 / 0.7));
    const double t_back = seconds_since(t);
    double num = 0.0, den = 0.0;
    for (std::size_t c = 0; c < m.channel_count(); c += 10) {
        for (std::size_t k = 0; k < m.D.cells; ++k) {
            const int i = int(k / 180);
            const double u = (i + 0.5) / 90, th = 0.5 * npf::kPiD * u * u, w = std::cos(th) * std::sin(th) * u;
            const double a = std::max(0.0, m.D.at(c, k)), b = std::max(0.0, back.D.at(c, k));
            num += w * (a - b) * (a - b);
            den += w * a * a;
        }
    }

    t = std::chrono::steady_clock::now();
    const npf::NpfModel diffuse = npf::edit::replace_diffuse_albedo(m, npf::color::Rgb{0.6, 0.2, 0.1});
    const double t_diffuse = seconds_since(t);

    t = std::chrono::steady_clock::now();
    npf::edit::ThinFilm f;
    f.thickness_nm = 615;
    f.film_eta = npf::color::SampledSpectrum::constant(1.3);
    const npf::NpfModel film = npf::edit::apply_thin_film(m, f);
    const double t_film = seconds_since(t);

    t = std::chrono::steady_clock::now();
    const npf::AlbedoPeak a = npf::npf_largest_albedo(stretched);
    const double t_albedo = seconds_since(t);
    std::printf("[ measured ] paper-sized material (195 wavelengths, ranks 8/6): ndf stretch %.2f s, inverse %.2f s "
                "(round trip D rel. RMS %.4f); diffuse %.3f s; thin film (fitted base) %.3f s; albedo check %.2f s "
                "(largest %.4f)\n  %s\n",
                t_ndf, t_back, std::sqrt(num / den), t_diffuse, t_film, t_albedo, a.max, r.summary.c_str());
    EXPECT_LT(std::sqrt(num / den), 0.02);
    EXPECT_LE(a.max, 1.0);
}

}  // namespace
