// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/eval/MapAccuracy.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

using emslam::eval::MapAccuracy;
using emslam::eval::ReferenceSurface;
using mrpt::math::TPoint3Df;

namespace
{
constexpr double SPACING = 0.02;

/** Samples of the unit square z = 0 (x, y in [0, 1]) at the centres of a
 * 2 cm grid, normal +z, seen from `seen` metres; and, if `wall`, as many on
 * the square x = 5 (y, z in [0, 1]), normal +x, seen from 6 m. */
ReferenceSurface squares(bool wall, float seen = 2.0F)
{
    ReferenceSurface r;
    r.spacing = SPACING;
    for (int i = 0; i < 50; ++i)
    {
        for (int j = 0; j < 50; ++j)
        {
            const auto a = static_cast<float>((i + 0.5) * SPACING);
            const auto b = static_cast<float>((j + 0.5) * SPACING);
            r.points.emplace_back(a, b, 0.0F);
            r.normals.emplace_back(0.0F, 0.0F, 1.0F);
            r.seen_range.push_back(seen);
            if (wall)
            {
                r.points.emplace_back(5.0F, a, b);
                r.normals.emplace_back(1.0F, 0.0F, 0.0F);
                r.seen_range.push_back(6.0F);
            }
        }
    }
    return r;
}
}  // namespace

TEST(MapAccuracy, knownOffsetsGiveTheirMedianAndNinetiethPercentile)
{
    // Ten points above the floor square at 1, 2, ..., 10 cm, anywhere over it.
    std::vector<TPoint3Df> map;
    for (int k = 1; k <= 10; ++k)
    {
        map.emplace_back(
            0.09F * static_cast<float>(k) - 0.05F, 0.5F, 0.01F * static_cast<float>(k));
    }
    const auto a = MapAccuracy::compute(map, squares(false));
    EXPECT_EQ(a.map_points, 10U);
    EXPECT_EQ(a.reference_points, 2500U);
    EXPECT_NEAR(a.median_m, 0.05, 1e-6);  // rank ceil(0.5 * 10) = 5
    EXPECT_NEAR(a.p90_m, 0.09, 1e-6);     // rank 9
    EXPECT_NEAR(a.mean_m, 0.055, 1e-6);
}

TEST(MapAccuracy, completenessIsTheShareOfTheTruthNearTheMap)
{
    // The map covers the floor square 1 cm above it, and not the wall.
    const ReferenceSurface truth = squares(true);
    std::vector<TPoint3Df> map;
    for (std::size_t i = 0; i < truth.points.size(); ++i)
    {
        const auto& p = truth.points[i];
        if (p.z == 0.0F)
        {
            map.emplace_back(p.x, p.y, 0.01F);
        }
    }
    const auto a = MapAccuracy::compute(map, truth);
    EXPECT_EQ(a.reference_points, 5000U);
    EXPECT_DOUBLE_EQ(a.completeness, 0.5);
    EXPECT_NEAR(a.median_m, 0.01, 1e-6);
    EXPECT_NEAR(a.p90_m, 0.01, 1e-6);
    // Near (seen within 4 m): the floor only, all of it covered.
    EXPECT_EQ(a.near_reference_points, 2500U);
    EXPECT_DOUBLE_EQ(a.completeness_near, 1.0);

    // 6 cm above the floor: beyond the 5 cm reach, nothing is covered.
    for (auto& p : map)
    {
        p.z = 0.06F;
    }
    EXPECT_DOUBLE_EQ(MapAccuracy::compute(map, truth).completeness, 0.0);
    MapAccuracy::Options wide;
    wide.completeness_distance = 0.07;
    EXPECT_DOUBLE_EQ(MapAccuracy::compute(map, truth, wide).completeness, 0.5);
}

TEST(MapAccuracy, normalsMeasureToTheSurfaceNotToTheNearestSample)
{
    // A point on the floor plane half-way between samples: 0 to the surface,
    // 1 cm to the nearest sample.
    const std::vector<TPoint3Df> map{{0.02F, 0.01F, 0.0F}};
    EXPECT_NEAR(MapAccuracy::compute(map, squares(false)).median_m, 0.0, 1e-6);
    ReferenceSurface bare = squares(false);
    bare.normals.clear();
    EXPECT_NEAR(MapAccuracy::compute(map, bare).median_m, 0.01, 1e-6);

    // 10 cm beyond the square's edge: the overshoot past the nearest sample's
    // patch (half-diagonal spacing / sqrt 2) counts, so the distance is
    // within spacing / sqrt 2 below the true 10 cm.
    const std::vector<TPoint3Df> outside{{-0.1F, 0.01F, 0.0F}};
    EXPECT_NEAR(
        MapAccuracy::compute(outside, squares(false)).median_m, 0.11 - SPACING / std::sqrt(2.0),
        1e-6);
}

TEST(MapAccuracy, percentilesAreNearestRank)
{
    EXPECT_DOUBLE_EQ(MapAccuracy::percentile({4, 1, 3, 2}, 50), 2);
    EXPECT_DOUBLE_EQ(MapAccuracy::percentile({4, 1, 3, 2}, 90), 4);
    EXPECT_DOUBLE_EQ(MapAccuracy::percentile({7}, 90), 7);
    EXPECT_TRUE(std::isnan(MapAccuracy::percentile({}, 50)));
}

TEST(MapAccuracy, refusesEmptyOrMismatchedInputs)
{
    const std::vector<TPoint3Df> map{{0, 0, 0}};
    EXPECT_THROW(MapAccuracy::compute({}, squares(false)), std::invalid_argument);
    EXPECT_THROW(MapAccuracy::compute(map, ReferenceSurface()), std::invalid_argument);
    ReferenceSurface r = squares(false);
    r.normals.pop_back();
    EXPECT_THROW(MapAccuracy::compute(map, r), std::invalid_argument);
    r = squares(false);
    r.seen_range.pop_back();
    EXPECT_THROW(MapAccuracy::compute(map, r), std::invalid_argument);
}
