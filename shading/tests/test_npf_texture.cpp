// NPF factor textures (docs/format.md): written and read back bit for bit, opened by open_material
// and the `npf` tool as a material, and every damaged or foreign file rejected with an
// npf::Error naming it.
#include "npf_test_factors.h"
#include "raw_exr.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/fit/spectral_compression.h>
#include <npf/materials/open_material.h>
#include <npf/core/error.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_texture_file.h>

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

using npf::NpfModel, npf::Vec3, npf::testing::contains, npf::testing::describe,
      npf::testing::make_test_factors, npf::testing::TestFactorSpec, npf::testing::ToolRun,
      npf::testing::RawPart, npf::testing::read_raw, npf::testing::write_raw, npf::testing::find_raw,
      npf::testing::set_value, npf::testing::drop_channel;

const std::string& folder() {
    static const std::string dir = npf::testing::temporary_folder("npf-texture");
    return dir;
}

std::string file(const std::string& name) { return folder() + "/" + name; }

NpfModel make_model(const TestFactorSpec& kind, int d_rank = 0, int g_rank = 0) {
    npf::CompressionOptions o;
    o.d_rank = d_rank;
    o.g_rank = g_rank;
    NpfModel m = npf::compress_factors(make_test_factors(kind), o);
    m.metadata = {{"description", "test material"},
                  {"source", "synthetic \"factors\"\nwith a second line"},
                  {"fit.relative_error", "0.0123"},
                  {"Zeta first in order, not in name", "ü ✓"}};
    return m;
}

std::vector<TestFactorSpec> all_kinds() {
    return {{false, 3, false, 1}, {true, 3, false, 2}, {false, 20, true, 3}, {true, 20, true, 4}};
}

std::string kind_name(const TestFactorSpec& s) {
    return std::string(s.anisotropic ? "aniso" : "iso") + (s.spectral ? "_spectral" : "_rgb");
}

template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void expect_identical(const NpfModel& a, const NpfModel& b) {
    EXPECT_EQ(a.channels.is_rgb(), b.channels.is_rgb());
    EXPECT_TRUE(same_bits(a.channels.wavelengths(), b.channels.wavelengths()));
    EXPECT_EQ(a.d_theta, b.d_theta);
    EXPECT_EQ(a.d_phi, b.d_phi);
    EXPECT_EQ(a.f_theta, b.f_theta);
    EXPECT_EQ(a.g_theta, b.g_theta);
    EXPECT_EQ(a.g_phi, b.g_phi);
    EXPECT_TRUE(same_bits(a.rho_d, b.rho_d));
    EXPECT_TRUE(same_bits(a.rho_s, b.rho_s));
    EXPECT_TRUE(same_bits(a.F, b.F));
    for (auto [x, y] : {std::pair{&a.D, &b.D}, std::pair{&a.G, &b.G}}) {
        EXPECT_EQ(x->rank, y->rank);
        EXPECT_EQ(x->cells, y->cells);
        EXPECT_TRUE(same_bits(x->basis, y->basis));
        EXPECT_TRUE(same_bits(x->weights, y->weights));
        EXPECT_TRUE(same_bits(x->singular_values, y->singular_values));
        EXPECT_EQ(x->kept_ratio, y->kept_ratio);
    }
    EXPECT_EQ(a.metadata, b.metadata);
}

// Expects `f` to throw an npf::Error whose message names `path` and contains `part`.
void expect_error(const std::function<void()>& f, const std::string& path, const std::string& part) {
    try {
        f();
        ADD_FAILURE() << "no error for " << path << " (expected '" << part << "')";
    } catch (const npf::Error& e) {
        EXPECT_EQ(e.source(), path) << e.what();
        EXPECT_TRUE(contains(e.what(), part)) << "message: " << e.what() << "\nexpected to contain: " << part;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not an npf::Error: " << e.what();
    }
}

// A valid anisotropic spectral file, edited by `edit`, written under `name`.
std::string damaged(const std::string& name, const std::function<void(std::vector<RawPart>&)>& edit) {
    static const std::string valid = [] {
        const std::string p = file("valid_for_damage.exr");
        npf::write_npf_texture(make_model({true, 20, true, 4}, 12, 5), p);
        return p;
    }();
    std::vector<RawPart> parts = read_raw(valid);
    edit(parts);
    const std::string path = file(name);
    write_raw(path, parts);
    return path;
}

std::vector<unsigned char> bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {});
}

std::string write_bytes(const std::string& name, const std::vector<unsigned char>& bytes) {
    const std::string path = file(name);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    return path;
}

// ---- Round trip -------------------------------------------------------------------------------

TEST(NpfTexture, RoundTripIsBitExact) {
    for (const TestFactorSpec& kind : all_kinds()) {
        SCOPED_TRACE(kind_name(kind));
        const NpfModel m = make_model(kind);
        if (kind.spectral && kind.anisotropic) {
            ASSERT_GT(m.D.rank, 10);  // past the channel-sorting pitfall (D.u10 < D.u2)
            ASSERT_GT(m.G.rank, 10);
        }
        const std::string path = file(kind_name(kind) + ".exr");
        npf::write_npf_texture(m, path);
        EXPECT_TRUE(npf::is_npf_texture(path));
        expect_identical(npf::read_npf_texture(path), m);
        // Truncated ranks and no metadata too.
        NpfModel low = make_model(kind, 2, 1);
        low.metadata.clear();
        npf::write_npf_texture(low, path);
        expect_identical(npf::read_npf_texture(path), low);
    }
}

TEST(NpfTexture, OverwritesAndLeavesNoTemporaries) {
    const std::string dir = npf::testing::temporary_folder("npf-texture-overwrite");
    const std::string path = dir + "/m.exr";
    npf::write_npf_texture(make_model({false, 3, false, 1}), path);
    const NpfModel second = make_model({true, 20, true, 2});
    npf::write_npf_texture(second, path);
    expect_identical(npf::read_npf_texture(path), second);
    EXPECT_EQ(npf::testing::folder_entries(dir), std::vector<std::string>{"m.exr"});
}

TEST(NpfTexture, LayoutIsAsDocumented) {
    const NpfModel m = make_model({true, 20, true, 4}, 12, 5);
    const std::string path = file("layout.exr");
    npf::write_npf_texture(m, path);
    std::vector<RawPart> parts = read_raw(path);
    ASSERT_EQ(parts.size(), 4u);
    const char* names[] = {"D", "G", "F", "spectral"};
    for (std::size_t i = 0; i < 4; ++i) {
        const OIIO::ImageSpec& s = parts[i].spec;
        EXPECT_EQ(s.get_string_attribute("oiio:subimagename"), names[i]);
        EXPECT_EQ(s.format, OIIO::TypeFloat);
        EXPECT_EQ(s.get_string_attribute("compression"), "zip");
        // One display window for all parts (OpenEXR): D's grid.
        EXPECT_EQ(s.full_width, m.d_phi);
        EXPECT_EQ(s.full_height, m.d_theta);
        EXPECT_EQ(s.x, 0);
        EXPECT_EQ(s.y, 0);
    }
    EXPECT_EQ(parts[0].spec.width, 16);
    EXPECT_EQ(parts[0].spec.height, 8);
    EXPECT_EQ(parts[0].spec.channelnames.front(), "D.u000");
    EXPECT_EQ(parts[0].spec.channelnames.back(), "D.u011");
    EXPECT_EQ(parts[0].spec.get_int_attribute("npf:format_version"), 1);
    EXPECT_EQ(parts[0].spec.get_string_attribute("npf:channel_kind"), "spectral");
    EXPECT_EQ(parts[0].spec.get_string_attribute("wrapmodes"), "periodic,clamp");
    EXPECT_EQ(parts[1].spec.width, 12);
    EXPECT_EQ(parts[2].spec.width, 6);
    EXPECT_EQ(parts[2].spec.height, 1);
    EXPECT_EQ(parts[2].spec.nchannels, 20);
    EXPECT_EQ(parts[3].spec.width, 20);
    EXPECT_EQ(parts[3].spec.nchannels, 3 + 12 + 5);
    // D.u003 of pixel (x 5, y 2) is the basis value at theta_h row 2, phi_h column 5.
    const int c = parts[0].spec.channelindex("D.u003");
    ASSERT_GE(c, 0);
    EXPECT_EQ(parts[0].pixels[(2 * 16 + 5) * 12 + std::size_t(c)], m.D.basis[3 * m.D.cells + 2 * 16 + 5]);
    const int w = parts[3].spec.channelindex("wavelength");
    EXPECT_EQ(parts[3].pixels[7 * std::size_t(parts[3].spec.nchannels) + std::size_t(w)], 400.f + 15.f * 7);
}

TEST(NpfTexture, IinfoReadsTheFile) {
    if (std::system("command -v iinfo > /dev/null 2>&1") != 0) GTEST_SKIP() << "iinfo is not installed";
    const std::string path = file("for_iinfo.exr"), log = file("iinfo.txt");
    npf::write_npf_texture(make_model({true, 20, true, 4}), path);
    const std::string command =
        "iinfo -v -a " + npf::testing::shell_quote(path) + " > " + npf::testing::shell_quote(log) + " 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << npf::testing::read_text(log);
    const std::string out = npf::testing::read_text(log);
    EXPECT_TRUE(contains(out, "npf:format_version: 1")) << out;
    EXPECT_TRUE(contains(out, "D.u019")) << out;
    EXPECT_TRUE(contains(out, "subimage")) << out;
}

// docs/format.md sec. 6: the TextureSystem maps s, t over the display window all parts share (D's
// grid); with the documented scaling, lookups in every part are the bilinear interpolation of its
// cell centres, periodic in phi.
TEST(NpfTexture, TextureSystemLookupsFollowTheDocumentedMapping) {
    const NpfModel m = make_model({true, 20, true, 4}, 6, 3);
    const std::string path = file("texture_system.exr");
    npf::write_npf_texture(m, path);
    struct Case {
        int subimage, channel;
        const float* table;  // [h][w]
        int w, h;
        bool periodic;
    };
    const Case cases[] = {
        {0, 2, m.D.basis.data() + 2 * m.D.cells, m.d_phi, m.d_theta, true},
        {1, 1, m.G.basis.data() + 1 * m.G.cells, m.g_phi, m.g_theta, true},
        {2, 5, m.F.data() + 5 * std::size_t(m.f_theta), m.f_theta, 1, false},
    };
    OIIO::TextureSystem* ts = OIIO::TextureSystem::create(/*shared=*/false);
    const OIIO::ustring name(path);
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (const Case& c : cases) {
        SCOPED_TRACE(c.subimage);
        OIIO::TextureOpt opt;
        opt.subimage = c.subimage;
        opt.firstchannel = c.channel;
        opt.mipmode = OIIO::TextureOpt::MipModeNoMIP;
        opt.interpmode = OIIO::TextureOpt::InterpBilinear;
        opt.swrap = c.periodic ? OIIO::TextureOpt::WrapPeriodic : OIIO::TextureOpt::WrapClamp;
        opt.twrap = OIIO::TextureOpt::WrapClamp;
        for (int n = 0; n < 200; ++n) {
            const double x = c.w * uni(rng), y = c.h * uni(rng);  // in cells; centres at k + 1/2
            auto at = [&](int i, int j) { return double(c.table[std::size_t(j) * std::size_t(c.w) + std::size_t(i)]); };
            const double cy = std::clamp(y - 0.5, 0.0, double(c.h - 1));
            double cx = x - 0.5;
            int i0, i1;
            if (c.periodic) {
                const double f = std::floor(cx);
                i0 = (int(f) % c.w + c.w) % c.w;
                i1 = (i0 + 1) % c.w;
                cx -= f;
            } else {
                cx = std::clamp(cx, 0.0, double(c.w - 1));
                i0 = int(cx);
                i1 = std::min(i0 + 1, c.w - 1);
                cx -= i0;
            }
            const int j0 = int(cy), j1 = std::min(j0 + 1, c.h - 1);
            const double ty = cy - j0;
            const double want =
                ((1 - cx) * at(i0, j0) + cx * at(i1, j0)) * (1 - ty) + ((1 - cx) * at(i0, j1) + cx * at(i1, j1)) * ty;
            float got = 0.f;
            // s = (x / w) * w / d_phi, t = (y / h) * h / d_theta.
            ASSERT_TRUE(ts->texture(name, opt, float(x / m.d_phi), float(y / m.d_theta), 0, 0, 0, 0, 1, &got))
                << ts->geterror();
            ASSERT_NEAR(got, want, 1e-5 * (std::fabs(want) + 0.1)) << "x " << x << " y " << y;
        }
    }
    OIIO::TextureSystem::destroy(ts);
}

// ---- As a material ----------------------------------------------------------------------------

TEST(NpfTexture, OpensAsAMaterial) {
    const NpfModel m = make_model({true, 20, true, 4}, 6, 3);
    const std::string path = file("material.exr");
    npf::write_npf_texture(m, path);
    const std::unique_ptr<npf::Brdf> brdf = npf::open_material(path);
    const npf::BrdfInfo& info = brdf->info();
    EXPECT_EQ(info.format, "npf-exr");
    EXPECT_EQ(info.path, path);
    EXPECT_EQ(info.description, "test material");
    EXPECT_FALSE(info.isotropic);
    EXPECT_EQ(info.channels.wavelengths(), m.channels.wavelengths());
    EXPECT_EQ(info.file_bytes, std::filesystem::file_size(path));
    bool saw_rank = false, saw_source = false;
    for (const auto& [key, value] : info.details) {
        if (key == "D rank") saw_rank = contains(value, "6 of 20");
        if (key == "source") saw_source = value == m.metadata[1].second;
    }
    EXPECT_TRUE(saw_rank);
    EXPECT_TRUE(saw_source);

    // eval_cos = f_r cos(theta_o) of the model, for every stored channel.
    const npf::NpfBrdf direct(m);
    const npf::ChannelQuery q = brdf->native_query();
    std::vector<float> v(q.size()), w(q.size());
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    for (int n = 0; n < 50; ++n) {
        const Vec3 wi = npf::spherical_direction(1.5f * uni(rng), 6.28f * uni(rng));
        const Vec3 wo = npf::spherical_direction(1.5f * uni(rng), 6.28f * uni(rng));
        brdf->eval_cos(wi, wo, q, v.data());
        direct.eval_cos(wi, wo, q, w.data());
        for (std::size_t c = 0; c < q.size(); ++c) {
            EXPECT_EQ(v[c], w[c]);
            EXPECT_NEAR(v[c], m.eval(c, wi, wo) * wo.z, 1e-6 * v[c]);
        }
    }
    brdf->eval_cos({0.f, 0.f, 1.f}, {0.f, 1.f, 0.f}, q, v.data());
    for (float x : v) EXPECT_EQ(x, 0.f);
}

TEST(NpfTexture, WavelengthQueriesInterpolateAndClampToTheEnds) {
    const npf::NpfBrdf brdf(make_model({false, 20, true, 6}));
    const Vec3 wi = npf::spherical_direction(0.4f, 1.f), wo = npf::spherical_direction(0.7f, 3.f);
    const npf::ChannelQuery all = brdf.native_query();
    std::vector<float> stored(all.size());
    brdf.eval_cos(wi, wo, all, stored.data());
    const npf::ChannelQuery q = brdf.query(npf::Channels::spectral({300.f, 407.5f, 445.f, 800.f}));
    float v[4];
    brdf.eval_cos(wi, wo, q, v);
    EXPECT_EQ(v[0], stored[0]);
    EXPECT_NEAR(v[1], 0.5f * (stored[0] + stored[1]), 1e-6f * v[1]);
    EXPECT_EQ(v[2], stored[3]);
    EXPECT_EQ(v[3], stored[19]);
    EXPECT_THROW(brdf.query(npf::Channels::rgb()), npf::Error);
    const npf::NpfBrdf rgb(make_model({false, 3, false, 6}));
    EXPECT_THROW(rgb.query(npf::Channels::spectral({500.f})), npf::Error);
    EXPECT_EQ(rgb.native_query().size(), 3u);
}

TEST(NpfTexture, SamplingIsConsistentWithPdf) {
    const npf::NpfBrdf brdf(make_model({true, 3, false, 6}));
    const npf::ChannelQuery q = brdf.native_query();
    const Vec3 wi = npf::spherical_direction(0.6f, 0.3f);
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    for (int n = 0; n < 200; ++n) {
        npf::BrdfSample s;
        float weight[3], value[3];
        if (!brdf.sample(wi, {uni(rng), uni(rng)}, q, s, weight)) continue;
        EXPECT_GT(s.wo.z, 0.f);
        EXPECT_FLOAT_EQ(s.pdf, brdf.pdf(wi, s.wo));
        brdf.eval_cos(wi, s.wo, q, value);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(weight[c], value[c] / s.pdf, 1e-5f * weight[c]);
    }
    EXPECT_EQ(brdf.pdf(wi, {0.f, 0.6f, -0.8f}), 0.f);
    npf::BrdfSample s;
    EXPECT_FALSE(brdf.sample({0.f, 0.6f, -0.8f}, {0.3f, 0.3f}, q, s, nullptr));
}

// ---- Bad input ---------------------------------------------------------------------------------

void expect_rejected(const std::string& path, const std::string& part) {
    SCOPED_TRACE(path);
    expect_error([&] { npf::read_npf_texture(path); }, path, part);
    expect_error([&] { npf::open_material(path); }, path, part);
}

TEST(NpfTextureBadInput, MissingEmptyAndForeignFiles) {
    expect_error([&] { npf::read_npf_texture(file("absent.exr")); }, file("absent.exr"), "file not found");
    expect_rejected(write_bytes("empty.exr", {}), "empty");
    expect_error([&] { npf::read_npf_texture(folder()); }, folder(), "is a directory");
    const std::vector<unsigned char> text = {'h', 'e', 'l', 'l', 'o', '\n'};
    const std::string not_exr = write_bytes("text.exr", text);
    expect_error([&] { npf::read_npf_texture(not_exr); }, not_exr, "not an OpenEXR file");
    EXPECT_FALSE(npf::is_npf_texture(not_exr));
    EXPECT_FALSE(npf::is_npf_texture(file("absent.exr")));
    const std::string rgl = npf::testing::write_synthetic_rgl({}, file("material.bsdf"));
    EXPECT_FALSE(npf::is_npf_texture(rgl));
    expect_error([&] { npf::read_npf_texture(rgl); }, rgl, "not an OpenEXR file");

    // A plain OpenEXR image.
    const std::string plain = file("plain.exr");
    {
        auto out = OIIO::ImageOutput::create(plain);
        ASSERT_TRUE(out);
        OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeFloat);
        std::vector<float> pixels(4 * 4 * 3, 0.5f);
        ASSERT_TRUE(out->open(plain, spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeFloat, pixels.data()));
        ASSERT_TRUE(out->close());
    }
    EXPECT_FALSE(npf::is_npf_texture(plain));
    expect_rejected(plain, "not an NPF factor texture");
}

TEST(NpfTextureBadInput, TruncatedFiles) {
    const std::string path = file("whole.exr");
    npf::write_npf_texture(make_model({true, 20, true, 4}), path);
    const std::vector<unsigned char> bytes = bytes_of(path);
    for (std::size_t keep : {std::size_t(3), std::size_t(8), std::size_t(100), bytes.size() / 3, bytes.size() / 2,
                             bytes.size() - 200, bytes.size() - 1}) {
        SCOPED_TRACE(keep);
        const std::string cut =
            write_bytes("cut" + std::to_string(keep) + ".exr", {bytes.begin(), bytes.begin() + std::ptrdiff_t(keep)});
        try {
            npf::read_npf_texture(cut);
            ADD_FAILURE() << "a file cut to " << keep << " of " << bytes.size() << " bytes was read";
        } catch (const npf::Error& e) {
            EXPECT_EQ(e.source(), cut) << e.what();
        }
        EXPECT_THROW(npf::open_material(cut), npf::Error);
    }
}

TEST(NpfTextureBadInput, DamagedContents) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    expect_rejected(damaged("nan_basis.exr", [&](auto& p) { set_value(*find_raw(p, "D"), "D.u003", 17, nan); }),
                    "non-finite value in part 'D' channel 'D.u003' at x 1, y 1");
    expect_rejected(damaged("inf_weight.exr",
                            [&](auto& p) {
                                set_value(*find_raw(p, "spectral"), "G.v001", 2,
                                          std::numeric_limits<float>::infinity());
                            }),
                    "non-finite value in part 'spectral' channel 'G.v001'");
    expect_rejected(damaged("negative_rho.exr", [&](auto& p) { set_value(*find_raw(p, "spectral"), "rho_d", 4, -0.1f); }),
                    "negative value in part 'spectral' channel 'rho_d'");
    expect_rejected(damaged("negative_f.exr", [&](auto& p) { set_value(*find_raw(p, "F"), "F.c007", 0, -1.f); }),
                    "negative value in part 'F'");
    expect_rejected(damaged("descending_wavelengths.exr",
                            [&](auto& p) { set_value(*find_raw(p, "spectral"), "wavelength", 5, 300.f); }),
                    "strictly ascending");
    expect_rejected(damaged("version3.exr", [&](auto& p) { find_raw(p, "D")->spec.attribute("npf:format_version", 3); }),
                    "unsupported npf:format_version 3");
    // Version 2 promises a detail layer: a version-1 file relabelled lacks its attributes.
    expect_rejected(damaged("version2.exr", [&](auto& p) { find_raw(p, "D")->spec.attribute("npf:format_version", 2); }),
                    "missing attribute npf:detail_theta_h");
    expect_rejected(damaged("version_string.exr",
                            [&](auto& p) { find_raw(p, "D")->spec.attribute("npf:format_version", "1"); }),
                    "not an NPF factor texture");
    expect_rejected(damaged("no_g.exr", [&](auto& p) { p.erase(p.begin() + 1); }), "missing part 'G'");
    expect_rejected(damaged("no_d.exr", [&](auto& p) { p.erase(p.begin()); }), "not an NPF factor texture");
    expect_rejected(damaged("no_basis_channel.exr", [&](auto& p) { drop_channel(*find_raw(p, "D"), "D.u007"); }),
                    "part 'D' lacks channel 'D.u007'");
    expect_rejected(damaged("no_weight_channel.exr", [&](auto& p) { drop_channel(*find_raw(p, "spectral"), "D.v011"); }),
                    "lacks channel 'D.v011'");
    expect_rejected(damaged("no_rho_s.exr", [&](auto& p) { drop_channel(*find_raw(p, "spectral"), "rho_s"); }),
                    "lacks channel 'rho_s'");
    expect_rejected(damaged("rank_mismatch.exr", [&](auto& p) { find_raw(p, "D")->spec.attribute("npf:d_rank", 11); }),
                    "part 'D' has 12 channels D.u*, the attributes call for 11");
    expect_rejected(damaged("rank_too_large.exr", [&](auto& p) { find_raw(p, "D")->spec.attribute("npf:g_rank", 21); }),
                    "npf:g_rank = 21 is outside 1..20");
    expect_rejected(damaged("wrong_size.exr", [&](auto& p) { find_raw(p, "D")->spec.attribute("npf:d_theta", 9); }),
                    "part 'D' is 16 x 8 pixels, the attributes call for 16 x 9");
    expect_rejected(damaged("wrong_channel_count.exr",
                            [&](auto& p) { find_raw(p, "D")->spec.attribute("npf:channel_count", 19); }),
                    "npf:");
    expect_rejected(damaged("no_kind.exr", [&](auto& p) { find_raw(p, "D")->spec.erase_attribute("npf:channel_kind"); }),
                    "missing attribute npf:channel_kind");
    expect_rejected(damaged("bad_kind.exr",
                            [&](auto& p) { find_raw(p, "D")->spec.attribute("npf:channel_kind", "xyz"); }),
                    "npf:channel_kind is 'xyz'");
    expect_rejected(damaged("bad_sigma.exr",
                            [&](auto& p) { find_raw(p, "D")->spec.attribute("npf:d_singular_values", "1 2 x"); }),
                    "npf:d_singular_values is not a list of numbers");
    expect_rejected(damaged("isotropic_flag.exr", [&](auto& p) { find_raw(p, "D")->spec.attribute("npf:isotropic", 1); }),
                    "npf:isotropic disagrees");
}

// The same model gives the same bytes, whenever it is written: no time stamp (OpenImageIO
// stamps the time of writing as capDate unless told otherwise; docs/format.md).
TEST(NpfTextureWriter, NoTimeStampTheSameModelGivesTheSameBytes) {
    const std::string dir = npf::testing::temporary_folder("npf-texture-no-stamp");
    const NpfModel m = make_model({false, 3, false, 1});
    const auto bytes_of = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    };
    npf::write_npf_texture(m, dir + "/a.exr");
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // another second of the clock
    npf::write_npf_texture(m, dir + "/b.exr");
    EXPECT_EQ(bytes_of(dir + "/a.exr"), bytes_of(dir + "/b.exr"));
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(dir + "/a.exr");
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().get_string_attribute("DateTime"), "");  // absent or empty: no date
}

// ---- Writing failures ------------------------------------------------------------------------

TEST(NpfTextureWriter, FailuresLeaveNoFile) {
    const std::string dir = npf::testing::temporary_folder("npf-texture-fail");
    const NpfModel m = make_model({false, 3, false, 1});
    const std::string missing_dir = dir + "/no/such/folder/m.exr";
    expect_error([&] { npf::write_npf_texture(m, missing_dir); }, missing_dir, "cannot create output");
    // The destination is a folder: the finished temporary cannot be renamed over it.
    std::filesystem::create_directory(dir + "/taken.exr");
    expect_error([&] { npf::write_npf_texture(m, dir + "/taken.exr"); }, dir + "/taken.exr", "cannot move");
    // Inconsistent models are refused before anything is written.
    NpfModel bad = m;
    bad.F[2] = std::numeric_limits<float>::quiet_NaN();
    expect_error([&] { npf::write_npf_texture(bad, dir + "/nan.exr"); }, dir + "/nan.exr", "non-finite value in F");
    bad = m;
    bad.D.rank = 2;
    expect_error([&] { npf::write_npf_texture(bad, dir + "/rank.exr"); }, dir + "/rank.exr", "D basis");
    bad = m;
    bad.metadata.emplace_back("source", "again");
    expect_error([&] { npf::write_npf_texture(bad, dir + "/dup.exr"); }, dir + "/dup.exr", "appears twice");
    bad = m;
    bad.metadata.emplace_back("two\nlines", "x");
    expect_error([&] { npf::write_npf_texture(bad, dir + "/ctl.exr"); }, dir + "/ctl.exr", "control character");
    EXPECT_EQ(npf::testing::folder_entries(dir), std::vector<std::string>{"taken.exr"});
}

// ---- The npf tool ------------------------------------------------------------------------------

TEST(NpfTextureCli, InfoAndEval) {
    const NpfModel m = make_model({true, 20, true, 4}, 6, 3);
    const std::string path = file("cli.exr");
    npf::write_npf_texture(m, path);

    const ToolRun info = npf::testing::run_tool({"info", path});
    ASSERT_EQ(info.status, 0) << describe(info);
    EXPECT_TRUE(npf::testing::has_line(info.out, "file: " + path)) << describe(info);
    EXPECT_TRUE(contains(info.out, "format: NPF factor texture")) << describe(info);
    EXPECT_TRUE(npf::testing::has_line(info.out, "isotropic: no")) << describe(info);
    EXPECT_TRUE(npf::testing::has_line(info.out, "channels: spectral, 20 wavelengths, 400.0 to 685.0 nm"))
        << describe(info);
    EXPECT_TRUE(npf::testing::has_line(info.out, "description: test material")) << describe(info);
    EXPECT_TRUE(contains(info.out, "D rank: 6 of 20")) << describe(info);
    EXPECT_TRUE(contains(info.out, "fit.relative_error: 0.0123")) << describe(info);

    // eval prints f_r; compare with the in-process evaluation.
    const npf::NpfBrdf brdf(m);
    std::string pairs;
    std::vector<std::pair<Vec3, Vec3>> dirs;
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    for (int n = 0; n < 20; ++n) {
        const Vec3 wi = npf::spherical_direction(1.4f * uni(rng), 6.28f * uni(rng));
        const Vec3 wo = npf::spherical_direction(1.4f * uni(rng), 6.28f * uni(rng));
        char line[256];
        std::snprintf(line, sizeof line, "%.9g %.9g %.9g %.9g %.9g %.9g\n", wi.x, wi.y, wi.z, wo.x, wo.y, wo.z);
        pairs += line;
        dirs.emplace_back(wi, wo);
    }
    npf::testing::ToolRunOptions o;
    o.stdin_text = pairs;
    const ToolRun eval = npf::testing::run_tool({"eval", path, "--wavelengths", "450,500,612.5"}, o);
    ASSERT_EQ(eval.status, 0) << describe(eval);
    const std::vector<std::string> lines = npf::testing::lines_of(eval.out);
    ASSERT_EQ(lines.size(), dirs.size() + 1) << describe(eval);
    EXPECT_EQ(lines[0], "# 450 500 612.5");
    const npf::ChannelQuery q = brdf.query(npf::Channels::spectral({450.f, 500.f, 612.5f}));
    for (std::size_t n = 0; n < dirs.size(); ++n) {
        std::istringstream is(lines[n + 1]);
        double printed[3];
        is >> printed[0] >> printed[1] >> printed[2];
        // The tool normalises the printed directions again; the values agree to float precision.
        float want[3];
        brdf.eval_cos(dirs[n].first, dirs[n].second, q, want);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(printed[k], want[k] / dirs[n].second.z, 1e-5 * std::fabs(printed[k]));
    }

    const std::string broken = damaged("cli_broken.exr", [](auto& p) { p.erase(p.begin() + 2); });
    const ToolRun bad = npf::testing::run_tool({"info", broken});
    EXPECT_EQ(bad.status, 1) << describe(bad);
    EXPECT_TRUE(contains(bad.err, broken + ": missing part 'F'")) << describe(bad);
}

}  // namespace
