// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/TextParsing.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace emslam::io
{
TEST(TextParsing, trimmedDropsBlanksAtBothEnds)
{
    EXPECT_EQ(trimmed("  P0: 1 2 \t\r\n"), "P0: 1 2");
    EXPECT_EQ(trimmed("abc"), "abc");
    EXPECT_EQ(trimmed("a b"), "a b");
    EXPECT_EQ(trimmed(" \t\r\n "), "");
    EXPECT_EQ(trimmed(""), "");
}

TEST(TextParsing, blankAndCommentLines)
{
    EXPECT_TRUE(isBlank(""));
    EXPECT_TRUE(isBlank(" \t\r"));
    EXPECT_FALSE(isBlank(" 1 "));
    EXPECT_FALSE(isBlank("# comment"));

    EXPECT_TRUE(isCommentOrBlank(""));
    EXPECT_TRUE(isCommentOrBlank("\r"));
    EXPECT_TRUE(isCommentOrBlank("# timestamp tx ty tz"));
    EXPECT_TRUE(isCommentOrBlank("  \t#x"));
    EXPECT_FALSE(isCommentOrBlank("1 # trailing"));
}

TEST(TextParsing, parseDoubleAcceptsNumbersAndLeadingPlus)
{
    double v = 0;
    ASSERT_TRUE(parseDouble("1.5", v));
    EXPECT_EQ(v, 1.5);
    ASSERT_TRUE(parseDouble("-2.25e-3", v));
    EXPECT_EQ(v, -2.25e-3);
    ASSERT_TRUE(parseDouble("+7.070912000000e+02", v));
    EXPECT_EQ(v, 707.0912);
    ASSERT_TRUE(parseDouble("42", v));
    EXPECT_EQ(v, 42.0);
    ASSERT_TRUE(parseDouble(".5", v));
    EXPECT_EQ(v, 0.5);
    // Non-finite values parse: callers that forbid them check std::isfinite.
    ASSERT_TRUE(parseDouble("inf", v));
    EXPECT_TRUE(std::isinf(v));
    ASSERT_TRUE(parseDouble("nan", v));
    EXPECT_TRUE(std::isnan(v));
}

TEST(TextParsing, parseDoubleRejectsGarbageAndLeavesValue)
{
    for (const char* bad :
         {"", "+", "-", "++1", "+ 1", "1.5x", "1.5 ", " 1.5", "1,5", "abc", "0x10", "1e", "1e999",
          "1.5\r"})
    {
        double v = 3.0;
        EXPECT_FALSE(parseDouble(bad, v)) << "'" << bad << "'";
        EXPECT_EQ(v, 3.0) << "'" << bad << "'";
    }
}

TEST(TextParsing, parseDoubleReadsOnlyTheView)
{
    const std::string s = "12.5,7";
    double v = 0;
    ASSERT_TRUE(parseDouble(std::string_view(s).substr(0, 4), v));
    EXPECT_EQ(v, 12.5);
}

TEST(TextParsing, parseInt64AcceptsTheFullRange)
{
    std::int64_t v = 0;
    ASSERT_TRUE(parseInt64("1403715274312143104", v));
    EXPECT_EQ(v, 1403715274312143104);
    ASSERT_TRUE(parseInt64("-17", v));
    EXPECT_EQ(v, -17);
    ASSERT_TRUE(parseInt64("9223372036854775807", v));
    EXPECT_EQ(v, std::numeric_limits<std::int64_t>::max());
    ASSERT_TRUE(parseInt64("-9223372036854775808", v));
    EXPECT_EQ(v, std::numeric_limits<std::int64_t>::min());
}

TEST(TextParsing, parseInt64RejectsOverflowAndGarbage)
{
    for (const char* bad :
         {"9223372036854775808", "-9223372036854775809", "99999999999999999999", "", "+5", "-",
          "1.0", "1e3", "12a", " 12", "12 ", "12\r"})
    {
        std::int64_t v = 5;
        EXPECT_FALSE(parseInt64(bad, v)) << "'" << bad << "'";
        EXPECT_EQ(v, 5) << "'" << bad << "'";
    }
}

TEST(TextParsing, parseNanosecondsAcceptsTheInt64RangeFromZero)
{
    std::int64_t v = 5;
    ASSERT_TRUE(parseNanoseconds("9223372036854775807", v));
    EXPECT_EQ(v, std::numeric_limits<std::int64_t>::max());
    ASSERT_TRUE(parseNanoseconds("0.000", v));
    EXPECT_EQ(v, 0);
    ASSERT_TRUE(parseNanoseconds("1403715274312143104.0000000000", v));
    EXPECT_EQ(v, 1403715274312143104);
    // Negative stamps would make the difference of two stamps overflow; a
    // non-zero fraction of a nanosecond would be lost (it was truncated).
    for (const char* bad :
         {"-9223372036854775808", "-1", "-0", "-1.5", "9223372036854775808", "1e19", "12.3x", "",
          ".5", "+1", "1403636579763555584.5", "1.0000000001"})
    {
        v = 5;
        EXPECT_FALSE(parseNanoseconds(bad, v)) << "'" << bad << "'";
        EXPECT_EQ(v, 5) << "'" << bad << "'";
    }
}

TEST(TextParsing, parseNumbersSplitsOnBlanks)
{
    std::vector<double> v;
    ASSERT_TRUE(parseNumbers("1 -2.5\t+3e2   4", v));
    EXPECT_EQ(v, (std::vector<double>{1.0, -2.5, 300.0, 4.0}));
    ASSERT_TRUE(parseNumbers("  \t 0.1 ", v));
    EXPECT_EQ(v, (std::vector<double>{0.1}));
}

TEST(TextParsing, parseNumbersAcceptsCrlfLines)
{
    std::vector<double> v;
    ASSERT_TRUE(parseNumbers("0.000000e+00 1.03\r", v));
    EXPECT_EQ(v, (std::vector<double>{0.0, 1.03}));
    ASSERT_TRUE(parseNumbers("\r", v));
    EXPECT_TRUE(v.empty());
}

TEST(TextParsing, parseNumbersEmptyLineGivesEmptyVector)
{
    std::vector<double> v{1.0, 2.0};
    ASSERT_TRUE(parseNumbers("", v));
    EXPECT_TRUE(v.empty());
    v = {1.0};
    ASSERT_TRUE(parseNumbers(" \t ", v));
    EXPECT_TRUE(v.empty());
}

TEST(TextParsing, parseNumbersCommasOnlyWhenAsked)
{
    std::vector<double> v;
    EXPECT_FALSE(parseNumbers("1,2,3", v));
    ASSERT_TRUE(parseNumbers("1,2, 3,,4\r", v, " \t,\r"));
    EXPECT_EQ(v, (std::vector<double>{1.0, 2.0, 3.0, 4.0}));
    ASSERT_TRUE(parseNumbers(",5,", v, " \t,\r"));
    EXPECT_EQ(v, (std::vector<double>{5.0}));
}

TEST(TextParsing, parseNumbersRejectsGarbage)
{
    std::vector<double> v;
    EXPECT_FALSE(parseNumbers("1 2 x 4", v));
    EXPECT_EQ(v, (std::vector<double>{1.0, 2.0}));  // the numbers before the bad token
    EXPECT_FALSE(parseNumbers("1 2.0.0", v));
    EXPECT_FALSE(parseNumbers("1 +", v));
    EXPECT_FALSE(parseNumbers("1;2", v));
    EXPECT_FALSE(parseNumbers("1\n", v));  // LF is not a default separator
    EXPECT_FALSE(parseNumbers("1 1e999", v));
}

// Every reader quotes input in its messages through this: a 400 KB line was
// echoed whole before.
TEST(TextParsing, quotedExcerptCutsLongInputAfter60Bytes)
{
    EXPECT_EQ(quotedExcerpt(""), "''");
    EXPECT_EQ(quotedExcerpt("12x4,a.png"), "'12x4,a.png'");
    const std::string sixty(60, 'a');
    EXPECT_EQ(quotedExcerpt(sixty), "'" + sixty + "'");
    EXPECT_EQ(quotedExcerpt(sixty + "b"), "'" + sixty + "\u2026' (61 bytes)");
    EXPECT_EQ(
        quotedExcerpt(std::string(100000, 'x')),
        "'" + std::string(60, 'x') + "\u2026' (100000 bytes)");
    // A 2-byte character (e with acute accent) across the cut is left out whole.
    const std::string e_acute = "\xC3\xA9";
    EXPECT_EQ(
        quotedExcerpt(std::string(59, 'a') + e_acute + "zz"),
        "'" + std::string(59, 'a') + "\u2026' (63 bytes)");
    EXPECT_EQ(
        quotedExcerpt(std::string(58, 'a') + e_acute + "zz"),
        "'" + std::string(58, 'a') + e_acute + "\u2026' (62 bytes)");
}

}  // namespace emslam::io
