// SPDX-License-Identifier: BSD-3-Clause
// A square walk on a level floor whose odometry tilts at a "staircase", seen
// by a camera that sees every floor 0.5 degrees tilted, with two ramps.
#include "PoseLoops.h"

#include <emslam/rectify/ActionCovariance.h>
#include <emslam/slam/LevelFloors.h>

#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>
#include <set>
#include <vector>

using emslam::rectify::diagonalCovariance;
using emslam::rectify::PoseGraph;
using emslam::slam::levelFloors;
using emslam::stereo::VerticalMeasurement;
using emslam::test::positionRmse;
using mrpt::poses::CPose3D;

namespace
{
/** Degrees between a camera's up (-y) and the world's. */
double tiltDeg(const CPose3D& p)
{
    const auto& R = p.getRotationMatrix();
    return mrpt::RAD2DEG(std::acos(std::min(1.0, R(1, 1))));
}

double maxTiltDeg(const std::vector<CPose3D>& poses)
{
    double m = 0;
    for (const auto& p : poses)
    {
        m = std::max(m, tiltDeg(p));
    }
    return m;
}

/** `up` measured with an isotropic `sigma` [rad] across it. */
VerticalMeasurement measured(const mrpt::math::TVector3D& up, double sigma)
{
    VerticalMeasurement m;
    m.up = up;
    const double n[3] = {up.x, up.y, up.z};
    for (int a = 0; a < 3; ++a)
    {
        for (int b = 0; b < 3; ++b)
        {
            m.covariance(a, b) = sigma * sigma * ((a == b ? 1.0 : 0.0) - n[a] * n[b]);
        }
    }
    m.patches = 50;
    return m;
}

/** (0, -1, 0) turned about the camera's x by `tilt` and about z by `roll` [rad]. */
mrpt::math::TVector3D tilted(double tilt, double roll)
{
    const double y = -std::cos(tilt) * std::cos(roll);
    return {std::sin(roll), y, -std::sin(tilt) * std::cos(roll)};
}
}  // namespace

TEST(LevelFloors, aStaircaseTiltIsUndoneTheCameraBiasFoundAndRampsLeftOut)
{
    const auto truth = emslam::test::squareLoop(40);
    // The odometry tilts the camera by 1 degree at each of steps 11-13 (a
    // staircase) and is right elsewhere; no loop closes.
    PoseGraph g;
    g.addNode(CPose3D());
    const auto step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(0.5));
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        CPose3D step = truth[k] - truth[k - 1];
        if (k >= 11 && k <= 13)
        {
            step = step + CPose3D(0, 0, 0, 0, 0, mrpt::DEG2RAD(1.0));
        }
        g.addNode(g.node(k - 1) + step);
        g.addEdge(k - 1, k, step, step_cov);
    }
    // Every camera sees its floor tilted by 0.5 degrees forward (its own
    // bias), with 0.3 degrees of noise; at nodes 5 and 25 it sees a ramp.
    const double sigma = mrpt::DEG2RAD(0.3);
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, sigma);
    std::vector<std::optional<VerticalMeasurement>> verticals(truth.size());
    for (std::size_t k = 0; k < truth.size(); ++k)
    {
        const double ramp = (k == 5 || k == 25) ? mrpt::DEG2RAD(10.0) : 0.0;
        verticals[k] = measured(tilted(mrpt::DEG2RAD(0.5) + ramp + noise(rng), noise(rng)), sigma);
    }
    verticals[30].reset();  // saw no floor
    const double tilt_before = maxTiltDeg(g.nodes());
    const double rmse_before = positionRmse(g.nodes(), truth);
    ASSERT_GT(tilt_before, 2.9);

    // The chain's tilt uncertainty: 0.5 degrees per step.
    std::vector<double> tilt_variance(truth.size());
    for (std::size_t k = 0; k < truth.size(); ++k)
    {
        tilt_variance[k] = static_cast<double>(k) * std::pow(mrpt::DEG2RAD(0.5), 2);
    }
    const auto stats = levelFloors(g, verticals, tilt_variance);

    const double tilt_after = maxTiltDeg(g.nodes());
    const double rmse_after = positionRmse(g.nodes(), truth);
    std::printf(
        "staircase: max tilt %.2f -> %.2f deg, position RMSE %.3f -> %.3f m, bias %.2f deg, "
        "%zu of %zu used\n",
        tilt_before, tilt_after, rmse_before, rmse_after, stats.bias_deg, stats.used,
        stats.measured);
    EXPECT_EQ(stats.measured, 40u);
    EXPECT_EQ(stats.used, 38u);
    std::set<std::size_t> in_graph;
    for (const auto& p : g.directionPriors())
    {
        in_graph.insert(p.node);
    }
    EXPECT_EQ(in_graph.count(5), 0u);
    EXPECT_EQ(in_graph.count(25), 0u);
    EXPECT_EQ(in_graph.count(30), 0u);
    // Each node keeps some of its own 0.3 degrees of noise (its steps are
    // known to 0.5 degrees only), and the bias trades a little with the
    // world up through node 0, which is held.
    EXPECT_NEAR(stats.bias_deg, 0.5, 0.2);
    EXPECT_LT(tilt_after, 1.0);
    EXPECT_LT(rmse_after, 0.25 * rmse_before);
}

TEST(LevelFloors, fewerThanTwoMeasurementsChangeNothing)
{
    const auto truth = emslam::test::squareLoop(10);
    PoseGraph g;
    for (const auto& p : truth)
    {
        g.addNode(p + CPose3D(0, 0, 0, 0, 0, mrpt::DEG2RAD(2.0)));
    }
    std::vector<std::optional<VerticalMeasurement>> verticals(truth.size());
    verticals[3] = measured({0, -1, 0}, 0.01);
    const auto before = g.nodes();
    const auto stats = levelFloors(g, verticals, std::vector<double>(truth.size(), 1.0));
    EXPECT_EQ(stats.measured, 1u);
    EXPECT_EQ(stats.used, 0u);
    EXPECT_TRUE(g.directionPriors().empty());
    for (std::size_t k = 0; k < before.size(); ++k)
    {
        EXPECT_EQ(g.node(k).asString(), before[k].asString());
    }
}
