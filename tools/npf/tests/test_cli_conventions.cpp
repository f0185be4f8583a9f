// The command-line conventions every npf subcommand shares (README "Exit status"): --version,
// usage errors as one line on stderr, --help on stdout, "--" ending the options, flag order,
// and the --json forms of info and eval carrying what their text carries.
#include "cli_run.h"
#include "command_line.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <sys/wait.h>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace npf::testing;  // run_tool, describe, contains, ...

// main.cpp's table.
const std::vector<std::string> kCommands = {"info",   "eval",   "convert", "synth",   "bench", "display",
                                            "render", "albedo", "compare", "edit",    "batch"};

// Unknown options keep the status 1 that existing tests pin (command_line.h, kOptionErrorStatus).
constexpr int kOptionErrorStatus = 1;

std::string project_version() {
    const std::string text = npf::testing::read_text(std::string(NPF_SOURCE_DIR) + "/CMakeLists.txt");
    std::smatch m;
    return std::regex_search(text, m, std::regex(R"(project\(npf VERSION ([0-9.]+))")) ? m[1].str() : "?";
}

// "npf CMD: error: ... (see npf CMD --help)" and nothing else on stderr, nothing on stdout.
void expect_usage_line(const ToolRun& r, const std::string& command, int status) {
    EXPECT_EQ(r.status, status) << describe(r);
    EXPECT_EQ(r.out, "") << describe(r);
    const std::vector<std::string> lines = lines_of(r.err);
    ASSERT_EQ(lines.size(), 1u) << describe(r);
    EXPECT_EQ(lines[0].rfind("npf " + command + ": error: ", 0), 0u) << describe(r);
    const std::string tail = "(see npf " + command + " --help)";
    EXPECT_TRUE(lines[0].size() > tail.size() && lines[0].compare(lines[0].size() - tail.size(), tail.size(), tail) == 0)
        << describe(r);
}

bool have_python() { return std::system("python3 -c pass > /dev/null 2>&1") == 0; }

// Runs a python3 snippet over the JSON in `json` (sys.argv[1] is its file) and returns its stdout;
// json.load failing makes the snippet fail.
ToolRun python_over(const std::string& json, const std::string& script) {
    const std::string dir = npf::testing::temporary_folder("cli_conventions_py");
    const std::string in = dir + "/in.json", py = dir + "/check.py", out = dir + "/out.txt";
    EXPECT_TRUE(npf::testing::write_text(in, json));
    EXPECT_TRUE(npf::testing::write_text(py, "import json, sys\nd = json.load(open(sys.argv[1]))\n" + script));
    ToolRun r;
    r.command = "python3 " + py + " " + in;
    const int raw = std::system((r.command + " > " + out + " 2>&1").c_str());
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = npf::testing::read_text(out);
    return r;
}

TEST(CliConventions, VersionForTheToolAndEveryCommand) {
    const std::string first = "npf " + project_version();
    std::vector<std::vector<std::string>> runs = {{"--version"}};
    for (const std::string& c : kCommands) runs.push_back({c, "--version"});
    for (const auto& args : runs) {
        const ToolRun r = npf::testing::run_tool(args);
        EXPECT_EQ(r.status, 0) << describe(r);
        EXPECT_EQ(r.err, "") << describe(r);
        const std::vector<std::string> lines = lines_of(r.out);
        ASSERT_EQ(lines.size(), 2u) << describe(r);
        EXPECT_EQ(lines[0], first) << describe(r);
        EXPECT_EQ(lines[1].rfind("built with OpenImageIO ", 0), 0u) << describe(r);
        EXPECT_TRUE(contains(lines[1], "OpenEXR ")) << describe(r);
    }
}

TEST(CliConventions, EveryCommandReportsUsageErrorsInOneLine) {
    // An argument each command needs, missing (not a bare command: that also prints the usage).
    const std::vector<std::pair<std::string, std::vector<std::string>>> missing = {
        {"info", {"--json"}},           {"eval", {"--cos"}},         {"synth", {"--diffuse", "0.5", "extra.bsdf"}},
        {"bench", {"--json"}},          {"display", {"in.exr"}},     {"render", {"material.bsdf"}},
        {"albedo", {"--json"}},         {"compare", {"only.exr"}},   {"edit", {"in.exr"}},
        {"batch", {"--quiet"}},         {"batch", {"--merge"}},
    };
    for (const auto& [command, args] : missing) {
        SCOPED_TRACE(command);
        expect_usage_line(npf::testing::run_tool([&] {
                              std::vector<std::string> all = {command};
                              all.insert(all.end(), args.begin(), args.end());
                              return all;
                          }()),
                          command, 2);
    }
    for (const std::string& command : kCommands) {
        SCOPED_TRACE(command);
        const ToolRun bad = npf::testing::run_tool({command, "--no-such-option"});
        expect_usage_line(bad, command, kOptionErrorStatus);
        EXPECT_TRUE(contains(bad.err, "unknown option '--no-such-option'")) << describe(bad);
        const ToolRun help = npf::testing::run_tool({command, "--help"});
        EXPECT_EQ(help.status, 0) << describe(help);
        EXPECT_EQ(help.err, "") << describe(help);
        EXPECT_TRUE(contains(help.out, "usage: npf " + command)) << describe(help);
        EXPECT_TRUE(contains(help.out, "\n  --version ")) << describe(help);
    }
}

// cmd_convert.cpp follows once its flag table settles (it still prints the usage itself).
TEST(CliConventions, ConvertMissingOutputIsAUsageError) {
    expect_usage_line(npf::testing::run_tool({"convert", material_recipe("red_plastic")}), "convert", 2);
}

TEST(CliConventions, BareCommandShowsUsageAndTheError) {
    const ToolRun r = npf::testing::run_tool({"eval"});
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(contains(r.out, "usage: npf eval")) << describe(r);
    EXPECT_EQ(r.err, "npf eval: error: expects one FILE, got none (see npf eval --help)\n") << describe(r);
}

TEST(CliConventions, DoubleDashEndsTheOptions) {
    const std::string dir = npf::testing::temporary_folder("cli_conventions_dash");
    fs::copy_file(material_recipe("red_plastic"), dir + "/-x.yaml", fs::copy_options::overwrite_existing);
    npf::testing::ToolRunOptions in_dir;
    in_dir.working_dir = dir;
    const ToolRun info = npf::testing::run_tool({"info", "--", "-x.yaml"}, in_dir);
    EXPECT_EQ(info.status, 0) << describe(info);
    EXPECT_TRUE(npf::testing::has_line(info.out, "file: -x.yaml")) << describe(info);
    // Without "--" it is an option, unknown.
    EXPECT_EQ(npf::testing::run_tool({"info", "-x.yaml"}, in_dir).status, kOptionErrorStatus);

    in_dir.stdin_text = "0 0 1 0 0 1\n";
    const ToolRun eval = npf::testing::run_tool({"eval", "--cos", "--", "-x.yaml"}, in_dir);
    EXPECT_EQ(eval.status, 0) << describe(eval);
    EXPECT_EQ(lines_of(eval.out).size(), 2u) << describe(eval);
    // After "--" even --help is a file name.
    EXPECT_NE(npf::testing::run_tool({"info", "--", "--help"}, in_dir).status, 0);
}

TEST(CliConventions, CommandLineKeepsFlagOrder) {
    using npf::cli::CommandLine;
    const std::vector<npf::cli::FlagSpec> flags = {{"--a", true, ""}, {"--b", false, ""}, {"-o", true, ""}};
    const CommandLine cl("test", {"--a", "1", "x", "--b", "--a=2", "-o", "out", "--", "--a", "-y"}, flags);
    const std::vector<std::pair<std::string, std::string>> order = {{"--a", "1"}, {"--b", ""}, {"--a", "2"}, {"-o", "out"}};
    EXPECT_EQ(cl.flags_in_order(), order);
    EXPECT_EQ(cl.value("--a"), "2");  // the last one wins
    EXPECT_EQ(cl.positional(), (std::vector<std::string>{"x", "--a", "-y"}));

    EXPECT_THROW(CommandLine("test", {"--version"}, flags), npf::cli::VersionRequest);
    try {
        CommandLine("test", {"--c"}, flags);
        ADD_FAILURE() << "no error for an unknown option";
    } catch (const npf::cli::UsageError& e) {
        EXPECT_EQ(e.status(), kOptionErrorStatus);
        EXPECT_STREQ(e.what(), "unknown option '--c'");
    }
    try {
        CommandLine("test", {"-o", "out"}, flags).expect_positional(1, 1, "one FILE");
        ADD_FAILURE() << "no error for a missing positional";
    } catch (const npf::cli::UsageError& e) {
        EXPECT_EQ(e.status(), 2);
    }
    EXPECT_THROW(CommandLine("test", {"x"}, flags).require("-o"), npf::cli::UsageError);
}

// A flag table reads as the help it prints; a named value is one of its names, or an error that
// names the flag; --help is every command's and answered by main.
TEST(CliConventions, FlagTableAndChoices) {
    using npf::cli::CommandLine;
    const std::vector<npf::cli::FlagSpec> flags = npf::cli::flag_table({
        "-o VALUE  output file",
        "--json  print JSON",
        "--mode VALUE  fast or slow, with a  double space",
    });
    ASSERT_EQ(flags.size(), 3u);
    EXPECT_EQ(flags[0].name, "-o");
    EXPECT_TRUE(flags[0].takes_value);
    EXPECT_EQ(flags[0].help, "output file");
    EXPECT_EQ(flags[1].name, "--json");
    EXPECT_FALSE(flags[1].takes_value);
    EXPECT_EQ(flags[2].help, "fast or slow, with a  double space");

    const std::vector<std::pair<std::string, int>> modes = {{"fast", 1}, {"slow", 2}};
    EXPECT_EQ(CommandLine("test", {}, flags).choice("--mode", modes, 0, "is not fast or slow"), 0);
    EXPECT_EQ(CommandLine("test", {"--mode", "slow"}, flags).choice("--mode", modes, 0, "is not fast or slow"), 2);
    try {
        CommandLine("test", {"--mode=quick"}, flags).choice("--mode", modes, 0, "is not fast or slow");
        ADD_FAILURE() << "no error for an unknown name";
    } catch (const npf::Error& e) {
        EXPECT_STREQ(e.what(), "--mode: 'quick' is not fast or slow");
    }
    EXPECT_TRUE(npf::cli::read_command_line("", flags, {"--json"}).has("--json"));
    try {
        npf::cli::read_command_line("usage: test\n\n", flags, {"--help"});
        ADD_FAILURE() << "no help for --help";
    } catch (const npf::cli::HelpRequest& help) {
        EXPECT_EQ(help.text.rfind("usage: test\n\n  -o VALUE", 0), 0u) << help.text;
        EXPECT_TRUE(contains(help.text, "\n  --help                 show this help\n")) << help.text;
    }
}

TEST(CliConventions, InfoJsonCarriesTheTextsContent) {
    const std::vector<std::string> files = {material_recipe("brushed_copper"), material_recipe("red_plastic")};
    const ToolRun text = npf::testing::run_tool({"info", files[0], files[1]});
    const ToolRun json = npf::testing::run_tool({"info", "--json", files[0], files[1]});
    ASSERT_EQ(text.status, 0) << describe(text);
    ASSERT_EQ(json.status, 0) << describe(json);
    EXPECT_EQ(json.err, "") << describe(json);
    EXPECT_EQ(json.out.front(), '[') << describe(json);

    // Each "key: value" line of the text, rebuilt from the JSON.
    if (!have_python()) GTEST_SKIP() << "python3 is needed to parse the JSON";
    const ToolRun rebuilt = python_over(json.out, R"(
def num(v): return format(v, '.7g')
out = []
for f in d:
    out.append('file: ' + f['file'])
    out.append('description: ' + (f['description'] or '(none)'))
    out.append('size: %d bytes' % f['size_bytes'])
    out.append('isotropic: ' + ('yes' if f['isotropic'] else 'no'))
    if f['channels'] == 'spectral':
        out.append('%d wavelengths' % f['channel_count'])
        out.append('wavelengths (nm): ' + ' '.join(num(w) for w in f['wavelengths_nm']))
    for k, v in f['details'].items(): out.append(k + ': ' + v)
print('\n'.join(out))
)");
    ASSERT_EQ(rebuilt.status, 0) << rebuilt.out;
    for (const std::string& line : lines_of(rebuilt.out)) EXPECT_TRUE(contains(text.out, line)) << line << "\n" << text.out;
    EXPECT_GE(lines_of(rebuilt.out).size(), 10u) << rebuilt.out;
}

TEST(CliConventions, EvalJsonCarriesTheTextsNumbers) {
    npf::testing::ToolRunOptions pairs;
    pairs.stdin_text = "0 0 1 0.5 0 0.866\n0.3 0.1 0.9 -0.2 0.4 0.8\n0 0 1 0 0 -1\n";
    const std::vector<std::string> args = {"eval", material_recipe("brushed_copper"), "--wavelengths", "450,550,650", "--pdf"};
    const ToolRun text = npf::testing::run_tool(args, pairs);
    std::vector<std::string> json_args = args;
    json_args.push_back("--json");
    const ToolRun json = npf::testing::run_tool(json_args, pairs);
    ASSERT_EQ(text.status, 0) << describe(text);
    ASSERT_EQ(json.status, 0) << describe(json);
    EXPECT_TRUE(contains(json.out, "\"channels\": [450, 550, 650]")) << describe(json);
    EXPECT_TRUE(contains(json.out, "\"quantity\": \"f_r\"")) << describe(json);

    if (!have_python()) GTEST_SKIP() << "python3 is needed to parse the JSON";
    const ToolRun rebuilt = python_over(json.out, R"(
print('# ' + ' '.join(format(c, '.7g') for c in d['channels']) + ' pdf')
for r in d['rows']: print(' '.join(format(v, '.9g') for v in r['values'] + [r['pdf']]))
)");
    ASSERT_EQ(rebuilt.status, 0) << rebuilt.out;
    EXPECT_EQ(rebuilt.out, text.out);
}

}  // namespace
