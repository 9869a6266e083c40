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

// The first frames of a run, straight ahead: the camera's own bias and the
// world up are one direction to the data. The bias is neither solved nor
// reported (it used to run off: "camera bias 5756.70 deg"), and levelling
// still takes the odometry's tilt out.
TEST(LevelFloors, aStraightShortRunDoesNotObserveTheBias)
{
    constexpr std::size_t N = 20;
    PoseGraph g;
    g.addNode(CPose3D());
    const auto step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(0.5));
    for (std::size_t k = 1; k < N; ++k)
    {
        CPose3D step(0, 0, 0.3, 0, 0, 0);
        if (k >= 5 && k <= 7)
        {
            step = step + CPose3D(0, 0, 0, 0, 0, mrpt::DEG2RAD(1.0));
        }
        g.addNode(g.node(k - 1) + step);
        g.addEdge(k - 1, k, step, step_cov);
    }
    const double sigma = mrpt::DEG2RAD(0.3);
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0.0, sigma);
    std::vector<std::optional<VerticalMeasurement>> verticals(N);
    std::vector<double> tilt_variance(N);
    for (std::size_t k = 0; k < N; ++k)
    {
        verticals[k] = measured(tilted(mrpt::DEG2RAD(0.5) + noise(rng), noise(rng)), sigma);
        tilt_variance[k] = static_cast<double>(k) * std::pow(mrpt::DEG2RAD(0.5), 2);
    }
    ASSERT_GT(maxTiltDeg(g.nodes()), 2.9);
    const auto stats = levelFloors(g, verticals, tilt_variance);
    EXPECT_EQ(stats.used, N);
    EXPECT_FALSE(stats.bias_observable);
    EXPECT_TRUE(std::isnan(stats.bias_deg));
    const auto& b = g.directionFrame().bias;
    EXPECT_EQ(b.x, 0.0);
    EXPECT_EQ(b.y, 0.0);
    EXPECT_EQ(b.z, 0.0);
    // Levelled to the up the camera sees (the bias stays in the poses).
    EXPECT_LT(maxTiltDeg(g.nodes()), 1.5);
}

// Turning makes the bias observable, and it is solved, but never beyond its
// bound: a camera whose floors look 5 degrees tilted gets at most 3.
TEST(LevelFloors, theSolvedBiasStaysWithinItsBound)
{
    const auto truth = emslam::test::squareLoop(40);
    PoseGraph g;
    g.addNode(CPose3D());
    const auto step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(0.5));
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        const CPose3D step = truth[k] - truth[k - 1];
        g.addNode(g.node(k - 1) + step);
        g.addEdge(k - 1, k, step, step_cov);
    }
    const double sigma = mrpt::DEG2RAD(0.3);
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, sigma);
    std::vector<std::optional<VerticalMeasurement>> verticals(truth.size());
    for (std::size_t k = 0; k < truth.size(); ++k)
    {
        verticals[k] = measured(tilted(mrpt::DEG2RAD(5.0) + noise(rng), noise(rng)), sigma);
    }
    const auto stats = levelFloors(
        g, verticals, std::vector<double>(truth.size(), std::pow(mrpt::DEG2RAD(3.0), 2)), 3,
        emslam::slam::DEFAULT_MAX_CAMERA_BIAS);
    EXPECT_TRUE(stats.bias_observable);
    EXPECT_LE(stats.bias_deg, 3.0 + 1e-9);
    EXPECT_GT(stats.bias_deg, 2.0);
}

// The staircase walk again, but the graph grows a node at a time and is
// levelled online: every 5 nodes relevelFloors() gates the ups seen so far
// and a local solve moves only the nodes added since the last one. It must
// level the walk as the batch levelFloors() does, leave the ramps out, and
// find the same bias, with no solve of the whole graph.
TEST(LevelFloors, relevellingAGrowingGraphLevelsItAsTheBatchDoes)
{
    const auto truth = emslam::test::squareLoop(40);
    const auto step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(0.5));
    std::vector<CPose3D> steps{CPose3D()};
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        CPose3D step = truth[k] - truth[k - 1];
        if (k >= 11 && k <= 13)
        {
            step = step + CPose3D(0, 0, 0, 0, 0, mrpt::DEG2RAD(1.0));
        }
        steps.push_back(step);
    }
    const double sigma = mrpt::DEG2RAD(0.3);
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, sigma);
    std::vector<std::optional<VerticalMeasurement>> verticals(truth.size());
    for (std::size_t k = 0; k < truth.size(); ++k)
    {
        const double ramp = (k == 5 || k == 25) ? mrpt::DEG2RAD(10.0) : 0.0;
        verticals[k] = measured(tilted(mrpt::DEG2RAD(0.5) + ramp + noise(rng), noise(rng)), sigma);
    }
    verticals[30].reset();
    const double step_tilt_var = std::pow(mrpt::DEG2RAD(0.5), 2);

    // Batch, as the first test.
    PoseGraph batch;
    batch.addNode(CPose3D());
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        batch.addNode(batch.node(k - 1) + steps[k]);
        batch.addEdge(k - 1, k, steps[k], step_cov);
    }
    const double rmse_before = positionRmse(batch.nodes(), truth);
    std::vector<double> tilt_variance(truth.size());
    for (std::size_t k = 0; k < truth.size(); ++k)
    {
        tilt_variance[k] = static_cast<double>(k) * step_tilt_var;
    }
    const auto batch_stats = levelFloors(batch, verticals, tilt_variance);

    // Online.
    PoseGraph online;
    online.addNode(CPose3D());
    std::size_t solved_upto = 1, gated_upto = 0;
    PoseGraph::DirectionFrame levelled_for;
    int whole_graph_solves = 0, relevels = 0;
    emslam::slam::LevelFloorsStats stats;
    const auto levelAndSolve = [&]
    {
        const std::size_t n = online.nodeCount();
        // The nodes not yet solved may be tilted by their chain since then.
        std::vector<std::optional<VerticalMeasurement>> seen(
            verticals.begin(), verticals.begin() + static_cast<long>(n));
        std::vector<double> pose_var(n, 0.0);
        for (std::size_t k = solved_upto; k < n; ++k)
        {
            pose_var[k] = static_cast<double>(k - solved_upto + 1) * step_tilt_var;
        }
        stats = emslam::slam::relevelFloors(online, seen, pose_var, levelled_for, gated_upto);
        gated_upto = n;
        const std::size_t first_free = std::min(solved_upto, stats.first_changed);
        if (first_free <= 1)
        {
            ++whole_graph_solves;
            levelled_for = online.directionFrame();
        }
        online.optimize(8, first_free, 1e-9);
        solved_upto = n;
    };
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        online.addNode(online.node(k - 1) + steps[k]);
        online.addEdge(k - 1, k, steps[k], step_cov);
        if ((k + 1) % 5 == 0 || k + 1 == truth.size())
        {
            levelAndSolve();
            ++relevels;
        }
    }
    const double tilt_online = maxTiltDeg(online.nodes());
    const double rmse_online = positionRmse(online.nodes(), truth);
    std::printf(
        "staircase online: max tilt %.2f deg (batch %.2f), position RMSE %.3f m (batch %.3f, "
        "before %.3f), bias %.2f deg (batch %.2f), %zu of %zu used (batch %zu), %d whole-graph "
        "solves\n",
        tilt_online, maxTiltDeg(batch.nodes()), rmse_online, positionRmse(batch.nodes(), truth),
        rmse_before, stats.bias_deg, batch_stats.bias_deg, stats.used, stats.measured,
        batch_stats.used, whole_graph_solves);
    // The first, and when the bias is first seen and while it settles:
    // the other relevellings move only the nodes added since.
    EXPECT_LT(whole_graph_solves, relevels);
    EXPECT_EQ(stats.measured, batch_stats.measured);
    EXPECT_EQ(stats.used, batch_stats.used);
    std::set<std::size_t> in_graph;
    for (const auto& p : online.directionPriors())
    {
        in_graph.insert(p.node);
    }
    EXPECT_EQ(in_graph.count(5), 0u);
    EXPECT_EQ(in_graph.count(25), 0u);
    EXPECT_TRUE(stats.bias_observable);
    EXPECT_NEAR(stats.bias_deg, batch_stats.bias_deg, 0.2);
    EXPECT_LT(tilt_online, 1.0);
    EXPECT_LT(rmse_online, 0.25 * rmse_before);
    EXPECT_LT(rmse_online, 1.5 * positionRmse(batch.nodes(), truth));
}
