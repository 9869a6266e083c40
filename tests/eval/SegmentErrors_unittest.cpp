// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/eval/SegmentErrors.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

using emslam::eval::segmentErrors;
using emslam::eval::segmentLengthsFor;
using mrpt::poses::CPose3D;

namespace
{
/** n poses along x, `stretch` metres apart, each turned `yaw_per_pose` more. */
std::vector<CPose3D> straight(std::size_t n, double stretch, double yaw_per_pose)
{
    std::vector<CPose3D> p{CPose3D()};
    for (std::size_t i = 1; i < n; ++i)
    {
        p.push_back(p.back() + CPose3D(stretch, 0, 0, yaw_per_pose, 0, 0));
    }
    return p;
}

void expectLengths(double path, const std::vector<double>& expected)
{
    const auto l = segmentLengthsFor(path);
    ASSERT_EQ(l.size(), expected.size()) << path;
    for (std::size_t i = 0; i < l.size(); ++i)
    {
        EXPECT_DOUBLE_EQ(l[i], expected[i]) << "path " << path << " m, length " << i;
    }
}
}  // namespace

TEST(SegmentErrors, lengthsFollowThePathAndReachKittiAtTwoKilometres)
{
    expectLengths(2000, {100, 200, 300, 400, 500, 600, 700, 800});
    expectLengths(9000, {100, 200, 300, 400, 500, 600, 700, 800});
    expectLengths(104, {5, 10, 15, 20, 25, 30, 35, 40});
    expectLengths(60, {2, 4, 6, 8, 10, 12, 14, 16});
    expectLengths(1500, {50, 100, 150, 200, 250, 300, 350, 400});
    expectLengths(
        3, {0.1, 0.2, 0.30000000000000004, 0.4, 0.5, 0.6000000000000001, 0.7000000000000001, 0.8});
    EXPECT_TRUE(segmentLengthsFor(0).empty());
    EXPECT_TRUE(segmentLengthsFor(std::nan("")).empty());
}

// 1 % too long steps: over a segment ending L + 1 m along the path (the first
// pose strictly beyond L) the estimate is 0.01 (L + 1) m too far.
TEST(SegmentErrors, scaleDriftGivesItsPercentPerLength)
{
    const auto gt = straight(201, 1.0, 0.0), est = straight(201, 1.01, 0.0);
    const auto e = segmentErrors(gt, est, {10, 20, 500}, 10);
    ASSERT_EQ(e.size(), 3u);
    EXPECT_EQ(e[0].segments, 19u);  // starts 0, 10, ..., 180: the end 189 fits in 200
    EXPECT_EQ(e[1].segments, 18u);
    EXPECT_NEAR(e[0].t_err_percent, 100.0 * 0.01 * 11.0 / 10.0, 1e-9);
    EXPECT_NEAR(e[1].t_err_percent, 100.0 * 0.01 * 21.0 / 20.0, 1e-9);
    EXPECT_NEAR(e[0].r_err_deg_per_m, 0.0, 1e-9);
    EXPECT_DOUBLE_EQ(e[2].length_m, 500.0);
    EXPECT_EQ(e[2].segments, 0u);  // longer than the path
    EXPECT_TRUE(std::isnan(e[2].t_err_percent));
    EXPECT_TRUE(std::isnan(e[2].r_err_deg_per_m));
}

// 1 mrad of heading error per pose: L + 1 mrad over a segment of length L.
TEST(SegmentErrors, headingDriftGivesItsDegreesPerMetre)
{
    auto gt = straight(101, 1.0, 0.0), est = straight(101, 1.0, 1e-3);
    const auto e = segmentErrors(gt, est, {10}, 5);
    ASSERT_EQ(e.size(), 1u);
    EXPECT_EQ(e[0].segments, 18u);  // starts 0, 5, ..., 85
    EXPECT_NEAR(e[0].r_err_deg_per_m, 11e-3 / 10.0 * 180.0 / M_PI, 1e-9);
}

TEST(SegmentErrors, differentSizesThrow)
{
    EXPECT_THROW(
        segmentErrors(straight(10, 1, 0), straight(9, 1, 0), {1.0}), std::invalid_argument);
}
