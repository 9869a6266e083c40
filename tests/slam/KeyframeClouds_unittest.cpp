// SPDX-License-Identifier: BSD-3-Clause
// The map clouds kept per keyframe: packed without losing what the fusion
// needs, and without the points the fusion would never use.
#include <emslam/slam/IntensityCloud.h>
#include <emslam/slam/KeyframeClouds.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

using emslam::slam::IntensityCloud;
using emslam::slam::KeyframeClouds;

namespace
{
/** A wall 1..9 m ahead, seen at a slant: σ = 0.01 z² (f b = 20, σ_d 0.2). */
IntensityCloud slantedWall(bool with_sigma)
{
    IntensityCloud c;
    for (int i = 0; i < 200; ++i)
    {
        const float z = 1.0f + 0.04f * static_cast<float>(i);
        c.points.emplace_back(-2.0f + 0.013f * static_cast<float>(i), 0.7f, z);
        c.intensity.push_back(static_cast<std::uint8_t>(i));
        if (with_sigma)
        {
            c.sigma.push_back(0.01f * z * z);
        }
    }
    return c;
}
}  // namespace

TEST(KeyframeClouds, unpacksEachKeyframesPointsToASmallFractionOfAMillimetre)
{
    KeyframeClouds clouds;
    const IntensityCloud wall = slantedWall(true);
    clouds.append(7, wall);
    clouds.append(9, wall);
    ASSERT_EQ(clouds.size(), 2u);
    EXPECT_EQ(clouds.pointCount(), 400u);
    // 9 bytes a point (3 × int16, uint16 σ, grey) and the scans' bookkeeping.
    EXPECT_LT(clouds.memoryBytes(), 400u * 9u + 1024u);

    const auto scans = clouds.takeScans();
    EXPECT_EQ(clouds.size(), 0u);
    ASSERT_EQ(scans.size(), 2u);
    EXPECT_EQ(scans[0].frame_index, 7u);
    EXPECT_EQ(scans[1].frame_index, 9u);
    const IntensityCloud& out = scans[1].cloud;
    ASSERT_EQ(out.size(), wall.size());
    ASSERT_TRUE(out.hasSigma());
    // The farthest coordinate is 8.96 m: one unit is 0.27 mm.
    for (std::size_t i = 0; i < wall.size(); ++i)
    {
        EXPECT_NEAR(out.points[i].x, wall.points[i].x, 1.5e-4);
        EXPECT_NEAR(out.points[i].y, wall.points[i].y, 1.5e-4);
        EXPECT_NEAR(out.points[i].z, wall.points[i].z, 1.5e-4);
        EXPECT_NEAR(out.sigma[i], wall.sigma[i], 1e-5 * 0.81);
        EXPECT_EQ(out.intensity[i], wall.intensity[i]);
    }
}

TEST(KeyframeClouds, dropsThePointsTheFusionWouldNeverUse)
{
    KeyframeClouds clouds(0.5);  // σ ≤ 0.5 m: z ≤ 7.07 m
    IntensityCloud wall = slantedWall(true);
    wall.points[3].y = std::numeric_limits<float>::quiet_NaN();
    wall.sigma[4] = std::numeric_limits<float>::infinity();
    clouds.append(0, wall);
    std::size_t expected = 0;
    for (std::size_t i = 0; i < wall.size(); ++i)
    {
        expected += (i != 3 && i != 4 && wall.sigma[i] <= 0.5f) ? 1 : 0;
    }
    EXPECT_EQ(expected, 150u);  // z = 1.00 .. 7.04 m (152 points), less the two bad ones
    EXPECT_EQ(clouds.pointCount(), expected);
    const auto scans = clouds.takeScans();
    ASSERT_EQ(scans.size(), 1u);
    for (const float s : scans[0].cloud.sigma)
    {
        EXPECT_LE(s, 0.5f);
    }
    EXPECT_NEAR(scans[0].cloud.points.back().z, 7.04f, 1e-3);
}

TEST(KeyframeClouds, keepsACloudWithoutSigmasWithoutSigmas)
{
    KeyframeClouds clouds(0.01);  // no σ to gate by: every finite point is kept
    clouds.append(3, slantedWall(false));
    const auto scans = clouds.takeScans();
    ASSERT_EQ(scans.size(), 1u);
    EXPECT_EQ(scans[0].cloud.size(), 200u);
    EXPECT_FALSE(scans[0].cloud.hasSigma());
    EXPECT_NEAR(scans[0].cloud.points[0].z, 1.0f, 1.5e-4);
}

TEST(KeyframeClouds, keepsAnEmptyKeyframeAsAnEmptyScan)
{
    KeyframeClouds clouds;
    clouds.append(5, IntensityCloud());
    const auto scans = clouds.takeScans();
    ASSERT_EQ(scans.size(), 1u);
    EXPECT_EQ(scans[0].frame_index, 5u);
    EXPECT_TRUE(scans[0].cloud.empty());
}

TEST(KeyframeClouds, thinsTheKeyframesEvenlyToStayWithinItsBudget)
{
    // 200 points of 9 bytes a keyframe: 1800 bytes; a budget of 10 clouds.
    KeyframeClouds clouds(std::numeric_limits<double>::infinity(), 10 * 1800);
    const IntensityCloud wall = slantedWall(true);
    for (std::size_t k = 0; k < 10; ++k)
    {
        clouds.append(100 + k, wall);
    }
    EXPECT_EQ(clouds.stride(), 1u);
    EXPECT_EQ(clouds.size(), 10u);
    clouds.append(110, wall);  // the 11th: over budget, every 2nd is kept
    EXPECT_EQ(clouds.stride(), 2u);
    EXPECT_EQ(clouds.size(), 6u);
    for (std::size_t k = 11; k < 30; ++k)
    {
        clouds.append(100 + k, wall);
    }
    // 30 keyframes: every 2nd fills 15 > 10, so every 4th: 0, 4, .., 28.
    EXPECT_EQ(clouds.stride(), 4u);
    EXPECT_LE(clouds.memoryBytes(), 10u * 1800u + 1024u);
    const auto scans = clouds.takeScans();
    ASSERT_EQ(scans.size(), 8u);
    for (std::size_t i = 0; i < scans.size(); ++i)
    {
        EXPECT_EQ(scans[i].frame_index, 100 + 4 * i);
    }
}
