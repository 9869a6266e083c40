// SPDX-License-Identifier: BSD-3-Clause
#include "PaperRectifierOptions.h"

#include <emslam/rectify/AnyTimeRectification.h>
#include <emslam/rectify/Revisit.h>
#include <emslam/rectify/TrajectoryRectifier.h>

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

using namespace emslam;
using namespace emslam::rectify;
using mrpt::poses::CPose3D;

namespace
{
/** A corridor of random points (about 500 per m³), x in [-3, 33], |y| <=
 * 0.5, |z| <= 1. */
const std::vector<mrpt::math::TPoint3Df>& corridor()
{
    static const auto points = []
    {
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> x(-3.f, 33.f), y(-0.5f, 0.5f), z(-1.f, 1.f);
        std::vector<mrpt::math::TPoint3Df> p(36000);
        for (auto& q : p)
        {
            q = {x(rng), y(rng), z(rng)};
        }
        return p;
    }();
    return points;
}

/** What a camera at (x, 0, 0) sees: the corridor within 2 m, in its frame. */
maps::WeightedPointCloud seenFrom(double x)
{
    maps::WeightedPointCloud c;
    for (const auto& p : corridor())
    {
        const double dx = p.x - x;
        if (dx * dx + double(p.y) * p.y + double(p.z) * p.z <= 4.0)
        {
            c.push_back({static_cast<float>(dx), p.y, p.z}, 1.f);
        }
    }
    return c;
}

/** Elements 1 m apart at the positions `xs` along the corridor. */
Trajectory walk(
    const std::vector<double>& xs, maps::EnergyType energy = maps::EnergyType::Unstructured)
{
    CEntropyVoxelMap::TCreationOptions o;
    o.energy = energy;
    o.dof = 6;
    Trajectory t(o);
    for (std::size_t i = 0; i < xs.size(); ++i)
    {
        t.append(CPose3D(i == 0 ? xs[0] : xs[i] - xs[i - 1], 0, 0), seenFrom(xs[i]), double(i), i);
    }
    return t;
}

std::vector<double> range(double from, double to)
{
    std::vector<double> xs;
    for (double x = from; from <= to ? x <= to : x >= to; x += from <= to ? 1.0 : -1.0)
    {
        xs.push_back(x);
    }
    return xs;
}

/** `search` checking, with four shifted grids, the moves beyond a cell
 * (the 6DOF configs), every success, and every success before a revisit. */
std::array<TRectifierOptions, 3> checkVariants(TRectifierOptions search)
{
    search.confirm_phases = 4;
    TRectifierOptions every = search;
    every.confirm_min_move = 0;
    TRectifierOptions gated = search;
    gated.confirm_all_before_revisit = true;
    return {search, every, gated};
}

/** walk() with a drift on every third action. */
Trajectory driftedWalk(
    const std::vector<double>& xs, maps::EnergyType energy = maps::EnergyType::Unstructured)
{
    Trajectory t = walk(xs, energy);
    for (std::size_t i = 1; i < t.size(); i += 3)
    {
        t.changeActions({{i, t.action(i) + CPose3D(0.03, 0.02, 0, 0.01, 0, 0)}});
        t.commitChange();
    }
    return t;
}

std::pair<RectificationStats, Trajectory> rectifiedWalk(
    const std::vector<double>& xs,
    const TRectifierOptions& opt,
    maps::EnergyType energy = maps::EnergyType::Unstructured)
{
    Trajectory t = driftedWalk(xs, energy);
    const RectificationStats s = TrajectoryRectifier(opt).rectify(t);
    return {s, t};
}

std::vector<double> outAndBack()
{
    std::vector<double> xs = range(0, 15);
    const std::vector<double> back = range(14, 0);
    xs.insert(xs.end(), back.begin(), back.end());
    return xs;
}
}  // namespace

TEST(Revisit, anOpenWalkNeverRevisitsItsNeighboursCells)
{
    // Neighbours 1-4 m apart share cells; their path is never longer than
    // the 2 + 2 m their views reach.
    EXPECT_FALSE(revisitsAPlace(walk(range(0, 29))));
    EXPECT_FALSE(revisitsAPlace(walk(range(0, 15))));
}

TEST(Revisit, comingBackDownTheCorridorIsARevisit)
{
    Trajectory t = walk(outAndBack());
    EXPECT_TRUE(revisitsAPlace(t));
    t.compress();  // elements 2 m apart, the path is the same
    EXPECT_TRUE(revisitsAPlace(t));
}

TEST(Revisit, confirmAllBeforeRevisitChecksEverySuccessOnlyOnAnOpenWalk)
{
    TRectifierOptions search = emslam::test::paperRectifierOptions();
    search.eps_xyz = 0.05;
    search.eps_rot_deg = 0.3;
    search.select_fraction = 0.1;
    search.max_attempts = 150;
    const auto [long_moves, every, gated] = checkVariants(search);
    const auto run = [](const std::vector<double>& xs, const TRectifierOptions& opt,
                        maps::EnergyType energy = maps::EnergyType::Unstructured)
    {
        const auto [s, t] = rectifiedWalk(xs, opt, energy);
        return std::make_pair(s, t.actions());
    };
    // Open: the gate checks every success, as confirm_min_move = 0 does.
    const auto open_every = run(range(0, 20), every);
    const auto open_gated = run(range(0, 20), gated);
    const auto open_long = run(range(0, 20), long_moves);
    EXPECT_GT(open_every.first.unconfirmed, 0u);
    EXPECT_EQ(open_gated.first.attempts, open_every.first.attempts);
    EXPECT_EQ(open_gated.first.unconfirmed, open_every.first.unconfirmed);
    EXPECT_EQ(open_gated.second, open_every.second);
    EXPECT_LT(open_long.first.unconfirmed, open_every.first.unconfirmed);
    // Revisited: only the long moves, as without the gate.
    const auto back_long = run(outAndBack(), long_moves);
    const auto back_gated = run(outAndBack(), gated);
    const auto back_every = run(outAndBack(), every);
    EXPECT_GT(back_every.first.unconfirmed, back_gated.first.unconfirmed);
    EXPECT_EQ(back_gated.first.attempts, back_long.first.attempts);
    EXPECT_EQ(back_gated.first.unconfirmed, back_long.first.unconfirmed);
    EXPECT_EQ(back_gated.second, back_long.second);
    // An energy that anchors a_0 sees what the egomotion did not: never held
    // back. Moves within a cell, so that only a check of every success acts.
    TRectifierOptions within_a_cell = search;
    within_a_cell.eps_xyz = 0.01;
    within_a_cell.eps_rot_deg = 0.02;
    const auto [small, small_every, small_gated] = checkVariants(within_a_cell);
    const auto structured = maps::EnergyType::Structured;
    const auto manhattan_long = run(range(0, 20), small, structured);
    const auto manhattan_gated = run(range(0, 20), small_gated, structured);
    EXPECT_EQ(manhattan_long.first.unconfirmed, 0u);
    EXPECT_GT(run(range(0, 20), small_every, structured).first.unconfirmed, 0u);
    EXPECT_EQ(manhattan_gated.first.attempts, manhattan_long.first.attempts);
    EXPECT_EQ(manhattan_gated.first.unconfirmed, 0u);
    EXPECT_EQ(manhattan_gated.second, manhattan_long.second);
}

TEST(Revisit, holdBeforeRevisitLeavesAnOpenWalkAloneAndIsInertAfterARevisit)
{
    TRectifierOptions free = emslam::test::paperRectifierOptions();
    free.eps_xyz = 0.05;
    free.eps_rot_deg = 0.3;
    free.max_attempts = 150;
    TRectifierOptions hold = free;
    hold.hold_before_revisit = true;
    // Open walk: the drift stays, no attempt is made, the run is "stable".
    const auto [open_free, open_free_t] = rectifiedWalk(range(0, 20), free);
    const auto [open_held, open_held_t] = rectifiedWalk(range(0, 20), hold);
    ASSERT_GT(open_free.successes, 0u);  // without the hold the energy moves it
    EXPECT_TRUE(open_held.held_before_revisit);
    EXPECT_EQ(open_held.attempts, 0u);
    EXPECT_TRUE(open_held.converged);
    EXPECT_EQ(open_held.energy_after, open_held.energy_before);
    EXPECT_EQ(open_held_t.actions(), driftedWalk(range(0, 20)).actions());
    // Out and back: a revisit, so the hold changes nothing.
    const auto [back_free, back_free_t] = rectifiedWalk(outAndBack(), free);
    const auto [back_held, back_held_t] = rectifiedWalk(outAndBack(), hold);
    EXPECT_FALSE(back_held.held_before_revisit);
    EXPECT_GT(back_held.attempts, 0u);
    EXPECT_EQ(back_held.attempts, back_free.attempts);
    EXPECT_EQ(back_held_t.actions(), back_free_t.actions());
    // An energy that anchors a_0 is never held.
    const auto structured = maps::EnergyType::Structured;
    const auto [m_free, m_free_t] = rectifiedWalk(range(0, 20), free, structured);
    const auto [m_held, m_held_t] = rectifiedWalk(range(0, 20), hold, structured);
    EXPECT_FALSE(m_held.held_before_revisit);
    EXPECT_GT(m_held.attempts, 0u);
    EXPECT_EQ(m_held.attempts, m_free.attempts);
    EXPECT_EQ(m_held_t.actions(), m_free_t.actions());
}

// AnyTime, where the river bed's open walk ended a few mm worse: every
// synchronisation before a revisit is held, and the walk stays as fed.
TEST(Revisit, anyTimeHoldsEverySynchronisationOfAnOpenWalk)
{
    TRectifierOptions hold = emslam::test::paperRectifierOptions();
    hold.mode = RectificationMode::AnyTime;
    hold.eps_xyz = 0.05;
    hold.eps_rot_deg = 0.3;
    hold.buffer_size = 5;
    hold.hold_before_revisit = true;
    CEntropyVoxelMap::TCreationOptions o;
    o.energy = maps::EnergyType::Unstructured;
    o.dof = 6;
    const Trajectory fed = driftedWalk(range(0, 20));
    AnyTimeRectification anytime(hold, o);
    for (std::size_t i = 0; i < fed.size(); ++i)
    {
        anytime.addFrame(fed.action(i), fed.map().observationCloud(i), double(i), i);
    }
    anytime.finish();
    const auto stats = anytime.statistics();
    ASSERT_FALSE(stats.empty());
    for (const RectificationStats& s : stats)
    {
        EXPECT_TRUE(s.held_before_revisit);
        EXPECT_EQ(s.attempts, 0u);
    }
    ASSERT_EQ(anytime.trajectory().size(), fed.size());
    for (std::size_t i = 0; i < fed.size(); ++i)
    {
        EXPECT_EQ(anytime.trajectory().action(i), fed.action(i)) << i;
    }
}
