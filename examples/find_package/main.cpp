// Opens a material through an installed npf and prints f_r cos at normal incidence.
#include <npf/materials/open_material.h>
#include <npf/core/error.h>

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: npf_consumer MATERIAL\n");
        return 2;
    }
    try {
        auto brdf = npf::open_material(argv[1]);
        npf::ChannelQuery q = brdf->native_query();
        std::vector<float> value(q.size());
        brdf->eval_cos({0.f, 0.f, 1.f}, {0.f, 0.f, 1.f}, q, value.data());
        std::printf("format %s, channels %s, first value %.6g\n", brdf->info().format.c_str(),
                    q.requested.describe().c_str(), double(value[0]));
        return 0;
    } catch (const npf::Error& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
}
