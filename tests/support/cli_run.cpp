#include "cli_run.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <sstream>

namespace npf::testing {

ToolRun run_npf(const std::vector<std::string>& args, const std::optional<std::string>& stdin_text) {
    ToolRunOptions options;
    options.stdin_text = stdin_text;
    return run_tool(args, options);
}

std::string material_recipe(const std::string& name) {
    return std::string(NPF_SOURCE_DIR) + "/configs/materials/" + name + ".yaml";
}

std::vector<std::string> words_of(const std::string& line) {
    std::istringstream is(line);
    std::vector<std::string> out;
    for (std::string t; is >> t;) out.push_back(t);
    return out;
}

void write_float_exr(const std::string& path, const std::vector<float>& pixels, int width, int height, int channels) {
    OIIO::ImageSpec spec(width, height, channels, OIIO::TypeFloat);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec) && out->write_image(OIIO::TypeFloat, pixels.data()) && out->close())
        << OIIO::geterror();
}

}  // namespace npf::testing
