// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/DegenerateRun.h>

#include <gtest/gtest.h>

using emslam::apps::degenerateRunWarning;

TEST(DegenerateRun, moreThanHalfOfTheStepsFailed)
{
    EXPECT_EQ(degenerateRunWarning(10, 5, std::nullopt), "");  // half is still a run
    EXPECT_EQ(degenerateRunWarning(10, 6, std::nullopt), "6 of 10 egomotion steps failed (60 %)");
    EXPECT_EQ(degenerateRunWarning(0, 0, std::nullopt), "");  // one frame: no step
    EXPECT_EQ(degenerateRunWarning(3, 3, 100), "3 of 3 egomotion steps failed (100 %)");
}

TEST(DegenerateRun, anEmptyMap)
{
    EXPECT_EQ(degenerateRunWarning(10, 0, 1), "");
    EXPECT_EQ(degenerateRunWarning(10, 0, 0), "the map has no point");
    EXPECT_EQ(
        degenerateRunWarning(4, 4, 0),
        "4 of 4 egomotion steps failed (100 %); the map has no point");
}
