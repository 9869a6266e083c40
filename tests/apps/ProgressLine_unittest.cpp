// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/ProgressLine.h>

#include <gtest/gtest.h>

#include <string>

using emslam::apps::ProgressLine;

TEST(ProgressLine, totalIsExtrapolatedFromTheFraction)
{
    EXPECT_EQ(ProgressLine::extrapolateTotal(1, 1.0 / 1161.0), 1161U);
    EXPECT_EQ(ProgressLine::extrapolateTotal(40, 40.0 / 51.0), 51U);
    EXPECT_EQ(ProgressLine::extrapolateTotal(3, 0.0), 0U);
    EXPECT_EQ(ProgressLine::extrapolateTotal(5, 2.0), 5U);  // clamped to 1
    ProgressLine quiet("test", 1, false);
    EXPECT_EQ(quiet.estimatedTotal(), 0U);
    quiet.updateFraction(10, 10.0 / 639.0);
    EXPECT_EQ(quiet.estimatedTotal(), 639U);
}

TEST(ProgressLine, lastLineSaysDoneWithEtaZero)
{
    testing::internal::CaptureStderr();
    {
        // Off a terminal (stderr is captured): one line per 10 %, and the last one.
        ProgressLine p("prog", 1, true);
        for (std::size_t i = 1; i <= 50; i++)
        {
            p.updateFraction(i, static_cast<double>(i) / 50.0, i > 20 ? "energy 1.5000" : "");
        }
        p.finish();
    }
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("prog: frame 5/~50 ( 10%)"), std::string::npos) << err;
    EXPECT_NE(err.find("prog: frame 50/~50 (100%)"), std::string::npos) << err;
    EXPECT_NE(err.find("ETA 0:00, energy 1.5000\n"), std::string::npos) << err;
    EXPECT_EQ(err.find("energy 0"), std::string::npos) << err;
    std::size_t lines = 0;
    for (const char c : err)
    {
        lines += c == '\n';
    }
    EXPECT_EQ(lines, 10U);
}
