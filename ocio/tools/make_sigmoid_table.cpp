// Build step: fits the sigmoid coefficient table (sigmoid_fit.h) and writes it as C++ source, so
// that no process spends the 0.7 s of CPU the fit costs (pbrt-v4 also generates its table at build
// time). Usage: make_sigmoid_table OUTPUT.cpp
#include "../src/sigmoid_fit.h"

#include <npf/core/atomic_file.h>
#include <npf/core/error.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: make_sigmoid_table OUTPUT.cpp\n");
        return 1;
    }
    try {
        using npf::color::detail::SigmoidTable;
        const SigmoidTable table = SigmoidTable::fit();
        const std::vector<float>& c = table.coefficients();
        std::string text =
            "// Generated when npf is built by ocio/tools/make_sigmoid_table.cpp (SigmoidTable::fit()): do not edit.\n"
            "#include <cstdint>\n\n"
            "namespace npf::color::detail {\n\n"
            "// The coefficients' bits, [largest][z][y][x][3] (sigmoid_fit.h).\n"
            "extern const std::uint32_t kSigmoidTableBits[" + std::to_string(c.size()) + "];\n"
            "const std::uint32_t kSigmoidTableBits[" + std::to_string(c.size()) + "] = {\n";
        char word[16];
        for (std::size_t i = 0; i < c.size(); ++i) {
            std::uint32_t bits;
            std::memcpy(&bits, &c[i], sizeof bits);
            std::snprintf(word, sizeof word, "0x%08xu,", unsigned(bits));
            text += word;
            text += (i % 8 == 7) ? "\n" : " ";
        }
        text += "};\n\n}  // namespace npf::color::detail\n";
        npf::write_file_atomically(argv[1], text.data(), text.size());
    } catch (const npf::Error& e) {
        std::fprintf(stderr, "make_sigmoid_table: %s\n", e.what());
        return 1;
    }
    return 0;
}
