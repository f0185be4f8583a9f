// The npf subcommands. Each takes its arguments (after the subcommand name) and returns the
// process exit status; user errors are thrown as npf::Error (exit 1), usage errors as
// UsageError (command_line.h, exit 2), and reported by main.
#pragma once

#include <string>
#include <vector>

namespace npf::cli {

int run_info(const std::vector<std::string>& args);
int run_eval(const std::vector<std::string>& args);
int run_synth(const std::vector<std::string>& args);
int run_convert(const std::vector<std::string>& args);
int run_bench(const std::vector<std::string>& args);
int run_display(const std::vector<std::string>& args);
int run_render(const std::vector<std::string>& args);
int run_albedo(const std::vector<std::string>& args);
int run_compare(const std::vector<std::string>& args);
int run_edit(const std::vector<std::string>& args);
int run_batch(const std::vector<std::string>& args);

}  // namespace npf::cli
