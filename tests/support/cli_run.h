// What the tests of the `npf` subcommands share on top of run_tool.h: running `npf` with a
// standard input, the shipped recipes, and reading printed tables and images.
#pragma once

#include "run_tool.h"

#include <optional>
#include <string>
#include <vector>

namespace npf::testing {

// Runs `npf args...` with `stdin_text` (or nothing) on standard input.
ToolRun run_npf(const std::vector<std::string>& args, const std::optional<std::string>& stdin_text = std::nullopt);

// A shipped analytic recipe: configs/materials/NAME.yaml.
std::string material_recipe(const std::string& name);

// The blank-separated words of a printed line.
std::vector<std::string> words_of(const std::string& line);

// Writes `pixels` (width x height x channels floats, interleaved) as a float OpenEXR file; a test
// failure if it cannot.
void write_float_exr(const std::string& path, const std::vector<float>& pixels, int width, int height, int channels);

}  // namespace npf::testing
