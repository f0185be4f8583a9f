// Running the built `npf` tool from tests: the command goes through the shell with its standard
// input, output and error redirected to files in a temporary folder, and the exit status and
// both streams come back as text.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace npf::testing {

struct ToolRun {
    int status = -1;      // exit status; -1 if the process did not exit normally
    std::string out, err;
    std::string command;  // the command line, shell-quoted, for failure messages
};

struct ToolRunOptions {
    std::optional<std::string> stdin_text;  // nothing: standard input is /dev/null
    std::string working_dir;                // empty: the test process's own
};

// Runs NPF_TOOL_PATH with `args`.
ToolRun run_tool(const std::vector<std::string>& args, const ToolRunOptions& options = {});

// "command: ...\nstatus: ...\nstdout:\n...\nstderr:\n...", for assertion messages.
std::string describe(const ToolRun& run);

std::string shell_quote(const std::string& s);
std::string read_text(const std::string& path);
// Writes `text` to `path` (truncating); returns false on failure.
bool write_text(const std::string& path, const std::string& text);
bool contains(const std::string& text, const std::string& part);
// The lines of `text` (without their newlines), and whether one of them is exactly `line`.
std::vector<std::string> lines_of(const std::string& text);
bool has_line(const std::string& text, const std::string& line);
// The names in a folder (not "." and ".."), sorted.
std::vector<std::string> folder_entries(const std::string& dir);

}  // namespace npf::testing
