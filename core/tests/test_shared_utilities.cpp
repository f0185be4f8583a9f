// The small helpers the libraries and tools share from core (issue 18): one definition each, so
// these pin what every caller gets.
#include <npf/core/error.h>
#include <npf/core/json_text.h>
#include <npf/core/number_text.h>
#include <npf/core/rec709_luminance.h>
#include <npf/core/text.h>
#include <npf/core/version.h>
#include <npf/core/vec.h>
#include <npf/shading/npf_equation.h>
#include <npf/shading/table_interpolation.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

TEST(SharedUtilities, JsonNumberWritesNullForNonFiniteAtAnyPrecision) {
    // JSON has no inf or nan: a bare inf or a string "inf" would break or mislead a parser.
    for (int digits : {1, 4, 9, 17}) {
        EXPECT_EQ(npf::json_number(kInf, digits), "null") << digits;
        EXPECT_EQ(npf::json_number(-kInf, digits), "null") << digits;
        EXPECT_EQ(npf::json_number(std::nan(""), digits), "null") << digits;
    }
    EXPECT_EQ(npf::json_number(-kInf), "null");
    EXPECT_EQ(npf::json_number(std::numeric_limits<double>::max() * 2.0), "null");
}

TEST(SharedUtilities, JsonNumberKeepsTheSignificantDigitsAskedFor) {
    EXPECT_EQ(npf::json_number(1.0 / 3.0), "0.333333333");  // the default: 9
    EXPECT_EQ(npf::json_number(1.0 / 3.0, 4), "0.3333");     // npf bench's timings
    EXPECT_EQ(npf::json_number(123456.0, 4), "1.235e+05");
    EXPECT_EQ(npf::json_number(0.1, 17), "0.10000000000000001");
    EXPECT_EQ(npf::json_number(2.75, 0), "3");  // fewer than 1 digit means 1
    EXPECT_EQ(npf::json_number(0.0, 4), "0");
    EXPECT_EQ(npf::json_number(-2.5e-12, 4), "-2.5e-12");
}

TEST(SharedUtilities, FirstLineStopsAtTheFirstNewline) {
    EXPECT_EQ(npf::first_line("cannot open file\nsecond error\nthird"), "cannot open file");
    EXPECT_EQ(npf::first_line("one line only"), "one line only");
    EXPECT_EQ(npf::first_line("trailing newline\n"), "trailing newline");
    EXPECT_EQ(npf::first_line("\nstarts with a newline"), "");
    EXPECT_EQ(npf::first_line(""), "");
}

TEST(SharedUtilities, PiConstantsAreExactScalingsOfPi) {
    EXPECT_EQ(npf::kHalfPiD, 0.5 * npf::kPiD);
    EXPECT_EQ(npf::kTwoPiD, 2.0 * npf::kPiD);
    EXPECT_EQ(npf::kHalfPiD, 1.5707963267948966);
    EXPECT_EQ(npf::kPiD, 3.141592653589793);
    // The equation's names are the same values.
    EXPECT_EQ(npf::equation::kHalfPi, npf::kHalfPiD);
    EXPECT_EQ(npf::equation::kTwoPi, npf::kTwoPiD);
    // table::atan2 lands exactly on them at the axes.
    EXPECT_EQ(npf::table::atan2(1.0, 0.0), npf::kHalfPiD);
    EXPECT_EQ(npf::table::atan2(0.0, -1.0), npf::kPiD);
    EXPECT_EQ(npf::table::polar_of(1.0, 0.0), npf::kHalfPiD);
}

TEST(SharedUtilities, Rec709LuminanceIsTheFourDigitWeights) {
    // Four digits, not the derived 0.2126390...: the samplers and the RGL writer's luminance
    // field were written with these, and files must not change.
    EXPECT_EQ(npf::rec709_luminance(1.0, 0.0, 0.0), 0.2126);
    EXPECT_EQ(npf::rec709_luminance(0.0, 1.0, 0.0), 0.7152);
    EXPECT_EQ(npf::rec709_luminance(0.0, 0.0, 1.0), 0.0722);
    EXPECT_NEAR(npf::rec709_luminance(1.0, 1.0, 1.0), 1.0, 1e-15);
    const float rgb[3] = {0.25f, 0.5f, 2.f};
    EXPECT_EQ(npf::rec709_luminance(rgb[0], rgb[1], rgb[2]), 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]);
}

namespace {

// The message npf::Error carries for `text` read by `parse`, or "" when it is accepted.
template <typename Parse>
std::string problem_of(Parse parse) {
    try {
        parse();
    } catch (const npf::Error& e) {
        return e.problem();
    }
    return "";
}

}  // namespace

TEST(SharedUtilities, WholeNumbersReadTheSameEverywhere) {
    EXPECT_EQ(npf::parse_whole_number("7", 1, 1024, "--threads"), 7u);
    EXPECT_EQ(npf::parse_whole_number("18446744073709551615", 0, ~std::uint64_t(0), "--seed"), ~std::uint64_t(0));
    for (const char* bad : {"0", "1025", "", "-3", "+5", " 5", "5 ", "1.5", "0x10", "18446744073709551616", "abc"}) {
        EXPECT_EQ(problem_of([&] { npf::parse_whole_number(bad, 1, 1024, "--threads"); }),
                  std::string("needs a whole number in [1, 1024], got '") + bad + "'")
            << bad;
    }
}

TEST(SharedUtilities, FiniteNumbersAndNumberLists) {
    EXPECT_EQ(npf::parse_finite_number("-2.5e-3", "--x"), -2.5e-3);
    EXPECT_EQ(npf::parse_finite_number("+.5", "--x"), 0.5);
    EXPECT_EQ(npf::parse_finite_number("5.", "--x"), 5.0);
    EXPECT_EQ(npf::parse_finite_number("1E+2", "--x"), 100.0);
    // Plain decimals only: blanks, hex, C's special words and a bare sign or point are not
    // numbers, here as in every flag and key.
    for (const char* bad : {"", "nan", "inf", "1e999", "1,2", "2x", " ", " 5", "5 ", "0x10", "infinity", "-", ".", "1e", "e5",
                            "1.2.3", "--1"}) {
        EXPECT_EQ(problem_of([&] { npf::parse_finite_number(bad, "--x"); }), std::string("'") + bad + "' is not a number") << bad;
    }
    EXPECT_EQ(npf::parse_number_list("1.5"), std::vector<double>({1.5}));
    EXPECT_EQ(npf::parse_number_list("0.2,3.1,-1"), std::vector<double>({0.2, 3.1, -1.0}));
    for (const char* other : {"", ",", "1,,2", "1,2,", "Cu", "1,inf", "file.spd", "1, 2", "0x1"}) {
        EXPECT_FALSE(npf::parse_number_list(other).has_value()) << other;
    }
}

TEST(SharedUtilities, TheVersionIsTheProjectVersion) {
    // Defined once (core/CMakeLists.txt); the tool prints it and the batch hashes it.
    EXPECT_EQ(std::string(npf::version()), NPF_TEST_PROJECT_VERSION);
}
