// npf_bench_fit: time and accuracy of the NPF fitter (AWLS) on one source, with a breakdown of
// where the time goes and the peak memory. Not a test: the paper-size runs take minutes.
//
//   build/bench/npf_bench_fit SOURCE [--grid TH,PH,TD,PD] [--g-grid T,P] [--phi-d-samples K]
//        [--wavelengths rgb|LIST|START:END:COUNT] [--iterations N] [--tolerance T]
//        [--threads N] [--importance P] [--compressive P] [--epsilon E] [--three-angle]
//        [--pairs N]
//
// SOURCE is a material file (RGL, MERL, ...) or a recipe (.yaml), fitted analytically.
#include <npf/fit/awls.h>
#include <npf/fit/fit_error.h>
#include <npf/materials/open_material.h>
#include <npf/core/error.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <sys/resource.h>

namespace {

double peak_rss_gib() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / (1024.0 * 1024.0);
}

}  // namespace

int main(int argc, char** argv) try {
    if (argc < 2) {
        std::fprintf(stderr, "usage: npf_bench_fit SOURCE [options] (see the file's header)\n");
        return 2;
    }
    const std::string path = argv[1];
    npf::AwlsOptions o;
    std::string wavelengths;
    int pairs = 20000;
    for (int i = 2; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) throw npf::Error(a, "needs a value");
            return argv[++i];
        };
        if (a == "--grid") {
            const std::string v = next();
            if (std::sscanf(v.c_str(), "%d,%d,%d,%d", &o.grid.theta_h, &o.grid.phi_h, &o.grid.theta_d, &o.grid.phi_d) != 4)
                throw npf::Error(a, "expects TH,PH,TD,PD");
        } else if (a == "--g-grid") {
            const std::string v = next();
            if (std::sscanf(v.c_str(), "%d,%d", &o.g_theta, &o.g_phi) != 2) throw npf::Error(a, "expects T,P");
        } else if (a == "--phi-d-samples") o.phi_d_samples = std::atoi(next().c_str());
        else if (a == "--wavelengths") wavelengths = next();
        else if (a == "--iterations") o.max_iterations = std::atoi(next().c_str());
        else if (a == "--tolerance") o.tolerance = std::atof(next().c_str());
        else if (a == "--threads") o.threads = std::atoi(next().c_str());
        else if (a == "--importance") o.importance_power_view = o.importance_power_light = std::atof(next().c_str());
        else if (a == "--compressive") o.compressive_power = std::atof(next().c_str());
        else if (a == "--epsilon") o.compressive_epsilon = std::atof(next().c_str());
        else if (a == "--plain") o.acceleration = npf::AwlsOptions::Acceleration::None;
        else if (a == "--three-angle") o.volume_weight = npf::VolumeWeight::ThreeAngle;
        else if (a == "--pairs") pairs = std::atoi(next().c_str());
        else throw npf::Error(a, "unknown option");
    }
    const std::unique_ptr<npf::Brdf> source = npf::open_material(path);
    const npf::Channels stored = source->info().channels;
    o.channels = wavelengths.empty() ? stored : npf::parse_channel_list(wavelengths, "--wavelengths");
    npf::AwlsReport r;
    const auto t0 = std::chrono::steady_clock::now();
    const npf::NpfFactors f = npf::fit_npf(*source, o, &r);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::size_t C = f.channel_count();
    int it_min = 1 << 30, it_max = 0;
    double e_max = 0.0, e_mean = 0.0;
    for (std::size_t c = 0; c < C; ++c) {
        it_min = std::min(it_min, r.iterations[c]);
        it_max = std::max(it_max, r.iterations[c]);
        e_max = std::max(e_max, r.relative_error[c]);
        e_mean += r.relative_error[c] / double(C);
    }
    std::printf("source            %s\n", path.c_str());
    std::printf("grid              %d x %d x %d x %d, G %d x %d, phi_d samples %d, channels %zu\n", o.grid.theta_h, o.grid.phi_h,
                o.grid.theta_d, o.grid.phi_d, o.g_theta, o.g_phi, o.phi_d_samples > 0 ? o.phi_d_samples : o.grid.phi_d, C);
    std::printf("samples           %zu (%zu invalid values)\n", r.samples, r.invalid_values);
    std::printf("time              %.2f s: geometry %.2f, resampling %.2f, fitting %.2f\n", wall, r.seconds_geometry,
                r.seconds_resampling, r.seconds_fitting);
    std::printf("iterations        %d .. %d per block\n", it_min, it_max);
    std::printf("weighted error    mean %.3e, max %.3e (relative, fit objective)\n", e_mean, e_max);
    std::printf("peak memory       %.2f GiB\n", peak_rss_gib());
    if (pairs > 0) {
        const npf::BrdfSpaceError e = npf::brdf_space_error(*source, f.channels, [&](const npf::Vec3& wi, const npf::Vec3& wo, double* out) {
            const npf::Vec3d a{wi.x, wi.y, wi.z}, b{wo.x, wo.y, wo.z};
            for (std::size_t c = 0; c < C; ++c) out[c] = f.eval(c, a, b);
        }, pairs);
        std::printf("BRDF-space error  relative RMS mean %.3f %%, worst channel %.3f %%, pooled %.3f %% (%d pairs, theta < 80 deg)\n",
                    100.0 * e.mean_relative_rms, 100.0 * e.max_relative_rms, 100.0 * e.overall_relative_rms, pairs);
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "npf_bench_fit: %s\n", e.what());
    return 1;
}
