// End-to-end tests of `npf eval`: values printed by the built tool are compared with the same
// evaluation done in-process through RglBrdf; its format, its flags and its errors.

#include "cli_materials.h"
#include "cli_run.h"
#include "synthetic_rgl.h"

#include <npf/materials/rgl_brdf.h>
#include <npf/core/brdf.h>
#include <npf/core/channels.h>
#include <npf/core/vec.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace npf::testing;  // the CLI tests' helpers: run_npf, cli_materials, describe, ...
using npf::RglBrdf;
using npf::Vec3;

void write_text(const std::string& path, const std::string& text) {
    ASSERT_TRUE(npf::testing::write_text(path, text)) << "cannot write " << path;
}

struct Pair {
    double v[6];
};

std::string format_pairs(const std::vector<Pair>& pairs, double scale_i = 1.0, double scale_o = 1.0) {
    std::string text;
    char buf[256];
    for (const Pair& p : pairs) {
        std::snprintf(buf, sizeof(buf), "%.17g %.17g %.17g %.17g %.17g %.17g\n", p.v[0] * scale_i, p.v[1] * scale_i,
                      p.v[2] * scale_i, p.v[3] * scale_o, p.v[4] * scale_o, p.v[5] * scale_o);
        text += buf;
    }
    return text;
}

// Random pairs above the horizon (not too grazing), deterministic.
std::vector<Pair> random_pairs(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::vector<Pair> out;
    for (int i = 0; i < n; ++i) {
        const Vec3 wi = npf::spherical_direction(float(0.45 * npf::kPiD * uni(rng)), float(2 * npf::kPiD * uni(rng)));
        const Vec3 wo = npf::spherical_direction(float(0.45 * npf::kPiD * uni(rng)), float(2 * npf::kPiD * uni(rng)));
        out.push_back({{wi.x, wi.y, wi.z, wo.x, wo.y, wo.z}});
    }
    return out;
}

// What `npf eval` computes for one pair, done in-process the same way: normalise in double,
// evaluate in float, divide by wo.z in double unless `with_cos`.
std::vector<double> expected_values(const npf::Brdf& brdf, const npf::ChannelQuery& q, const Pair& p, bool with_cos) {
    const double li = std::sqrt(p.v[0] * p.v[0] + p.v[1] * p.v[1] + p.v[2] * p.v[2]);
    const double lo = std::sqrt(p.v[3] * p.v[3] + p.v[4] * p.v[4] + p.v[5] * p.v[5]);
    const Vec3 wi(float(p.v[0] / li), float(p.v[1] / li), float(p.v[2] / li));
    const Vec3 wo(float(p.v[3] / lo), float(p.v[4] / lo), float(p.v[5] / lo));
    std::vector<float> out(q.size());
    brdf.eval_cos(wi, wo, q, out.data());
    std::vector<double> r;
    for (float v : out) r.push_back(with_cos ? double(v) : (wo.z > 0.f ? double(v) / double(wo.z) : 0.0));
    return r;
}

struct EvalOutput {
    std::string header;
    std::vector<std::vector<std::string>> tokens;
    std::vector<std::vector<double>> values;
};

EvalOutput parse_eval(const std::string& out) {
    EvalOutput r;
    std::vector<std::string> lines = lines_of(out);
    if (lines.empty()) return r;
    r.header = lines[0];
    for (std::size_t i = 1; i < lines.size(); ++i) {
        std::istringstream is(lines[i]);
        std::vector<std::string> tok;
        std::vector<double> val;
        for (std::string t; is >> t;) {
            tok.push_back(t);
            val.push_back(std::strtod(t.c_str(), nullptr));
        }
        r.tokens.push_back(tok);
        r.values.push_back(val);
    }
    return r;
}

int significant_digits(const std::string& token) {
    int digits = 0;
    bool leading = true;
    for (char c : token) {
        if (c == 'e' || c == 'E') break;
        if (c < '0' || c > '9') continue;
        if (leading && c == '0') continue;
        leading = false;
        ++digits;
    }
    return digits;
}

// Runs eval on `pairs` through a --dirs file and checks every value against the in-process
// evaluation with relative tolerance `rel` (1e-7 demands at least seven significant digits).
EvalOutput eval_and_compare(const std::string& material, const std::vector<Pair>& pairs,
                            const std::vector<std::string>& flags, const npf::ChannelQuery& q, bool with_cos,
                            double rel = 1e-7) {
    static int counter = 0;
    const std::string dirs = cli_folder() + "/pairs" + std::to_string(++counter) + ".txt";
    write_text(dirs, format_pairs(pairs));
    std::vector<std::string> args = {"eval", material, "--dirs", dirs};
    args.insert(args.end(), flags.begin(), flags.end());
    const ToolRun r = run_npf(args);
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(r.err, "") << describe(r);
    EvalOutput e = parse_eval(r.out);
    EXPECT_EQ(e.values.size(), pairs.size()) << describe(r);
    const std::unique_ptr<RglBrdf> brdf = RglBrdf::load(material);
    for (std::size_t i = 0; i < pairs.size() && i < e.values.size(); ++i) {
        const std::vector<double> want = expected_values(*brdf, q, pairs[i], with_cos);
        if (e.values[i].size() != want.size()) {
            ADD_FAILURE() << "line " << i + 2 << " has " << e.values[i].size() << " values, expected " << want.size()
                          << "\n" << describe(r);
            continue;
        }
        for (std::size_t k = 0; k < want.size(); ++k) {
            EXPECT_NEAR(e.values[i][k], want[k], rel * std::fabs(want[k]) + 1e-30)
                << "pair " << i << " channel " << k << " printed '" << e.tokens[i][k] << "'";
        }
    }
    return e;
}

npf::ChannelQuery query_for(const std::string& material, const npf::Channels& channels, bool clamp = true) {
    const std::unique_ptr<RglBrdf> b = RglBrdf::load(material);
    npf::ChannelQuery q = b->query(channels);
    q.clamp_negative = clamp;
    return q;
}
TEST(CliEval, RgbHeaderAndOneLinePerPair) {
    const std::vector<Pair> pairs = random_pairs(40, 1);
    const EvalOutput e = eval_and_compare(cli_materials().rgb, pairs, {}, query_for(cli_materials().rgb, npf::Channels::rgb()),
                                          false);
    EXPECT_EQ(e.header, "# R G B");
    int nonzero = 0;
    for (const auto& row : e.values) {
        for (double v : row) nonzero += v > 0.0;
    }
    EXPECT_GT(nonzero, 60);
}

TEST(CliEval, SpectralHeaderAndValues) {
    const std::string m = cli_materials().spectral;
    const EvalOutput e = eval_and_compare(m, random_pairs(40, 2), {},
                                          query_for(m, npf::Channels::spectral({400.f, 500.f, 600.f, 700.f})), false);
    EXPECT_EQ(e.header, "# 400 500 600 700");
}

TEST(CliEval, CommentsAndBlankLinesAreSkipped) {
    const std::vector<Pair> pairs = random_pairs(3, 3);
    const std::vector<std::string> l = lines_of(format_pairs(pairs));
    const std::string text = "# a comment\n\n" + l[0] + "\n   \n\t# indented comment\n" + l[1] + "\r\n\r\n" + l[2];
    const ToolRun piped = run_npf({"eval", cli_materials().rgb}, text);  // no trailing newline either
    ASSERT_EQ(piped.status, 0) << describe(piped);
    const ToolRun plain = run_npf({"eval", cli_materials().rgb}, format_pairs(pairs));
    ASSERT_EQ(plain.status, 0) << describe(plain);
    EXPECT_EQ(piped.out, plain.out);
    EXPECT_EQ(lines_of(plain.out).size(), 4u) << describe(plain);
}

TEST(CliEval, StdinAndDirsFileAgree) {
    const std::vector<Pair> pairs = random_pairs(10, 4);
    const std::string dirs = cli_folder() + "/agree.txt";
    write_text(dirs, format_pairs(pairs));
    const ToolRun a = run_npf({"eval", cli_materials().rgb}, format_pairs(pairs));
    const ToolRun b = run_npf({"eval", cli_materials().rgb, "--dirs", dirs});
    const ToolRun c = run_npf({"eval", cli_materials().rgb, "--dirs=" + dirs});
    const ToolRun d = run_npf({"eval", "--dirs", "-", cli_materials().rgb}, format_pairs(pairs));
    for (const ToolRun* r : {&a, &b, &c, &d}) {
        EXPECT_EQ(r->status, 0) << describe(*r);
        EXPECT_EQ(r->out, a.out) << describe(*r);
    }
    EXPECT_EQ(lines_of(a.out).size(), pairs.size() + 1);
}

TEST(CliEval, DirectionsAreNormalised) {
    const std::vector<Pair> pairs = random_pairs(20, 5);
    // Exactly representable scales, so the normalised directions are bit-identical.
    for (const std::string& m : {cli_materials().rgb, cli_materials().spectral}) {
        const ToolRun unit = run_npf({"eval", m}, format_pairs(pairs));
        const ToolRun scaled = run_npf({"eval", m}, format_pairs(pairs, 4.0, 0.125));
        const ToolRun scaled2 = run_npf({"eval", m, "--cos"}, format_pairs(pairs, 1024.0, 2.0));
        const ToolRun unit2 = run_npf({"eval", m, "--cos"}, format_pairs(pairs));
        ASSERT_EQ(unit.status, 0) << describe(unit);
        EXPECT_EQ(scaled.out, unit.out) << describe(scaled);
        EXPECT_EQ(scaled2.out, unit2.out) << describe(scaled2);
    }
    // Non-power-of-two scales agree to float precision.
    const ToolRun unit = run_npf({"eval", cli_materials().rgb}, format_pairs(pairs));
    const ToolRun odd = run_npf({"eval", cli_materials().rgb}, format_pairs(pairs, 3.7, 0.3));
    const EvalOutput a = parse_eval(unit.out), b = parse_eval(odd.out);
    ASSERT_EQ(a.values.size(), b.values.size());
    for (std::size_t i = 0; i < a.values.size(); ++i) {
        for (std::size_t k = 0; k < a.values[i].size(); ++k) {
            EXPECT_NEAR(b.values[i][k], a.values[i][k], 1e-4 * std::fabs(a.values[i][k]) + 1e-6) << i;
        }
    }
}

TEST(CliEval, BelowHorizonGivesZero) {
    const std::string text =
        "0.3 0.1 -0.9  0.2 0.2 0.9\n"    // wi below
        "0.3 0.1 0.9   0.2 0.2 -0.9\n"   // wo below
        "0 0 -1        0 0 -1\n"         // both below
        "1 0 0         0.3 0.2 0.9\n"    // wi on the horizon
        "0.3 0.2 0.9   0 1 0\n";         // wo on the horizon
    for (const std::string& m : {cli_materials().rgb, cli_materials().spectral}) {
        for (const std::vector<std::string>& flags :
             {std::vector<std::string>{}, std::vector<std::string>{"--cos"}, std::vector<std::string>{"--raw"}}) {
            std::vector<std::string> args = {"eval", m};
            args.insert(args.end(), flags.begin(), flags.end());
            const ToolRun r = run_npf(args, text);
            ASSERT_EQ(r.status, 0) << describe(r);
            const EvalOutput e = parse_eval(r.out);
            ASSERT_EQ(e.values.size(), 5u) << describe(r);
            for (const auto& row : e.tokens) {
                ASSERT_EQ(row.size(), m == cli_materials().rgb ? 3u : 4u) << describe(r);
                for (const std::string& t : row) EXPECT_EQ(t, "0") << describe(r);
            }
        }
    }
}

TEST(CliEval, CosIsFrTimesCosThetaO) {
    const std::vector<Pair> pairs = random_pairs(30, 6);
    const std::string m = cli_materials().rgb_aniso;
    const npf::ChannelQuery q = query_for(m, npf::Channels::rgb());
    const EvalOutput fr = eval_and_compare(m, pairs, {}, q, false);
    const EvalOutput fc = eval_and_compare(m, pairs, {"--cos"}, q, true);
    ASSERT_EQ(fr.values.size(), fc.values.size());
    for (std::size_t i = 0; i < pairs.size() && i < fr.values.size(); ++i) {
        const double lo = std::sqrt(pairs[i].v[3] * pairs[i].v[3] + pairs[i].v[4] * pairs[i].v[4] +
                                    pairs[i].v[5] * pairs[i].v[5]);
        const double cos_o = double(float(pairs[i].v[5] / lo));
        for (std::size_t k = 0; k < 3; ++k) {
            EXPECT_NEAR(fc.values[i][k], fr.values[i][k] * cos_o, 1e-7 * std::fabs(fc.values[i][k]) + 1e-30);
        }
    }
}

TEST(CliEval, PdfColumnIsTheSamplingDensity) {
    const std::vector<Pair> pairs = random_pairs(30, 8);
    const std::string m = cli_materials().rgb_aniso;
    const std::string dirs = cli_folder() + "/pdf_pairs.txt";
    write_text(dirs, format_pairs(pairs));
    const ToolRun r = run_npf({"eval", m, "--dirs", dirs, "--cos", "--pdf"});
    ASSERT_EQ(r.status, 0) << describe(r);
    const EvalOutput e = parse_eval(r.out);
    EXPECT_EQ(e.header, "# R G B pdf");
    ASSERT_EQ(e.values.size(), pairs.size()) << describe(r);
    const std::unique_ptr<RglBrdf> brdf = RglBrdf::load(m);
    int positive = 0;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        ASSERT_EQ(e.values[i].size(), 4u) << describe(r);
        const Pair& p = pairs[i];
        const double li = std::sqrt(p.v[0] * p.v[0] + p.v[1] * p.v[1] + p.v[2] * p.v[2]);
        const double lo = std::sqrt(p.v[3] * p.v[3] + p.v[4] * p.v[4] + p.v[5] * p.v[5]);
        const double want = brdf->pdf(Vec3(float(p.v[0] / li), float(p.v[1] / li), float(p.v[2] / li)),
                                      Vec3(float(p.v[3] / lo), float(p.v[4] / lo), float(p.v[5] / lo)));
        EXPECT_NEAR(e.values[i][3], want, 1e-7 * want + 1e-30) << "pair " << i;
        positive += want > 0.0;
    }
    EXPECT_GT(positive, 20);
}

TEST(CliEval, WavelengthListInterpolatesLinearly) {
    const std::string m = cli_materials().spectral;
    const std::vector<Pair> pairs = random_pairs(25, 7);
    const EvalOutput e = eval_and_compare(m, pairs, {"--wavelengths", "450,550"},
                                          query_for(m, npf::Channels::spectral({450.f, 550.f})), false);
    EXPECT_EQ(e.header, "# 450 550");
    // Against the stored wavelengths directly: halfway between neighbours.
    const std::unique_ptr<RglBrdf> b = RglBrdf::load(m);
    const npf::ChannelQuery native = b->native_query();
    int checked = 0;
    for (std::size_t i = 0; i < pairs.size() && i < e.values.size(); ++i) {
        const std::vector<double> s = expected_values(*b, native, pairs[i], false);
        ASSERT_EQ(s.size(), 4u);
        EXPECT_NEAR(e.values[i][0], 0.5 * (s[0] + s[1]), 1e-5 * std::fabs(e.values[i][0]) + 1e-12) << i;
        EXPECT_NEAR(e.values[i][1], 0.5 * (s[1] + s[2]), 1e-5 * std::fabs(e.values[i][1]) + 1e-12) << i;
        checked += s[0] > 0.0 && s[0] != s[1];
    }
    EXPECT_GT(checked, 10);  // the check is not vacuous
}

TEST(CliEval, WavelengthRange) {
    const std::string m = cli_materials().spectral;
    const std::vector<Pair> pairs = random_pairs(15, 8);
    const EvalOutput range = eval_and_compare(m, pairs, {"--wavelengths", "400:700:4"},
                                              query_for(m, npf::Channels::spectral({400.f, 500.f, 600.f, 700.f})),
                                              false);
    EXPECT_EQ(range.header, "# 400 500 600 700");
    const ToolRun plain = run_npf({"eval", m}, format_pairs(pairs));
    const ToolRun ranged = run_npf({"eval", m, "--wavelengths", "400:700:4"}, format_pairs(pairs));
    EXPECT_EQ(ranged.out, plain.out);

    // Outside the stored range the values are constant; 475 is three quarters of the way
    // from 400 to 500.
    const EvalOutput wide = eval_and_compare(m, pairs, {"--wavelengths=300:900:3", "--cos"},
                                             query_for(m, npf::Channels::spectral({300.f, 600.f, 900.f})), true);
    EXPECT_EQ(wide.header, "# 300 600 900");
    const EvalOutput odd = eval_and_compare(m, pairs, {"--wavelengths", "475,700,400"},
                                            query_for(m, npf::Channels::spectral({475.f, 700.f, 400.f})), false);
    EXPECT_EQ(odd.header, "# 475 700 400");
    const std::unique_ptr<RglBrdf> b = RglBrdf::load(m);
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const std::vector<double> s = expected_values(*b, b->native_query(), pairs[i], true);
        const std::vector<double> f = expected_values(*b, b->native_query(), pairs[i], false);
        EXPECT_NEAR(wide.values[i][0], s[0], 1e-6 * s[0] + 1e-12);
        EXPECT_NEAR(wide.values[i][1], s[2], 1e-6 * s[2] + 1e-12);
        EXPECT_NEAR(wide.values[i][2], s[3], 1e-6 * s[3] + 1e-12);
        EXPECT_NEAR(odd.values[i][0], 0.25 * f[0] + 0.75 * f[1], 1e-5 * f[1] + 1e-12);
        EXPECT_NEAR(odd.values[i][1], f[3], 1e-6 * f[3] + 1e-12);
        EXPECT_NEAR(odd.values[i][2], f[0], 1e-6 * f[0] + 1e-12);
    }
}

TEST(CliEval, RawKeepsNegativeValues) {
    const std::string m = cli_materials().rgb;
    const std::unique_ptr<RglBrdf> b = RglBrdf::load(m);
    npf::ChannelQuery raw = b->native_query();
    raw.clamp_negative = false;
    // Find pairs whose raw blue value is negative (the synthetic file dips below zero there).
    std::vector<Pair> found;
    for (const Pair& p : random_pairs(4000, 9)) {
        if (expected_values(*b, raw, p, false)[2] < -1e-3) found.push_back(p);
        if (found.size() == 5) break;
    }
    ASSERT_FALSE(found.empty()) << "no pair with a negative raw value in the synthetic RGB file";
    const EvalOutput r = eval_and_compare(m, found, {"--raw"}, raw, false);
    const EvalOutput c = eval_and_compare(m, found, {}, b->native_query(), false);
    ASSERT_EQ(r.values.size(), found.size());
    ASSERT_EQ(c.values.size(), found.size());
    for (std::size_t i = 0; i < found.size(); ++i) {
        EXPECT_LT(r.values[i][2], 0.0) << r.tokens[i][2];
        EXPECT_EQ(c.tokens[i][2], "0");
        EXPECT_EQ(r.values[i][0], c.values[i][0]);  // positive channels are unaffected
    }
}

TEST(CliEval, ValuesHaveAtLeastSevenSignificantDigits) {
    const std::string m = cli_materials().rgb_aniso;
    const std::vector<Pair> pairs = random_pairs(30, 10);
    // eval_and_compare's default tolerance of 1e-7 relative already requires 7 digits; check the
    // printed text as well: any value that is not short by nature shows 7 or more digits.
    const EvalOutput e = eval_and_compare(m, pairs, {"--cos"}, query_for(m, npf::Channels::rgb()), true, 1e-7);
    int long_values = 0, total = 0;
    for (const auto& row : e.tokens) {
        for (const std::string& t : row) {
            if (t == "0") continue;
            ++total;
            long_values += significant_digits(t) >= 7;
        }
    }
    ASSERT_GT(total, 30);
    EXPECT_GE(long_values, total * 9 / 10);
}

// ---- npf eval: errors ---------------------------------------------------------------------

TEST(CliEval, MalformedLineNamesFileAndLine) {
    const std::string dirs = cli_folder() + "/malformed.txt";
    struct Case {
        std::string line;
        std::string problem;
    };
    const Case cases[] = {
        {"0 0 1 0 0", "expected six numbers"},
        {"0 0 1 0 0 one", "expected six numbers"},
        {"0 0 1 0 0 1 7", "unexpected text after six numbers: '7'"},
        {"0 0 1 0 0 1 junk", "unexpected text after six numbers: 'junk'"},
        {"nan 0 1 0 0 1", "expected six numbers"},  // iostreams do not read "nan"
        {"1e999 0 1 0 0 1", ""},                    // out of range: rejected, whatever the reason
        {"0 0 0 0 0 1", "a direction of zero length"},
        {"0 0 1 0 0 0", "a direction of zero length"},
    };
    for (const Case& c : cases) {
        const std::string text = "# header comment\n0 0 1 0.6 0 0.8\n\n" + c.line + "\n0 0 1 0 0 1\n";
        write_text(dirs, text);
        ToolRun r = run_npf({"eval", cli_materials().rgb, "--dirs", dirs});
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_TRUE(contains(r.err, dirs + ":4: ")) << describe(r);
        if (!c.problem.empty()) {
            EXPECT_TRUE(contains(r.err, c.problem)) << describe(r);
        }
        r = run_npf({"eval", cli_materials().rgb}, text);
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_TRUE(contains(r.err, "<stdin>:4: ")) << describe(r);
    }
}

TEST(CliEval, MissingFiles) {
    const std::string missing = cli_folder() + "/missing_material.bsdf";
    ToolRun r = run_npf({"eval", missing}, "0 0 1 0 0 1\n");
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "npf eval: error: " + missing + ": cannot open")) << describe(r);
    EXPECT_EQ(r.out, "");

    const std::string missing_dirs = cli_folder() + "/missing_dirs.txt";
    r = run_npf({"eval", cli_materials().rgb, "--dirs", missing_dirs});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, missing_dirs + ": cannot open: file not found")) << describe(r);

    r = run_npf({"eval", cli_materials().rgb, "--dirs", cli_folder()});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, cli_folder() + ": is a directory, not a direction file")) << describe(r);

    r = run_npf({"eval", cli_folder()}, "0 0 1 0 0 1\n");
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, cli_folder() + ": is a directory")) << describe(r);

    const std::string broken = cli_folder() + "/broken_eval.bsdf";
    std::vector<std::uint8_t> bytes = npf::testing::make_synthetic_rgl(SyntheticRglSpec()).serialize();
    bytes.resize(bytes.size() / 2);
    write_text(broken, std::string(bytes.begin(), bytes.end()));
    r = run_npf({"eval", broken}, "0 0 1 0 0 1\n");
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, broken + ": field '")) << describe(r);
    EXPECT_TRUE(contains(r.err, "extends past the end of the file")) << describe(r);
}

TEST(CliEval, WavelengthsOnRgbFile) {
    const ToolRun r = run_npf({"eval", cli_materials().rgb, "--wavelengths", "450,550"}, "0 0 1 0 0 1\n");
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, cli_materials().rgb + ": holds RGB data; --wavelengths needs a spectral file"))
        << describe(r);
    EXPECT_EQ(r.out, "");
}

TEST(CliEval, UnknownOptionAndBadUsage) {
    ToolRun r = run_npf({"eval", cli_materials().rgb, "--bogus"}, "0 0 1 0 0 1\n");
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "unknown option '--bogus'")) << describe(r);
    r = run_npf({"eval", cli_materials().rgb, "--cos=1"}, "0 0 1 0 0 1\n");
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "--cos: takes no value")) << describe(r);
    r = run_npf({"eval", cli_materials().rgb, "--dirs"});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "--dirs: needs a value")) << describe(r);
    r = run_npf({"eval"});
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(contains(r.out, "usage: npf eval")) << describe(r);
    r = run_npf({"eval", cli_materials().rgb, cli_materials().spectral});
    EXPECT_EQ(r.status, 2) << describe(r);
    r = run_npf({"eval", "--help"});
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, "--wavelengths")) << describe(r);
}

TEST(CliEval, BadWavelengthList) {
    struct Case {
        std::string list;
        std::string problem;
    };
    const Case cases[] = {
        {"abc", "'abc' in wavelength list 'abc' is not a positive number (nm)"},
        {"450,,550", "'' in wavelength list"},
        {"0,500", "'0' in wavelength list"},
        {"-450", "'-450' in wavelength list"},
        {"450nm", "'450nm' in wavelength list"},
        {"400:700", "wavelength range '400:700' must be start:end:count"},
        {"400:700:4:5", "must be start:end:count"},
        {"700:400:4", "wavelength range '700:400:4' ends before it starts"},
        {"400:700:2.5", "count '2.5' in '400:700:2.5' must be a whole number"},
        {"400:700:0", "'0' in wavelength list"},
        {"400:700:1", "a range of one wavelength needs start == end"},
        {"", "empty wavelength list"},
        {"450,", "'' in wavelength list '450,'"},
        {",450", "'' in wavelength list ',450'"},
        {"0x1c2", "'0x1c2' in wavelength list"},
        {" 450", "' 450' in wavelength list"},
        {"inf", "'inf' in wavelength list"},
    };
    for (const Case& c : cases) {
        const ToolRun r = run_npf({"eval", cli_materials().spectral, "--wavelengths", c.list}, "0 0 1 0 0 1\n");
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_TRUE(contains(r.err, "--wavelengths: ")) << describe(r);
        EXPECT_TRUE(contains(r.err, c.problem)) << "expected '" << c.problem << "'\n" << describe(r);
        EXPECT_EQ(r.out, "") << describe(r);
    }
}

}  // namespace
