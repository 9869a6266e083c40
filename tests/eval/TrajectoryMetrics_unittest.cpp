// SPDX-License-Identifier: BSD-3-Clause
#include "TestHelpers.h"

#include <emslam/eval/TrajectoryMetrics.h>

#include <mrpt/random/RandomGenerators.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using emslam::eval::Alignment;
using emslam::eval::TrajectoryMetrics;
using emslam::io::TumTrajectory;
using mrpt::poses::CPose3D;

namespace
{
constexpr double T0 = 1317340800.0;  // a KITTI-like UNIX time: stamps keep their 1e-7 s digits

/** A 3D helix with turning and pitching orientation, 10 Hz. */
TumTrajectory helix(std::size_t n)
{
    TumTrajectory t;
    for (std::size_t i = 0; i < n; ++i)
    {
        const double a = 0.1 * static_cast<double>(i);
        t.add(
            T0 + a, CPose3D(
                        5 * std::cos(a), 5 * std::sin(a), 0.2 * a, a + M_PI / 2, 0.05 * std::sin(a),
                        0.02 * a));
    }
    return t;
}

/** A straight line along x, one pose per metre, 10 Hz. */
TumTrajectory line(std::size_t n, double stretch = 1.0, double yaw_per_pose = 0.0)
{
    TumTrajectory t;
    for (std::size_t i = 0; i < n; ++i)
    {
        const double k = static_cast<double>(i);
        t.add(T0 + 0.1 * k, CPose3D(stretch * k, 0, 0, yaw_per_pose * k, 0, 0));
    }
    return t;
}

TrajectoryMetrics evaluate(const TumTrajectory& gt, const TumTrajectory& est, Alignment a)
{
    TrajectoryMetrics::Options o;
    o.alignment = a;
    return TrajectoryMetrics::compute(gt, est, o);
}
}  // namespace

TEST(TrajectoryMetrics, parseAlignmentAcceptsTheThreeNamesOnly)
{
    EXPECT_EQ(emslam::eval::parseAlignment("se3"), Alignment::SE3);
    EXPECT_EQ(emslam::eval::parseAlignment("SIM3"), Alignment::Sim3);
    EXPECT_EQ(emslam::eval::parseAlignment("none"), Alignment::None);
    emslam::test::expectThrowContaining(
        [] { emslam::eval::parseAlignment("se2"); }, {"'se2'", "se3", "sim3", "none"});
}

// est = T ⊕ gt: the rigid alignment recovers inv(T) exactly, every error is 0.
TEST(TrajectoryMetrics, rigidTransformGivesZeroSe3Ate)
{
    const TumTrajectory gt = helix(80);
    const CPose3D T(1.0, -2.0, 0.5, 0.3, 0.1, -0.2);
    TumTrajectory est;
    for (const auto& p : gt.poses)
    {
        est.add(p.t, T + p.pose);
    }
    const auto m = evaluate(gt, est, Alignment::SE3);
    EXPECT_EQ(m.matched_poses, 80u);
    EXPECT_LT(m.ate_rmse_m, 1e-9);
    EXPECT_DOUBLE_EQ(m.align.scale, 1.0);
    const CPose3D should_be_identity = m.align.T_gt_est + T;
    EXPECT_LT(should_be_identity.norm(), 1e-9);
    EXPECT_LT(std::abs(should_be_identity.yaw()) + std::abs(should_be_identity.pitch()), 1e-9);
    EXPECT_LT(m.rel.t_rel_percent, 1e-9);
    EXPECT_LT(m.rel.r_rel_deg_per_m, 1e-9);
    EXPECT_LT(m.end_error_m, 1e-9);
    // Without alignment the ATE is large.
    EXPECT_GT(evaluate(gt, est, Alignment::None).ate_rmse_m, 1.0);
}

// A pure offset of (0, 3, 4) m: ATE 5 m unaligned, 0 aligned.
TEST(TrajectoryMetrics, unalignedAteOfAConstantOffset)
{
    const TumTrajectory gt = helix(30);
    TumTrajectory est;
    for (const auto& p : gt.poses)
    {
        est.add(p.t, CPose3D(0, 3, 4, 0, 0, 0) + p.pose);
    }
    EXPECT_NEAR(evaluate(gt, est, Alignment::None).ate_rmse_m, 5.0, 1e-12);
    EXPECT_LT(evaluate(gt, est, Alignment::SE3).ate_rmse_m, 1e-9);
}

// est positions are half the true ones (and rigidly moved): sim3 finds scale 2.
TEST(TrajectoryMetrics, sim3RecoversScaleSe3DoesNot)
{
    const TumTrajectory gt = helix(60);
    const CPose3D T(-3.0, 1.0, 2.0, -0.4, 0.2, 0.1);
    TumTrajectory est;
    for (const auto& p : gt.poses)
    {
        CPose3D e = T + p.pose;
        e.x(0.5 * e.x());
        e.y(0.5 * e.y());
        e.z(0.5 * e.z());
        est.add(p.t, e);
    }
    const auto sim = evaluate(gt, est, Alignment::Sim3);
    EXPECT_NEAR(sim.align.scale, 2.0, 1e-9);
    EXPECT_LT(sim.ate_rmse_m, 1e-9);
    EXPECT_LT(sim.rel.t_rel_percent, 1e-7);
    EXPECT_NEAR(sim.path_length_m, sim.est_path_length_m, 1e-9);

    const auto se3 = evaluate(gt, est, Alignment::SE3);
    EXPECT_DOUBLE_EQ(se3.align.scale, 1.0);
    EXPECT_GT(se3.ate_rmse_m, 1.0);
    // Half-length steps: 50 % translational drift.
    EXPECT_GT(se3.rel.t_rel_percent, 40.0);
}

// Estimate stretched by 2 % along a 160 m line: the devkit lengths apply and only
// 100 m fits, from poses 0, 10, ..., 50 (6 segments); each ends at the first pose
// beyond 100 m (101 m away), so each error is 0.02 * 101 m / 100 m = 2.02 %.
TEST(TrajectoryMetrics, constantScaleDriftLongPath)
{
    const auto m = evaluate(line(161), line(161, 1.02), Alignment::None);
    EXPECT_DOUBLE_EQ(m.path_length_m, 160.0);
    ASSERT_EQ(m.rel.lengths_m.size(), 8u);
    EXPECT_EQ(m.rel.lengths_m.front(), 100.0);
    EXPECT_EQ(m.rel.segments, 6u);
    EXPECT_NEAR(m.rel.t_rel_percent, 2.02, 1e-9);
    EXPECT_NEAR(m.rel.r_rel_deg_per_m, 0.0, 1e-12);
    EXPECT_NEAR(m.end_error_m, 0.02 * 160, 1e-9);
    // Relative errors ignore a rigid alignment.
    EXPECT_NEAR(evaluate(line(161), line(161, 1.02), Alignment::SE3).rel.t_rel_percent, 2.02, 1e-9);
}

// 40 m line: lengths 4, 8, 12, 16, 20 m (10-50 %). Segments (start every 10
// poses, end 1 m beyond L): L=4: 4 of them, error 5/4 of 2 %; L=8: 4, 9/8;
// L=12: 3, 13/12; L=16: 3, 17/16; L=20: 2, 21/20. Mean ratio 18.0375 / 16.
TEST(TrajectoryMetrics, constantScaleDriftShortPath)
{
    const auto m = evaluate(line(41), line(41, 1.02), Alignment::None);
    ASSERT_EQ(m.rel.lengths_m.size(), 5u);
    EXPECT_DOUBLE_EQ(m.rel.lengths_m[0], 4.0);
    EXPECT_DOUBLE_EQ(m.rel.lengths_m[4], 20.0);
    EXPECT_EQ(m.rel.segments, 16u);
    EXPECT_NEAR(m.rel.t_rel_percent, 2.0 * 18.0375 / 16.0, 1e-9);
}

// A heading drift of 1 mrad per pose (per metre): the 100 m segments end 101
// poses later, 0.101 rad of error over 100 m.
TEST(TrajectoryMetrics, constantHeadingDriftGivesRRel)
{
    const double w = 1e-3;
    const auto m = evaluate(line(161), line(161, 1.0, w), Alignment::None);
    EXPECT_EQ(m.rel.segments, 6u);
    EXPECT_NEAR(m.rel.r_rel_deg_per_m, w * 101.0 / 100.0 * 180.0 / M_PI, 1e-9);
}

// A 10 m square driven once; the estimate drifts linearly to (0.3, 0.4) m at the end.
TEST(TrajectoryMetrics, loopGapAndPathLength)
{
    TumTrajectory gt, est;
    const double corners[5][2] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}};
    for (std::size_t i = 0; i <= 40; ++i)
    {
        const std::size_t side = std::min<std::size_t>(i / 10, 3);
        const double f = static_cast<double>(i - 10 * side) / 10.0;
        const double x = corners[side][0] + f * (corners[side + 1][0] - corners[side][0]);
        const double y = corners[side][1] + f * (corners[side + 1][1] - corners[side][1]);
        const double k = static_cast<double>(i) / 40.0;
        gt.add(T0 + 0.1 * static_cast<double>(i), CPose3D(x, y, 0, 0, 0, 0));
        est.add(T0 + 0.1 * static_cast<double>(i), CPose3D(x + 0.3 * k, y + 0.4 * k, 0, 0, 0, 0));
    }
    for (const auto a : {Alignment::None, Alignment::SE3})
    {
        const auto m = evaluate(gt, est, a);
        EXPECT_NEAR(m.loop_gap_m, 0.5, 1e-12);
        EXPECT_NEAR(m.path_length_m, 40.0, 1e-12);
        EXPECT_NEAR(m.end_error_m, 0.5, 1e-9);
    }
    // The ground truth closes the loop.
    EXPECT_NEAR(evaluate(gt, gt, Alignment::None).loop_gap_m, 0.0, 1e-12);
}

// Jittered stamps (±9 ms), estimate poses with no ground truth nearby (50 ms off)
// and a near-duplicate: exactly the right 100 pairs, one to one.
TEST(TrajectoryMetrics, associationWithJitteredTimestamps)
{
    const TumTrajectory gt = helix(100);
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(1234);
    TumTrajectory est;
    for (std::size_t i = 0; i < gt.size(); ++i)
    {
        const auto& p = gt.poses[i];
        est.add(p.t + rng.drawUniform(-0.009, 0.009), p.pose);
        if (i % 10 == 3)
        {
            est.add(p.t + 0.05, CPose3D(100, 100, 100, 0, 0, 0));
        }
    }
    // A worse candidate for ground-truth pose 7, 15 ms away: the closer one wins.
    est.add(gt.poses[7].t + 0.015, CPose3D(-100, 0, 0, 0, 0, 0));
    const auto a = emslam::eval::associateByTimestamp(gt, est, 0.02);
    ASSERT_EQ(a.size(), 100u);
    for (std::size_t i = 0; i < a.size(); ++i)
    {
        EXPECT_EQ(a.t_gt[i], gt.poses[i].t);
        EXPECT_LE(std::abs(a.t_est[i] - a.t_gt[i]), 0.009 + 1e-6);
    }
    TrajectoryMetrics::Options o;
    const auto m = TrajectoryMetrics::compute(gt, est, o);
    EXPECT_EQ(m.matched_poses, 100u);
    EXPECT_EQ(m.est_poses, 111u);
    EXPECT_LT(m.ate_rmse_m, 1e-9);
    // A tighter tolerance drops the pairs beyond it.
    EXPECT_LT(emslam::eval::associateByTimestamp(gt, est, 0.001).size(), 20u);
}

TEST(TrajectoryMetrics, badInputThrows)
{
    const TumTrajectory gt = helix(10);
    TrajectoryMetrics::Options o;
    emslam::test::expectThrowContaining(
        [&] { TrajectoryMetrics::compute(gt, TumTrajectory(), o); }, {"estimate", "no poses"});
    emslam::test::expectThrowContaining(
        [&] { TrajectoryMetrics::compute(TumTrajectory(), gt, o); }, {"ground-truth", "no poses"});
    TumTrajectory late;
    for (const auto& p : gt.poses)
    {
        late.add(p.t + 10.0, p.pose);
    }
    emslam::test::expectThrowContaining(
        [&] { TrajectoryMetrics::compute(gt, late, o); }, {"no timestamp", "max_dt"});
}

// One matched pose: no path, no segment; the drift is NaN and null in JSON.
TEST(TrajectoryMetrics, singlePoseHasNoDrift)
{
    TumTrajectory one;
    one.add(T0, CPose3D(1, 2, 3, 0, 0, 0));
    const auto m = evaluate(one, one, Alignment::Sim3);
    EXPECT_EQ(m.matched_poses, 1u);
    EXPECT_EQ(m.rel.segments, 0u);
    EXPECT_TRUE(std::isnan(m.rel.t_rel_percent));
    EXPECT_DOUBLE_EQ(m.align.scale, 1.0);
    EXPECT_LT(m.ate_rmse_m, 1e-12);
    EXPECT_NE(m.toJson().find("\"t_rel_percent\": null"), std::string::npos) << m.toJson();
}

TEST(TrajectoryMetrics, jsonHasEveryKey)
{
    const auto json = evaluate(line(41), line(41, 1.02), Alignment::SE3).toJson();
    for (const char* key :
         {"ate_rmse_m", "t_rel_percent", "r_rel_deg_per_m", "end_error_m", "loop_gap_m",
          "path_length_m", "matched_poses", "alignment"})
    {
        EXPECT_NE(json.find(std::string("\"") + key + "\": "), std::string::npos) << key;
    }
    EXPECT_NE(json.find("\"matched_poses\": 41,"), std::string::npos) << json;
    EXPECT_NE(json.find("\"path_length_m\": 40,"), std::string::npos) << json;
}

TEST(TrajectoryMetrics, closedLoopNeedsTheEndNearTheStart)
{
    using emslam::eval::isClosedLoop;
    // A 40 m square back at its start, and ending 0.8 m short (within 1 m).
    TumTrajectory square, almost, open;
    for (int i = 0; i <= 40; ++i)
    {
        const double s = i % 40, u = std::fmod(s, 10.0);
        const int side = static_cast<int>(s / 10.0);
        const double x[] = {u, 10.0, 10.0 - u, 0.0}, z[] = {0.0, u, 10.0, 10.0 - u};
        square.add(i, CPose3D(x[side], 0, z[side], 0, 0, 0));
    }
    EXPECT_TRUE(isClosedLoop(square));
    almost = square;
    almost.poses.back().pose = CPose3D(0, 0, 0.8, 0, 0, 0);
    EXPECT_TRUE(isClosedLoop(almost));
    almost.poses.back().pose = CPose3D(0, 0, 1.5, 0, 0, 0);  // 1.5 m > max(0.4 m, 1 m)
    EXPECT_FALSE(isClosedLoop(almost));
    // A straight 60 m drive (the KITTI 06 excerpt's shape) is no loop.
    EXPECT_FALSE(isClosedLoop(line(61)));
    // 1 % of a 400 m path: 3.5 m from the start still closes it.
    TumTrajectory big;
    for (int i = 0; i <= 400; ++i)
    {
        const double a = 2 * M_PI * i / 400.0 * (1.0 - 3.5 / 400.0);
        big.add(i, CPose3D(63.66 * std::sin(a), 0, 63.66 * (1 - std::cos(a)), 0, 0, 0));
    }
    EXPECT_TRUE(isClosedLoop(big));
    EXPECT_FALSE(isClosedLoop(TumTrajectory{}));
    TumTrajectory still;  // shorter than LOOP_MIN_PATH_M
    still.add(0, CPose3D());
    still.add(1, CPose3D(0.2, 0, 0, 0, 0, 0));
    still.add(2, CPose3D());
    EXPECT_FALSE(isClosedLoop(still));
}

// A straight path leaves the rotation about it free for the positions: mm of
// noise set it. The map's alignment takes the cameras' orientations too, so a
// point 2 m beside a camera lands beside the true camera, also with Sim3.
TEST(TrajectoryMetrics, mapAlignmentFixesTheTurnAboutAStraightPath)
{
    const TumTrajectory gt = line(30);
    const CPose3D T(1.0, -2.0, 0.5, 0.3, 0.1, 0.5);  // a turn of 0.5 rad about x among others
    for (const double scale : {1.0, 0.5})
    {
        TumTrajectory est;
        for (std::size_t i = 0; i < gt.poses.size(); ++i)
        {
            CPose3D e = T + gt.poses[i].pose;
            const double k = static_cast<double>(i);
            e.x(scale * e.x() + 0.002 * std::sin(1.7 * k));
            e.y(scale * e.y() + 0.002 * std::cos(2.3 * k));
            e.z(scale * e.z() + 0.002 * std::sin(3.1 * k));
            est.add(gt.poses[i].t, e);
        }
        const auto m = evaluate(gt, est, scale == 1.0 ? Alignment::SE3 : Alignment::Sim3);
        EXPECT_NEAR(m.map_align.scale, 1.0 / scale, 0.01);
        double worst_map = 0, worst_positions = 0;
        for (std::size_t i = 0; i < gt.poses.size(); i += 7)
        {
            const mrpt::math::TPoint3D beside(0, 2.0, 0);
            const auto truth = gt.poses[i].pose.composePoint(beside);
            const auto& e = est.poses[i].pose;
            // The estimate's point, at its scale, in its frame.
            std::vector<mrpt::math::TPoint3Df> p{
                mrpt::math::TPoint3Df(e.composePoint(mrpt::math::TPoint3D(0, 2.0 * scale, 0)))};
            std::vector<mrpt::math::TPoint3Df> q = p;
            m.map_align.applyToPoints(p);
            m.align.applyToPoints(q);
            worst_map = std::max(worst_map, (mrpt::math::TPoint3D(p[0]) - truth).norm());
            worst_positions =
                std::max(worst_positions, (mrpt::math::TPoint3D(q[0]) - truth).norm());
        }
        EXPECT_LT(worst_map, 0.02) << "scale " << scale;
        EXPECT_GT(worst_positions, 0.1) << "scale " << scale;
    }
}
