// SPDX-License-Identifier: BSD-3-Clause
// Global rectification closes the simulated double loop of the paper's
// Fig. 17 (3DOF robot in a hall) from drifting odometry.
#include "PaperRectifierOptions.h"
#include "SimulatedDrive.h"

#include <emslam/rectify/SerialRectification.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <iostream>

using namespace emslam;
using namespace emslam::rectify;

namespace
{
double median(std::vector<double> v)
{
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}
}  // namespace

TEST(LoopClosure, hallDoubleLoopGapShrinksFiveFold)
{
    test::DriveOptions drive;
    const auto t_render = std::chrono::steady_clock::now();
    const auto frames = test::driveWorld("config/sim/hall_double_loop.ini", drive);
    ASSERT_GT(frames.size(), 300u);
    std::cout << "render "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_render).count()
              << " s\n";

    const auto ego = test::composeActions(frames);
    const double ego_gap = test::loopGap(ego);
    const double ego_ate = test::positionRmse(ego, frames);
    const double true_gap =
        (frames.back().T_world_true.translation() - frames.front().T_world_true.translation())
            .norm();

    CEntropyVoxelMap::TCreationOptions map;
    map.cell_size = 0.15;
    map.energy = maps::EnergyType::PlanarLowStructured;
    map.dof = 3;
    TRectifierOptions opt = emslam::test::paperRectifierOptions();  // the paper's defaults
    // Floor and ceiling carry no alignment information in the XZ plane and
    // reward shrinking the map onto itself: keep the walls (camera 1 m high).
    opt.vertical_band = true;
    SerialRectification slam(opt, map);
    for (const auto& f : frames)
    {
        slam.addFrame(f.action_drifted, f.cloud, f.timestamp, f.frame_index);
    }
    slam.finish();

    const auto stats = slam.statistics();
    std::vector<mrpt::poses::CPose3D> rect;
    for (const auto& p : slam.framePoses())
    {
        rect.push_back(p.T_world_frame);
    }
    ASSERT_EQ(rect.size(), frames.size());
    const double slam_gap = test::loopGap(rect);
    const double slam_ate = test::positionRmse(rect, frames);
    double seconds = 0;
    std::size_t attempts = 0;
    std::vector<double> per_call;
    for (const auto& s : stats)
    {
        per_call.push_back(s.seconds);
        seconds += s.seconds;
        attempts += s.attempts;
        EXPECT_LE(s.energy_after, s.energy_before + 1e-9);
    }
    std::cout << "frames " << frames.size() << " elements " << slam.trajectory().size()
              << " true gap " << true_gap << " | egomotion gap " << ego_gap << " ATE " << ego_ate
              << " | SLAM gap " << slam_gap << " ATE " << slam_ate << " | rectifications "
              << stats.size() << " attempts " << attempts << " time " << seconds
              << " s, median per rectification " << median(per_call) << " s\n";
    EXPECT_LT(true_gap, 0.02);
    EXPECT_GT(ego_gap, 1.0);
    EXPECT_LT(slam_gap, ego_gap / 5);
    EXPECT_LT(slam_ate, ego_ate);
}
