// SPDX-License-Identifier: BSD-3-Clause
// Trajectory compression (§2.2.4, Eq. 13-14).
#include "PaperRectifierOptions.h"

#include <emslam/rectify/SerialRectification.h>
#include <emslam/rectify/Trajectory.h>

#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace emslam;
using namespace emslam::rectify;
using mrpt::poses::CPose3D;

namespace
{
maps::WeightedPointCloud wall(std::uint64_t seed)
{
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(-3.f, 3.f);
    maps::WeightedPointCloud c;
    for (int i = 0; i < 600; ++i)
    {
        c.push_back({u(rng), u(rng) / 3, 4.f + u(rng) / 10}, 1.f);
    }
    return c;
}

CEntropyVoxelMap::TCreationOptions mapOptions()
{
    CEntropyVoxelMap::TCreationOptions o;
    o.cell_size = 0.15;
    o.energy = maps::EnergyType::Unstructured;
    o.dof = 6;
    return o;
}

}  // namespace

TEST(TrajectoryCompression, fusedMapIsTheUnionOfItsPartsUpToTheCellSize)
{
    Trajectory t(mapOptions());
    const CPose3D step(0.3, 0.0, 0.2, mrpt::DEG2RAD(4.0), 0, 0);
    for (int i = 0; i < 7; ++i)
    {
        t.append(i == 0 ? CPose3D() : step, wall(100 + i), 0.1 * i, i);
    }
    const auto frames_before = t.framePoses();
    const double weight_before = t.map().totalWeight();
    const double entropy_before = t.recomputeEnergy();
    // World positions and weights of every simplified point before.
    std::vector<std::pair<mrpt::math::TPoint3D, double>> before;
    for (std::size_t i = 0; i < t.size(); ++i)
    {
        const auto& c = t.map().observationCloud(i);
        for (std::size_t k = 0; k < c.size(); ++k)
        {
            before.emplace_back(
                t.pose(i).composePoint(mrpt::math::TPoint3D(c.points[k])), c.weights[k]);
        }
    }

    t.compress();
    ASSERT_EQ(t.size(), 4u);
    EXPECT_EQ(t.compressionCount(), 1u);
    // Every frame keeps its world pose; the weight is conserved.
    const auto frames_after = t.framePoses();
    ASSERT_EQ(frames_after.size(), frames_before.size());
    for (std::size_t i = 0; i < frames_after.size(); ++i)
    {
        EXPECT_LT(
            (frames_after[i].T_world_frame.translation() -
             frames_before[i].T_world_frame.translation())
                .norm(),
            1e-9);
        EXPECT_EQ(frames_after[i].frame_index, frames_before[i].frame_index);
    }
    EXPECT_NEAR(t.map().totalWeight(), weight_before, 1e-6);
    // Actions compose (Eq. 14): a'_1 = a_1 ⊕ a_2.
    EXPECT_LT((t.action(1).translation() - (step + step).translation()).norm(), 1e-12);

    // Every fused point stands for original points within l_d of it, and
    // every original point has a fused point within l_d.
    std::vector<mrpt::math::TPoint3D> after;
    for (std::size_t i = 0; i < t.size(); ++i)
    {
        const auto& c = t.map().observationCloud(i);
        for (const auto& p : c.points)
        {
            after.push_back(t.pose(i).composePoint(mrpt::math::TPoint3D(p)));
        }
    }
    const double l = t.map().creationOptions().cell_size;
    std::size_t far = 0;
    for (const auto& [p, w] : before)
    {
        double best = 1e9;
        for (const auto& q : after)
            best = std::min(best, (p - q).norm());
        far += best > l * std::sqrt(3.0) ? 1 : 0;
    }
    EXPECT_EQ(far, 0u);
    // Same map up to the resolution: re-simplification merges points that
    // share a cell, so the entropy changes by at most ~1 %.
    EXPECT_NEAR(t.recomputeEnergy(), entropy_before, 0.015 * entropy_before);
}

TEST(TrajectoryCompression, elementCountStaysWithinHalfAndFullNmax)
{
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.n_max = 10;
    opt.rectify_every = 1000;  // compression only
    SerialRectification slam(opt, mapOptions());
    const CPose3D step(0.2, 0.0, 0.1, 0.02, 0, 0);
    std::size_t max_seen = 0;
    for (int i = 0; i < 100; ++i)
    {
        slam.addFrame(i == 0 ? CPose3D() : step, wall(i), i, i);
        const std::size_t n = slam.trajectory().size();
        max_seen = std::max(max_seen, n);
        if (i >= opt.n_max)
        {
            EXPECT_GE(n, static_cast<std::size_t>(opt.n_max / 2)) << i;
            EXPECT_LE(n, static_cast<std::size_t>(opt.n_max)) << i;
        }
    }
    EXPECT_EQ(max_seen, 10u);
    EXPECT_EQ(slam.trajectory().frameCount(), 100u);
    // The frames still compose to the same path.
    CPose3D expected;
    for (int i = 1; i < 100; ++i)
        expected = expected + step;
    EXPECT_LT(
        (slam.framePoses().back().T_world_frame.translation() - expected.translation()).norm(),
        1e-9);
}
