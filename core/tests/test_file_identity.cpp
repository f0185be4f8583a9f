// Outputs against each other and the inputs, by identity (issue 33, class 7): the library check.
// The commands' use of it is tested in test_output_aliasing.cpp.
#include "error_of.h"

#include <npf/core/file_identity.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using npf::testing::error_of;

struct Folder {
    fs::path dir = fs::path(::testing::TempDir()) / "npf_file_identity";
    Folder() {
        fs::remove_all(dir);
        fs::create_directories(dir / "sub");
        std::ofstream(dir / "m.exr") << "m";
    }
    std::string operator/(const std::string& name) const { return (dir / name).string(); }
};

TEST(FileIdentity, DistinctFilesPass) {
    Folder f;
    npf::check_distinct_files({{f / "m.exr", "the input", false}, {f / "out.exr", "-o", true}, {f / "out.png", "--png", true}});
    // Two inputs may be one file (a reference compared with itself).
    npf::check_distinct_files({{f / "m.exr", "REF", false}, {f / "m.exr", "TEST", false}});
    // Devices are written through: /dev/null twice is fine.
    npf::check_distinct_files({{"/dev/null", "-o", true}, {"/dev/null", "--png", true}});
}

TEST(FileIdentity, AnOutputNamedTwiceOrOverAnInputIsRefusedByAnyName) {
    Folder f;
    std::string e = error_of([&] { npf::check_distinct_files({{f / "x", "-o", true}, {f / "x", "--png", true}}); });
    EXPECT_EQ(e, f / "x" + ": is named twice (-o and --png): one output would replace the other");
    // Not there yet, spelled differently.
    e = error_of([&] { npf::check_distinct_files({{f / "x", "-o", true}, {f / "sub/../x", "--png", true}}); });
    EXPECT_NE(e.find("is the same file as"), std::string::npos) << e;
    e = error_of([&] { npf::check_distinct_files({{f / "m.exr", "the input", false}, {f / "./m.exr", "-o", true}}); });
    EXPECT_NE(e.find(": the output would replace an input"), std::string::npos) << e;
    // A hard link and a symbolic link to the input.
    ASSERT_EQ(::link((f / "m.exr").c_str(), (f / "hard.exr").c_str()), 0);
    fs::create_symlink(f / "m.exr", f / "soft.exr");
    for (const char* name : {"hard.exr", "soft.exr"}) {
        e = error_of([&] { npf::check_distinct_files({{f / "m.exr", "the input", false}, {f / name, "-o", true}}); });
        EXPECT_EQ(e, f / name + ": is the same file as " + f / "m.exr" + " (the input and -o): the output would replace an input");
    }
    // A link whose target is not there yet, and that target named directly.
    fs::create_symlink("new.exr", f / "later.exr");
    e = error_of([&] { npf::check_distinct_files({{f / "later.exr", "-o", true}, {f / "new.exr", "--png", true}}); });
    EXPECT_NE(e.find("is the same file as"), std::string::npos) << e;
}

}  // namespace
