// SPDX-License-Identifier: BSD-3-Clause
// AnyTime mode: rectification in a second thread (also run under
// ThreadSanitizer, see tests/tsan).
#include "PaperRectifierOptions.h"
#include "SimulatedDrive.h"

#include <emslam/rectify/AnyTimeRectification.h>
#include <emslam/rectify/RectificationRunner.h>
#include <emslam/rectify/SerialRectification.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

using namespace emslam;
using namespace emslam::rectify;

namespace
{
struct Result
{
    double gap{0};
    double ate{0};
    std::size_t attempts{0};
    std::size_t records{0};
};

Result runMode(RectificationMode mode, const std::vector<test::DrivenFrame>& frames)
{
    CEntropyVoxelMap::TCreationOptions map;
    map.energy = maps::EnergyType::PlanarLowStructured;
    map.dof = 3;
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.mode = mode;
    opt.vertical_band = true;
    auto runner = createRectificationRunner(opt, map);
    // AnyTime: a reader polls the public state while frames arrive, as a
    // GUI would (the serial runner is single-threaded).
    std::atomic<bool> reading{mode == RectificationMode::AnyTime};
    std::thread reader(
        [&]
        {
            while (reading)
            {
                (void)runner->mapStable();
                (void)runner->statistics();
                (void)runner->progress();
                (void)runner->framePoses();
                std::this_thread::yield();
            }
        });
    for (const auto& f : frames)
    {
        runner->addFrame(f.action_drifted, f.cloud, f.timestamp, f.frame_index);
        if (mode == RectificationMode::AnyTime)
        {
            // Stands for the stereo + egomotion time of a frame, during
            // which the rectification thread works.
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }
    runner->finish();
    reading = false;
    reader.join();
    EXPECT_THROW(
        runner->addFrame(frames[0].action_drifted, frames[0].cloud, 0, 0), std::logic_error);

    Result r;
    std::vector<mrpt::poses::CPose3D> poses;
    for (const auto& p : runner->framePoses())
        poses.push_back(p.T_world_frame);
    EXPECT_EQ(poses.size(), frames.size());
    r.gap = test::loopGap(poses);
    r.ate = test::positionRmse(poses, frames);
    for (const auto& s : runner->statistics())
    {
        r.attempts += s.attempts;
        EXPECT_LE(s.energy_after, s.energy_before + 1e-9);
    }
    r.records = runner->statistics().size();
    const auto progress = runner->progress();
    EXPECT_EQ(progress.rectifications, r.records);
    EXPECT_EQ(progress.energy, runner->statistics().back().energy_after);
    EXPECT_TRUE(runner->mapStable());
    return r;
}
}  // namespace

TEST(AnyTimeRectification, reachesResultsComparableToSerial)
{
    test::DriveOptions o;
    o.max_frames = 560;  // the first loop of the hall
    const auto frames = test::driveWorld("config/sim/hall_double_loop.ini", o);
    const double ego_ate = test::positionRmse(test::composeActions(frames), frames);

    const Result serial = runMode(RectificationMode::Serial, frames);
    const Result anytime = runMode(RectificationMode::AnyTime, frames);
    std::cout << "egomotion ATE " << ego_ate << " | serial ATE " << serial.ate << " gap "
              << serial.gap << " attempts " << serial.attempts << " | anytime ATE " << anytime.ate
              << " gap " << anytime.gap << " attempts " << anytime.attempts << " records "
              << anytime.records << "\n";
    EXPECT_LT(serial.ate, ego_ate);
    EXPECT_LT(anytime.ate, ego_ate);
    // Comparable: the AnyTime result is within 50 % (+5 cm) of the serial one.
    EXPECT_LT(anytime.ate, 1.5 * serial.ate + 0.05);
    EXPECT_GT(anytime.records, 2u);
}

TEST(AnyTimeRectification, destructorStopsTheThreadWithoutFinish)
{
    CEntropyVoxelMap::TCreationOptions map;
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.buffer_size = 2;
    {
        AnyTimeRectification a(opt, map);
        maps::WeightedPointCloud c;
        for (int i = 0; i < 200; ++i)
            c.push_back({0.01f * i, 0.f, 2.f}, 1.f);
        for (int i = 0; i < 6; ++i)
        {
            a.addFrame(mrpt::poses::CPose3D(0.1, 0, 0, 0, 0, 0), c, i, i);
        }
        EXPECT_EQ(a.synchronisations(), 3u);
        EXPECT_THROW(a.trajectory(), std::logic_error);
    }
    SUCCEED();
}

TEST(AnyTimeRectification, coarseLevelsAreWalkedDownToTheFineGrid)
{
    test::DriveOptions o;
    o.max_frames = 120;
    const auto frames = test::driveWorld("config/sim/hall_double_loop.ini", o);
    CEntropyVoxelMap::TCreationOptions map;
    map.energy = maps::EnergyType::PlanarLowStructured;
    map.dof = 3;
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.mode = RectificationMode::AnyTime;
    opt.vertical_band = true;
    opt.coarse_levels = 1;
    AnyTimeRectification a(opt, map);
    for (const auto& f : frames)
    {
        a.addFrame(f.action_drifted, f.cloud, f.timestamp, f.frame_index);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    a.finish();
    EXPECT_EQ(a.trajectory().resolutionLevel(), 0);
    EXPECT_DOUBLE_EQ(a.trajectory().map().creationOptions().cell_size, map.cell_size);
    std::size_t coarse = 0;
    for (const auto& s : a.statistics())
    {
        coarse += s.coarse_attempts;
        EXPECT_LE(s.coarse_attempts, s.attempts);
    }
    EXPECT_GT(coarse, 0u);
    // The final (serial) rectification ends on l_d, at the energy it reports.
    EXPECT_NEAR(a.trajectory().energy(), a.statistics().back().energy_after, 1e-9);
}
