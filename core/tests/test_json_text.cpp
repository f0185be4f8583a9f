// The hand-written JSON of --json outputs and batch summaries: strings escape what JSON requires,
// numbers that JSON cannot hold become null.
#include <npf/core/json_text.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

TEST(JsonText, StringsEscapeQuotesBackslashesAndControlCharacters) {
    EXPECT_EQ(npf::json_string("plain/path.exr"), "\"plain/path.exr\"");
    EXPECT_EQ(npf::json_string("a\"b\\c"), "\"a\\\"b\\\\c\"");
    EXPECT_EQ(npf::json_string("l1\nl2\r\t"), "\"l1\\nl2\\r\\t\"");
    EXPECT_EQ(npf::json_string(std::string("\x01\x7f", 2)), "\"\\u0001\\u007f\"");
    EXPECT_EQ(npf::json_string("caf\xc3\xa9"), "\"caf\xc3\xa9\"");  // UTF-8 passes through
}

TEST(JsonText, NumbersKeepNineDigitsAndNonFiniteBecomesNull) {
    EXPECT_EQ(npf::json_number(0.1), "0.1");
    EXPECT_EQ(npf::json_number(1.0 / 3.0), "0.333333333");
    EXPECT_EQ(npf::json_number(-2.5e-12), "-2.5e-12");
    EXPECT_EQ(npf::json_number(std::numeric_limits<double>::infinity()), "null");
    EXPECT_EQ(npf::json_number(std::nan("")), "null");
}
