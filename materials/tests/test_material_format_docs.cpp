// Each material format carries its user documentation (MaterialFormat::title, documentation),
// and docs/measured-readers.md holds every shipped format's text word for word.
#include <npf/materials/material_formats.h>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace {

std::string read_page(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

TEST(MaterialFormatDocs, EveryShippedFormatIsDocumented) {
    for (const npf::MaterialFormat& f : npf::shipped_material_formats()) {
        const std::string name = f.described_as.empty() ? f.title : f.described_as;
        EXPECT_FALSE(f.title.empty()) << "a shipped format has no title: " << name;
        EXPECT_FALSE(f.documentation.empty()) << "no documentation for " << name;
        EXPECT_EQ(f.documentation.empty() ? '\n' : f.documentation.back(), '\n') << name << ": end it with a newline";
    }
}

TEST(MaterialFormatDocs, ThePageHoldsEachFormatsText) {
    const std::string page_path = std::string(NPF_SOURCE_DIR) + "/docs/measured-readers.md";
    const std::string page = read_page(page_path);
    ASSERT_FALSE(page.empty()) << "cannot read " << page_path;
    for (const npf::MaterialFormat& f : npf::shipped_material_formats()) {
        const std::string text = npf::format_documentation(f);
        EXPECT_NE(page.find(text), std::string::npos)
            << page_path << " lacks the documentation of " << f.title << " (or has another version of it); the "
            << "format's text, to paste as its section's beginning:\n"
            << text;
    }
}

TEST(MaterialFormatDocs, TheDescriptionListsEachDocumentedFormatInOrder) {
    const std::string all = npf::describe_material_formats();
    std::size_t at = 0;
    for (const npf::MaterialFormat& f : npf::shipped_material_formats()) {
        const std::size_t found = all.find(npf::format_documentation(f), at);
        ASSERT_NE(found, std::string::npos) << f.title;
        at = found + 1;
    }
    EXPECT_EQ(all.rfind("## ", 0), 0u);
}

}  // namespace
