// Bounded text (issue 33, class 4): every line-based input has a cap on its size and on one line,
// refused at once, with the file and the line named; and one-line messages stay one line whatever
// a file name holds.
#include "error_of.h"

#include <npf/core/error.h>
#include <npf/core/text.h>
#include <npf/core/text_input.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <fcntl.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using npf::testing::error_of;

std::string temp_file(const std::string& name, const std::string& bytes) {
    const fs::path dir = fs::path(::testing::TempDir()) / "npf_text_input";
    fs::create_directories(dir);
    const std::string path = (dir / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
}

constexpr npf::TextBounds kSmall{64, 8};

TEST(TextInput, LinesAreReturnedWithoutTheirNewlineAndALastLineWithoutOne) {
    const std::string path = temp_file("lines.txt", "a b\r\n\nlast");
    npf::LineReader r(path, "a file", kSmall);
    std::string line;
    ASSERT_TRUE(r.next(line));
    EXPECT_EQ(line, "a b\r");
    ASSERT_TRUE(r.next(line));
    EXPECT_EQ(line, "");
    ASSERT_TRUE(r.next(line));
    EXPECT_EQ(line, "last");
    EXPECT_EQ(r.line_number(), 3u);
    EXPECT_FALSE(r.ended_with_newline());
    EXPECT_FALSE(r.next(line));
    // The whole file keeps its bytes.
    EXPECT_EQ(npf::read_text_file(path, "a file", kSmall), "a b\r\n\nlast");
    EXPECT_EQ(npf::read_text_file(temp_file("nl.txt", "x\n"), "a file", kSmall), "x\n");
}

TEST(TextInput, AFileAboveTheCapIsRefusedBeforeReading) {
    const std::string path = temp_file("big.txt", std::string(65, '\n'));
    const std::string e = error_of([&] { npf::read_text_file(path, "a recipe", kSmall); });
    EXPECT_NE(e.find(path + ": larger than the 64 bytes a recipe may hold"), std::string::npos) << e;
}

TEST(TextInput, ALongLineIsRefusedNamingItsLine) {
    const std::string path = temp_file("long.txt", "ok\n123456789\n");
    const std::string e = error_of([&] { npf::read_text_file(path, "a file", kSmall); });
    EXPECT_NE(e.find(path + ":2: a line longer than 8 bytes"), std::string::npos) << e;
}

TEST(TextInput, ANulByteIsRefused) {
    const std::string path = temp_file("nul.txt", std::string("ok\nx\0y\n", 7));
    const std::string e = error_of([&] { npf::read_text_file(path, "a file", kSmall); });
    EXPECT_NE(e.find(path + ":2: holds a NUL byte"), std::string::npos) << e;
}

// /dev/zero on a stream: refused after the first block, not after gigabytes.
TEST(TextInput, AnEndlessStreamCostsItsLineCap) {
    const int fd = ::open("/dev/zero", O_RDONLY);
    ASSERT_GE(fd, 0);
    npf::LineReader r(fd, "<stdin>", npf::kStreamTextBounds);
    std::string line;
    const std::string e = error_of([&] { r.next(line); });
    ::close(fd);
    EXPECT_NE(e.find("<stdin>:1: holds a NUL byte"), std::string::npos) << e;
    // Spaces without a newline: the line cap.
    const std::string path = temp_file("spaces.txt", std::string(100000, ' '));
    npf::LineReader s(path, "a direction file", npf::kStreamTextBounds);
    const std::string e2 = error_of([&] { s.next(line); });
    EXPECT_NE(e2.find(path + ":1: a line longer than 4 KiB"), std::string::npos) << e2;
}

TEST(TextInput, AStreamAboveItsTotalCapStops) {
    const std::string path = temp_file("many.txt", std::string(200, '\n'));
    const int fd = ::open(path.c_str(), O_RDONLY);
    ASSERT_GE(fd, 0);
    npf::LineReader r(fd, "pipe", npf::TextBounds{100, 8});
    std::string line;
    const std::string e = error_of([&] {
        while (r.next(line)) {
        }
    });
    ::close(fd);
    EXPECT_NE(e.find("pipe: more than 100 bytes of text"), std::string::npos) << e;
}

TEST(TextInput, MessagesStayOneLineWhateverANameHolds) {
    const npf::Error e("a\nb\tc\x1b[2Jd\x7f.exr", "bad\rvalue");
    EXPECT_STREQ(e.what(), "a\\nb\\tc\\x1b[2Jd\\x7f.exr: bad\\rvalue");
    EXPECT_EQ(e.source(), "a\nb\tc\x1b[2Jd\x7f.exr");  // raw for programs
    EXPECT_EQ(npf::printable("caf\xc3\xa9"), "caf\xc3\xa9");  // UTF-8 kept
}

}  // namespace
