// npf_writer_accuracy: how closely RGL files written by the virtual acquisition reproduce
// their analytic source between the data nodes, per shipped recipe and grid size. Prints a
// Markdown table (docs/synth.md quotes it). Not a test: it takes a minute or two.
//
//   build/bench/npf_writer_accuracy [RECIPE_DIR] [--pairs N]
//
// Errors over N random direction pairs with both directions below 80 degrees, on the
// luminance (CIE Y) of f_r cos(theta_o):
//   relative RMS = sqrt(sum (file - source)^2 / sum source^2)
//   max relative = max |file - source| / source over values above 1 % of the largest
#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/materials/material_recipe.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/materials/rgl_writer.h>
#include <npf/core/error.h>
#include <npf/core/rec709_luminance.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <dirent.h>
#include <random>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

struct Grid {
    const char* name;
    int phi, theta, vndf, data;
};

struct Errors {
    double relative_rms = 0.0, max_relative = 0.0;
};

Errors measure(const npf::Brdf& source, const npf::Brdf& file, int pairs) {
    const npf::ChannelQuery sq = source.query(npf::Channels::rgb()), fq = file.query(npf::Channels::rgb());
    std::mt19937 rng(2024);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    const float min_cos = std::cos(80.f * npf::kPi / 180.f);
    auto direction = [&] {
        return npf::spherical_direction(std::acos(min_cos + (1.f - min_cos) * uni(rng)), 2.f * npf::kPi * uni(rng) - npf::kPi);
    };
    std::vector<std::pair<double, double>> values;
    double largest = 0.0;
    for (int i = 0; i < pairs; ++i) {
        const npf::Vec3 wi = direction(), wo = direction();
        float a[3], b[3];
        source.eval_cos(wi, wo, sq, a);
        file.eval_cos(wi, wo, fq, b);
        const double ya = npf::rec709_luminance(a[0], a[1], a[2]);
        const double yb = npf::rec709_luminance(b[0], b[1], b[2]);
        values.emplace_back(ya, yb);
        largest = std::max(largest, ya);
    }
    Errors e;
    double num = 0.0, den = 0.0;
    for (const auto& [ref, got] : values) {
        num += (got - ref) * (got - ref);
        den += ref * ref;
        if (ref >= 0.01 * largest) e.max_relative = std::max(e.max_relative, std::fabs(got - ref) / ref);
    }
    e.relative_rms = std::sqrt(num / den);
    return e;
}

}  // namespace

int main(int argc, char** argv) {
    std::string recipes = std::string(NPF_SOURCE_DIR) + "/configs/materials";
    int pairs = 100000;
    bool analytic_ndf = true;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--pairs" && i + 1 < argc) pairs = std::atoi(argv[++i]);
        else if (a == "--power-iteration") analytic_ndf = false;
        else recipes = a;
    }
    const Grid grids[] = {
        {"small (vndf 64, data 16)", 12, 6, 64, 16},
        {"database (vndf 128, data 32)", 24, 8, 128, 32},
        {"fine (vndf 128, data 64)", 24, 8, 128, 64},
        {"dense theta_i (16, data 32)", 24, 16, 128, 32},
    };
    std::vector<std::string> names;
    if (DIR* d = opendir(recipes.c_str())) {
        while (dirent* e = readdir(d)) {
            const std::string n = e->d_name;
            if (n.size() > 5 && n.substr(n.size() - 5) == ".yaml") names.push_back(n);
        }
        closedir(d);
    }
    std::sort(names.begin(), names.end());
    char tmpl[] = "/tmp/npf-writer-accuracy-XXXXXX";
    const std::string folder = mkdtemp(tmpl);
    std::printf("| recipe | grid | phi_i x theta_i | relative RMS | max relative | write time |\n|---|---|---|---|---|---|\n");
    try {
        for (const std::string& name : names) {
            npf::MaterialRecipe recipe = npf::load_material_recipe(recipes + "/" + name);
            const npf::AnalyticBrdf source(recipe.material);
            for (const Grid& g : grids) {
                npf::RglWriterOptions o = recipe.writer;
                o.channels = npf::Channels::rgb();  // the interpolation error does not depend on the channels
                o.phi_count = g.phi;
                o.theta_count = g.theta;
                o.vndf_size = g.vndf;
                o.data_size = g.data;
                if (analytic_ndf) o.ndf = source.ndf_function();
                const std::string path = folder + "/" + name + ".bsdf";
                const npf::RglWriteReport report = npf::write_rgl(source, path, o);
                const auto file = npf::RglBrdf::load(path);
                const Errors e = measure(source, *file, pairs);
                std::printf("| %s | %s | %zu x %zu | %.2f %% | %.1f %% | %.1f s |\n", name.c_str(), g.name, report.phi_i.size(),
                            report.theta_i.size(), 100.0 * e.relative_rms, 100.0 * e.max_relative, report.seconds);
                std::fflush(stdout);
                unlink(path.c_str());
            }
        }
    } catch (const npf::Error& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
    rmdir(folder.c_str());
    return 0;
}
