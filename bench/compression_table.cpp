// npf_bench_compression: the paper's Table 2 on our data. Fits a material once with a preset,
// then compresses D and G at several cumulative contribution ratios and reports, per pair of
// ratios, the ranks, the file size and its ratio to the input, and the BRDF-space error.
//
//   build/bench/npf_bench_compression SOURCE [--preset production] [--phi-d-samples K]
//        [--pairs N] [--threads N]
#include <npf/converter/convert.h>
#include <npf/shading/npf_texture_file.h>
#include <npf/materials/open_material.h>
#include <npf/core/error.h>
#include <npf/shading/npf_model.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

int main(int argc, char** argv) try {
    if (argc < 2) {
        std::fprintf(stderr, "usage: npf_bench_compression SOURCE [--preset P] [--phi-d-samples K] [--pairs N] [--threads N]\n");
        return 2;
    }
    const auto source = npf::open_material(argv[1]);
    std::string preset = "production";
    int phi_d = -1, pairs = 20000, threads = 0;
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string a = argv[i], v = argv[i + 1];
        if (a == "--preset") preset = v;
        else if (a == "--phi-d-samples") phi_d = std::atoi(v.c_str());
        else if (a == "--pairs") pairs = std::atoi(v.c_str());
        else if (a == "--threads") threads = std::atoi(v.c_str());
        else throw npf::Error(a, "unknown option");
    }
    const bool iso = source->info().isotropic;
    npf::ConvertSettings s = npf::preset_settings(npf::parse_convert_preset(preset, "--preset"), iso);
    npf::AwlsOptions o = s.fit;
    o.channels = source->info().channels;
    if (iso) o.grid.phi_h = 1, o.g_phi = 1;
    if (phi_d >= 0) o.phi_d_samples = phi_d;
    o.threads = threads;
    npf::AwlsReport r;
    const npf::NpfFactors f = npf::fit_npf(*source, o, &r);
    std::printf("# %s: %zu channels, fitted in %.1f s; input %.2f MB\n", argv[1], f.channel_count(), r.seconds,
                double(source->info().file_bytes) / 1e6);
    std::printf("| PCA D / G | ranks D / G | size | ratio to input | BRDF-space rel. RMS (mean / worst channel) |\n|---|---|---|---|---|\n");
    const double ratios[][2] = {{1.0, 1.0}, {0.99, 0.99}, {0.99, 0.95}, {0.99, 0.90}, {0.95, 0.95}, {0.90, 0.90}};
    const std::string tmp = "/tmp/npf_bench_compression_" + std::to_string(getpid()) + ".exr";
    for (const auto& ratio : ratios) {
        npf::CompressionOptions c;
        c.d_ratio = ratio[0];
        c.g_ratio = ratio[1];
        const npf::NpfModel m = npf::compress_factors(f, c);
        npf::write_npf_texture(m, tmp);
        struct stat st {};
        ::stat(tmp.c_str(), &st);
        const npf::BrdfSpaceError e = npf::brdf_space_error(*source, f.channels, [&](const npf::Vec3& wi, const npf::Vec3& wo, double* out) {
            m.eval_all(wi, wo, out);
        }, pairs);
        std::printf("| %s | %d / %d | %.2f MB | %.3f %% | %.2f %% / %.2f %% |\n",
                    ratio[0] >= 1.0 ? "none" : (std::to_string(int(ratio[0] * 100)) + " / " + std::to_string(int(ratio[1] * 100))).c_str(),
                    m.D.rank, m.G.rank, double(st.st_size) / 1e6, 100.0 * double(st.st_size) / double(source->info().file_bytes),
                    100.0 * e.mean_relative_rms, 100.0 * e.max_relative_rms);
    }
    ::unlink(tmp.c_str());
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "npf_bench_compression: %s\n", e.what());
    return 1;
}
