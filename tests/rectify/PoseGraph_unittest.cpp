// SPDX-License-Identifier: BSD-3-Clause
// A drifting square loop, closed by one exact edge between its ends.
#include "PoseLoops.h"

#include <emslam/rectify/ActionCovariance.h>
#include <emslam/rectify/PoseGraph.h>

#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

using emslam::rectify::ActionCovariance;
using emslam::rectify::diagonalCovariance;
using emslam::rectify::PoseGraph;
using emslam::test::distance;
using emslam::test::positionRmse;
using mrpt::poses::CPose3D;

TEST(PoseGraph, exactEdgesGiveZeroCostAtTheTruth)
{
    const auto truth = emslam::test::squareLoop(40);
    PoseGraph g;
    for (const auto& p : truth)
    {
        g.addNode(p);
    }
    const ActionCovariance c = diagonalCovariance(0.02, mrpt::DEG2RAD(0.5));
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        g.addEdge(k - 1, k, truth[k] - truth[k - 1], c);
    }
    g.addEdge(0, 40, CPose3D(), c);
    EXPECT_NEAR(g.cost(), 0.0, 1e-12);
    const auto r = g.optimize();
    EXPECT_NEAR(r.final_cost, 0.0, 1e-12);
    for (std::size_t k = 0; k < truth.size(); ++k)
    {
        EXPECT_LT(distance(g.node(k), truth[k]), 1e-9) << k;
    }
}

TEST(PoseGraph, aPerturbedThreeDimensionalGraphReturnsToTheTruthInAFewIterations)
{
    // A helix turning about every axis, its exact edges and a loop edge;
    // every node but the first moved by up to 0.3 m and 6 deg: Newton steps
    // with the right derivatives come back in a few iterations.
    std::vector<CPose3D> truth;
    for (int k = 0; k < 30; ++k)
    {
        const double a = 0.25 * k;
        truth.emplace_back(
            3 * std::cos(a), 0.2 * k, 3 * std::sin(a), a, 0.3 * std::sin(a), 0.2 * std::cos(2 * a));
    }
    PoseGraph g;
    for (std::size_t k = 0; k < truth.size(); ++k)
    {
        const double s = k == 0 ? 0.0 : 1.0;
        const double u = std::sin(7.0 * static_cast<double>(k));
        g.addNode(
            truth[k] + CPose3D(
                           0.3 * s * u, -0.2 * s * u, 0.1 * s, mrpt::DEG2RAD(6 * s * u),
                           mrpt::DEG2RAD(-4 * s), mrpt::DEG2RAD(5 * s * u)));
    }
    const ActionCovariance c = diagonalCovariance(0.02, mrpt::DEG2RAD(0.5));
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        g.addEdge(k - 1, k, truth[k] - truth[k - 1], c);
    }
    g.addEdge(0, 29, truth[29] - truth[0], c);
    g.addEdge(5, 20, truth[20] - truth[5], c);
    const auto r = g.optimize(8);
    std::printf(
        "helix: cost %.1f -> %.2e in %d iterations\n", r.initial_cost, r.final_cost, r.iterations);
    EXPECT_LT(r.final_cost, 1e-8);
    for (std::size_t k = 0; k < truth.size(); ++k)
    {
        EXPECT_LT(distance(g.node(k), truth[k]), 1e-5) << k;
    }
}

TEST(PoseGraph, oneLoopEdgeSpreadsTheDriftOverTheLoop)
{
    const auto truth = emslam::test::squareLoop(40);
    // The odometry turns 0.3 degrees too far at every step: 12 degrees at the
    // end, 2-3 m of gap.
    std::vector<CPose3D> steps, drifted{CPose3D()};
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        steps.push_back((truth[k] - truth[k - 1]) + CPose3D(0, 0, 0, 0, mrpt::DEG2RAD(0.3), 0));
        drifted.push_back(drifted.back() + steps.back());
    }
    PoseGraph g;
    for (const auto& p : drifted)
    {
        g.addNode(p);
    }
    const ActionCovariance step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(0.5));
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        g.addEdge(k - 1, k, steps[k - 1], step_cov);
    }
    const double gap_before = distance(drifted[40], drifted[0]);
    const double rmse_before = positionRmse(drifted, truth);
    ASSERT_GT(gap_before, 1.0);
    // The revisit, registered to a centimetre and a tenth of a degree.
    g.addEdge(0, 40, CPose3D(), diagonalCovariance(0.01, mrpt::DEG2RAD(0.1)));
    const double cost_before = g.cost();
    const auto r = g.optimize();
    EXPECT_LT(r.final_cost, 0.01 * cost_before);
    EXPECT_GE(r.iterations, 1);
    const double gap_after = distance(g.node(40), g.node(0));
    const double rmse_after = positionRmse(g.nodes(), truth);
    std::printf(
        "square loop: gap %.3f -> %.3f m, position RMSE %.3f -> %.3f m, cost %.1f -> %.3f\n",
        gap_before, gap_after, rmse_before, rmse_after, cost_before, r.final_cost);
    EXPECT_LT(gap_after, 0.05);
    EXPECT_LT(rmse_after, 0.25 * rmse_before);
    // Node 0 is the world: it does not move.
    EXPECT_LT(distance(g.node(0), CPose3D()), 1e-12);
}

/** The square loop whose odometry turns 0.3 degrees too far at every step,
 * closed by one registration: a solve of several iterations. */
PoseGraph driftingSquareLoop()
{
    const auto truth = emslam::test::squareLoop(40);
    PoseGraph g;
    g.addNode(CPose3D());
    const ActionCovariance step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(0.5));
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        const CPose3D step = (truth[k] - truth[k - 1]) + CPose3D(0, 0, 0, 0, mrpt::DEG2RAD(0.3), 0);
        g.addNode(g.node(k - 1) + step);
        g.addEdge(k - 1, k, step, step_cov);
    }
    g.addEdge(0, 40, CPose3D(), diagonalCovariance(0.01, mrpt::DEG2RAD(0.1)));
    return g;
}

TEST(PoseGraph, aSolveStopsWhenTheStepLeftIsWithinTheNoise)
{
    PoseGraph full = driftingSquareLoop();
    PoseGraph enough = full;
    const auto r_full = full.optimize(30, 1, 1e-12);
    // Stop once the step left would lower ½χ² by less than 0.125: it moves
    // nothing by more than half its standard deviation.
    const auto r_enough = enough.optimize(30, 1, 1e-12, 0.125);
    std::printf(
        "square loop: %d iterations to cost %.6f; %d to %.6f\n", r_full.iterations,
        r_full.final_cost, r_enough.iterations, r_enough.final_cost);
    EXPECT_LT(r_enough.iterations, r_full.iterations);
    EXPECT_FALSE(r_enough.stopped);
    EXPECT_GE(r_enough.final_cost, r_full.final_cost);
    EXPECT_LT(r_enough.final_cost - r_full.final_cost, 0.125);
    for (std::size_t k = 0; k < full.nodeCount(); ++k)
    {
        // Half a standard deviation of one 2 cm step at most.
        EXPECT_LT(distance(enough.node(k), full.node(k)), 0.01) << k;
    }
}

TEST(PoseGraph, aStopRequestEndsTheSolveAfterTheIterationUnderWay)
{
    PoseGraph g = driftingSquareLoop();
    int asked = 0;
    const auto r = g.optimize(
        30, 1, 1e-12, 0,
        [&]
        {
            ++asked;
            return true;
        });
    EXPECT_TRUE(r.stopped);
    EXPECT_EQ(r.iterations, 1);
    EXPECT_EQ(asked, 1);
    EXPECT_LT(r.final_cost, 0.1 * r.initial_cost);
    EXPECT_NEAR(r.final_cost, g.cost(), 1e-9 * r.initial_cost);
}

TEST(PoseGraph, badEdgesThrow)
{
    PoseGraph g;
    g.addNode(CPose3D());
    g.addNode(CPose3D(1, 0, 0, 0, 0, 0));
    const ActionCovariance c = diagonalCovariance(0.02, 0.01);
    EXPECT_THROW(g.addEdge(0, 2, CPose3D(), c), std::out_of_range);
    EXPECT_THROW(g.addEdge(1, 1, CPose3D(), c), std::invalid_argument);
    EXPECT_NO_THROW(g.addEdge(0, 1, CPose3D(1, 0, 0, 0, 0, 0), c));
    // Nothing to move: a graph of one edge at its measurement stays.
    const auto r = g.optimize();
    EXPECT_NEAR(r.final_cost, 0.0, 1e-15);
}

TEST(PoseGraph, directionPriorsLevelAChainThatTilts)
{
    // A square loop on a level floor whose odometry tilts the camera down
    // by 0.2 degrees at every step (about the camera's x): 8 degrees at the
    // end, the path dives. Each camera saw the floor: up is -y.
    const auto truth = emslam::test::squareLoop(40);
    std::vector<CPose3D> drifted{CPose3D()};
    PoseGraph g;
    g.addNode(CPose3D());
    const ActionCovariance step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(0.5));
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        const CPose3D step = (truth[k] - truth[k - 1]) + CPose3D(0, 0, 0, 0, 0, mrpt::DEG2RAD(0.2));
        drifted.push_back(drifted.back() + step);
        g.addNode(drifted.back());
        g.addEdge(k - 1, k, step, step_cov);
    }
    const mrpt::math::TVector3D up(0, -1, 0);
    mrpt::math::CMatrixDouble33 info;
    info.setZero();
    const double w = 1.0 / std::pow(mrpt::DEG2RAD(0.5), 2);
    info(0, 0) = w;  // the measured direction is free along itself (y)
    info(2, 2) = w;
    for (std::size_t k = 0; k < truth.size(); ++k)
    {
        g.addDirectionPrior(k, up, info);
    }
    EXPECT_THROW(g.addDirectionPrior(41, up, info), std::out_of_range);
    const auto tilt_deg = [](const CPose3D& p)
    {
        const auto& R = p.getRotationMatrix();
        // The camera's -y in the world against the world's -y.
        return mrpt::RAD2DEG(std::acos(std::min(1.0, R(1, 1))));
    };
    double tilt_before = 0;
    for (const auto& p : g.nodes())
    {
        tilt_before = std::max(tilt_before, tilt_deg(p));
    }
    const double rmse_before = positionRmse(g.nodes(), truth);
    ASSERT_GT(tilt_before, 2.5);
    ASSERT_GT(g.priorCost(g.directionPriors()[20]), 10.0);
    g.optimize();
    double tilt_after = 0;
    for (const auto& p : g.nodes())
    {
        tilt_after = std::max(tilt_after, tilt_deg(p));
    }
    const double rmse_after = positionRmse(g.nodes(), truth);
    std::printf(
        "tilting square: max tilt %.2f -> %.3f deg, position RMSE %.3f -> %.3f m\n", tilt_before,
        tilt_after, rmse_before, rmse_after);
    // The steps' tilts are measured 0.2 degrees off with 0.5 degrees of
    // uncertainty each: the priors win, each step keeps a fraction.
    EXPECT_LT(tilt_after, 0.2);
    EXPECT_LT(rmse_after, 0.1 * rmse_before);
    g.clearDirectionPriors();
    EXPECT_TRUE(g.directionPriors().empty());
}

// Direction priors in a local solve: the held nodes stay, the free ones
// are levelled by their priors; with every node held, only the shared
// world direction moves (what the online levelling does between solves).
TEST(PoseGraph, directionPriorsCountInALocalSolveAndWithEveryNodeHeld)
{
    const auto truth = emslam::test::squareLoop(40);
    PoseGraph g;
    g.addNode(CPose3D());
    const ActionCovariance step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(0.5));
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        // Level until node 20, then 0.3 degrees of dive per step.
        CPose3D step = truth[k] - truth[k - 1];
        if (k > 20)
        {
            step = step + CPose3D(0, 0, 0, 0, 0, mrpt::DEG2RAD(0.3));
        }
        g.addNode(g.node(k - 1) + step);
        g.addEdge(k - 1, k, step, step_cov);
    }
    mrpt::math::CMatrixDouble33 info;
    info.setZero();
    info(0, 0) = info(2, 2) = 1.0 / std::pow(mrpt::DEG2RAD(0.5), 2);
    for (std::size_t k = 0; k < truth.size(); ++k)
    {
        g.addDirectionPrior(k, mrpt::math::TVector3D(0, -1, 0), info);
    }
    const auto tiltDeg = [](const CPose3D& p)
    { return mrpt::RAD2DEG(std::acos(std::min(1.0, p.getRotationMatrix()(1, 1)))); };
    ASSERT_GT(tiltDeg(g.node(truth.size() - 1)), 3.0);

    // With every node held, only the world direction moves: it starts
    // 2 degrees off and ends where the priors of the level half put it
    // (the diving half pulls it a little).
    PoseGraph::DirectionFrame frame;
    frame.world = {std::sin(mrpt::DEG2RAD(2.0)), -std::cos(mrpt::DEG2RAD(2.0)), 0};
    frame.solve_world = true;
    g.setDirectionFrame(frame);
    const std::vector<CPose3D> before = g.nodes();
    g.optimize(10, g.nodeCount());
    for (std::size_t k = 0; k < before.size(); ++k)
    {
        EXPECT_EQ(g.node(k).asVectorVal(), before[k].asVectorVal()) << k;
    }
    // Equal, isotropic priors: the world direction is their mean in the
    // world, at the held poses.
    double mx = 0, my = 0, mz = 0;
    for (const auto& p : before)
    {
        const auto& R = p.getRotationMatrix();
        mx -= R(0, 1);
        my -= R(1, 1);
        mz -= R(2, 1);
    }
    const double mn = std::sqrt(mx * mx + my * my + mz * mz);
    const auto& w = g.directionFrame().world;
    const double off_mean = std::acos(std::min(1.0, (w.x * mx + w.y * my + w.z * mz) / mn));
    EXPECT_LT(mrpt::RAD2DEG(off_mean), 0.05);

    // A local solve from node 21: nodes 0-20 stay, the dive is undone by
    // the priors of the free nodes (and the held nodes' priors still pull
    // on the world direction, which stays level).
    g.optimize(30, 21);
    for (std::size_t k = 0; k <= 20; ++k)
    {
        EXPECT_EQ(g.node(k).asVectorVal(), before[k].asVectorVal()) << k;
    }
    double tilt_after = 0;
    for (std::size_t k = 21; k < truth.size(); ++k)
    {
        tilt_after = std::max(tilt_after, tiltDeg(g.node(k)));
    }
    EXPECT_LT(tilt_after, 0.5);
    const double w_tilt = std::acos(std::min(1.0, -g.directionFrame().world.y));
    std::printf(
        "local levelling: max tilt of the free nodes %.3f deg, world direction %.3f deg off\n",
        tilt_after, mrpt::RAD2DEG(w_tilt));
    EXPECT_LT(mrpt::RAD2DEG(w_tilt), 0.2);
}
