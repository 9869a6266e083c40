// SPDX-License-Identifier: BSD-3-Clause
// EntropySlam on a loop of the simulator, whose every pose is exact: the
// rectified trajectory against the egomotion's, the keyframes, the
// compressions and the placing of the other frames; its parameters, and its
// life cycle (finish()).
#include "PoseLoops.h"
#include "SmallLoopWorld.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/slam/EntropySlam.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/io/vector_loadsave.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

using emslam::slam::EntropySlam;
using emslam::test::maxPoseDifference;
using emslam::test::rotationDeg;
using emslam::test::smallLoopFrames;
using emslam::test::TruthFrame;
using mrpt::poses::CPose3D;

namespace
{
constexpr double FPS = 4.0;               // 0.25 m per frame at 1 m/s
constexpr std::size_t LOOP_FRAMES = 110;  // the loop (86 frames) and 6 m of it again
constexpr int N_MAX = 20;                 // compressed several times on this loop
constexpr double T_MIN = 0.4;             // [m] every second frame along a wall
constexpr double THETA_MIN_DEG = 5.0;     // every frame in a corner

/** The shipped 3DOF robot configuration with a short trajectory and sparser
 * keyframes, with or without loop closing. */
EntropySlam::TParameters robotParameters(bool loop_closing)
{
    mrpt::config::CConfigFileMemory cfg(mrpt::io::file_get_contents(
        emslam::test::sourceDir() + "/config/mapper/3dof-low-structured.ini"));
    cfg.write("Rectifier", "n_max", N_MAX);
    cfg.write("SpaceSampler", "t_min", T_MIN);
    cfg.write("SpaceSampler", "theta_min_deg", THETA_MIN_DEG);
    cfg.write("LoopCloser", "enabled", loop_closing);
    EntropySlam::TParameters p;
    p.loadFromConfigFile(cfg);
    return p;
}

std::vector<CPose3D> posesOf(const std::vector<emslam::rectify::TimedPose>& timed)
{
    std::vector<CPose3D> poses;
    for (const auto& t : timed)
    {
        poses.push_back(t.T_world_frame);
    }
    return poses;
}

std::vector<CPose3D> truthOf(const std::vector<TruthFrame>& frames)
{
    std::vector<CPose3D> poses;
    for (const auto& f : frames)
    {
        poses.push_back(f.T_first_left);
    }
    return poses;
}

/** The frames space sampling keeps when fed the true motion, and the
 * smallest distance of a decision from its threshold (relative). */
std::vector<std::size_t> trueKeyframes(const std::vector<CPose3D>& truth, double& margin)
{
    std::vector<std::size_t> kept{0};
    margin = 1.0;
    for (std::size_t i = 1; i < truth.size(); ++i)
    {
        const CPose3D since = truth[i] - truth[kept.back()];
        const double t = since.translation().norm() / T_MIN;
        const double a = rotationDeg(since) / THETA_MIN_DEG;
        margin = std::min({margin, std::abs(t - 1), std::abs(a - 1)});
        if (t > 1 || a > 1)
        {
            kept.push_back(i);
        }
    }
    return kept;
}

struct LoopRun
{
    double ate_egomotion{0}, ate_slam{0};
};

/** Maps the loop and checks what holds with or without loop closing. */
LoopRun mapLoop(EntropySlam& slam)
{
    const std::vector<TruthFrame>& frames = smallLoopFrames(FPS, LOOP_FRAMES);
    const std::vector<CPose3D> truth = truthOf(frames);
    // Every keyframe's map cloud joins the map once, in order, whichever
    // process() (or finish()) finds it ready.
    std::vector<std::size_t> added;
    const auto collect = [&]
    {
        for (const auto& c : slam.addedClouds())
        {
            added.push_back(c.frame_index);
            EXPECT_FALSE(c.cloud.empty()) << "keyframe " << c.frame_index;
        }
    };
    for (const TruthFrame& f : frames)
    {
        EXPECT_TRUE(slam.process(*f.obs));
        collect();
    }
    slam.finish();
    collect();
    const auto ego = posesOf(slam.egomotionPoses());
    const auto est = posesOf(slam.slamPoses());
    const auto keyframe_poses = posesOf(slam.keyframePoses());
    LoopRun run;
    if (est.size() != frames.size() || ego.size() != frames.size())
    {
        ADD_FAILURE() << est.size() << " SLAM and " << ego.size() << " egomotion poses for "
                      << frames.size() << " frames";
        return run;
    }
    run.ate_egomotion = emslam::test::positionRmse(ego, truth);
    run.ate_slam = emslam::test::positionRmse(est, truth);
    std::printf(
        "%zu frames: %zu keyframes, %zu elements, %zu compressions, %zu rectifications, %zu loop "
        "edges; ATE egomotion %.4f m, SLAM %.4f m\n",
        frames.size(), slam.keyframes().size(), slam.trajectoryElements(), slam.compressions(),
        slam.rectifications().size(), slam.loopCloser().stats().loop_edges, run.ate_egomotion,
        run.ate_slam);
    EXPECT_EQ(slam.frameCount(), frames.size());
    EXPECT_EQ(slam.egomotionFailures(), 0U);
    EXPECT_TRUE(slam.unreliableReasons().empty());

    // The keyframes are the frames the true motion selects (far from the
    // thresholds, so the egomotion's millimetres do not matter).
    double margin = 0;
    const std::vector<std::size_t> expected = trueKeyframes(truth, margin);
    EXPECT_GT(margin, 0.1) << "a keyframe decision too close to call";
    EXPECT_EQ(slam.keyframes(), expected);
    EXPECT_EQ(added, expected);
    EXPECT_EQ(slam.acceptedCount(), expected.size());
    EXPECT_LT(expected.size(), frames.size());
    // Each keyframe sits at its rectified pose; every other frame at its
    // keyframe's plus the egomotion since.
    EXPECT_EQ(keyframe_poses.size(), expected.size());
    std::size_t k = 0;
    double worst = 0;
    for (std::size_t i = 0; i < frames.size() && k < keyframe_poses.size(); ++i)
    {
        if (k + 1 < expected.size() && expected[k + 1] == i)
        {
            ++k;
        }
        const CPose3D placed = keyframe_poses[k] + (ego[i] - ego[expected[k]]);
        worst = std::max(worst, maxPoseDifference(est[i], placed));
    }
    EXPECT_LT(worst, 1e-9);

    // Compressed: at most N_max elements, every frame still in one.
    EXPECT_LE(slam.trajectoryElements(), static_cast<std::size_t>(N_MAX));
    EXPECT_EQ(slam.trajectoryElements(), slam.trajectory().size());
    EXPECT_GE(slam.compressions(), 1U);
    // Entropy minimization: no rectification leaves a higher energy.
    EXPECT_FALSE(slam.rectifications().empty());
    for (const auto& r : slam.rectifications())
    {
        EXPECT_LE(r.energy_after, r.energy_before);
    }
    EXPECT_NEAR(slam.finalEntropy(), slam.entropyMap().energy(), 1e-9);
    EXPECT_GT(slam.mapCloud().size(), 1000U);
    return run;
}
}  // namespace

// Measured: ATE egomotion 0.049 m, SLAM 0.015 m (33 loop edges); 70
// keyframes of 110 frames, 20 elements after 5 compressions.
TEST(EntropySlam, aLoopClosedOnTheWayEndsFarCloserToTheTruth)
{
    EntropySlam slam(robotParameters(true));
    const LoopRun run = mapLoop(slam);
    EXPECT_GT(slam.loopCloser().stats().loop_edges, 0U);
    EXPECT_LT(run.ate_slam, 0.5 * run.ate_egomotion);
    EXPECT_LT(run.ate_slam, 0.03);
}

// Measured: ATE egomotion 0.049 m, SLAM 0.042 m.
TEST(EntropySlam, theRectifierAloneEndsNoWorseThanTheEgomotion)
{
    EntropySlam slam(robotParameters(false));
    const LoopRun run = mapLoop(slam);
    EXPECT_EQ(slam.loopCloser().stats().loop_edges, 0U);
    EXPECT_LE(run.ate_slam, run.ate_egomotion);
    EXPECT_GT(run.ate_egomotion, 0.02);  // drift to remove
}

TEST(EntropySlam, finishIsIdempotentAndEndsTheRun)
{
    const std::vector<TruthFrame>& frames = smallLoopFrames(FPS, 8);
    EntropySlam slam(robotParameters(true));
    EXPECT_THROW(slam.trajectory(), std::logic_error);
    EXPECT_THROW(slam.entropyMap(), std::logic_error);
    for (const TruthFrame& f : frames)
    {
        ASSERT_TRUE(slam.process(*f.obs));
    }
    EXPECT_EQ(slam.trajectoryElements(), 0U);  // not before finish()
    EXPECT_TRUE(slam.slamPoses().empty());
    slam.finish();
    const auto poses = posesOf(slam.slamPoses());
    const std::size_t rectifications = slam.rectifications().size();
    const double energy = slam.finalEnergy();
    ASSERT_EQ(poses.size(), frames.size());
    EXPECT_TRUE(slam.hasEnergy());
    EXPECT_GT(energy, 0.0);
    slam.finish();
    const auto again = posesOf(slam.slamPoses());
    ASSERT_EQ(again.size(), poses.size());
    for (std::size_t i = 0; i < poses.size(); ++i)
    {
        EXPECT_TRUE(again[i] == poses[i]) << "frame " << i;
    }
    EXPECT_EQ(slam.rectifications().size(), rectifications);
    EXPECT_EQ(slam.finalEnergy(), energy);
    EXPECT_THROW(slam.process(*frames[0].obs), std::logic_error);
    EXPECT_EQ(slam.frameCount(), frames.size());
}

TEST(EntropySlam, observationsItCannotUseChangeNothing)
{
    const std::vector<TruthFrame>& frames = smallLoopFrames(FPS, 4);
    EntropySlam slam(robotParameters(true));
    ASSERT_TRUE(slam.process(*frames[0].obs));
    ASSERT_TRUE(slam.process(*frames[1].obs));
    EXPECT_FALSE(slam.process(mrpt::obs::CObservationOdometry()));
    auto bad = std::make_shared<mrpt::obs::CObservationStereoImages>(*frames[2].obs);
    bad->imageRight = mrpt::img::CImage(10, 10, mrpt::img::CH_GRAY);
    EXPECT_THROW(slam.process(*bad), EntropySlam::UnusableObservation);
    EXPECT_EQ(slam.frameCount(), 2U);
    EXPECT_EQ(slam.egomotionPoses().size(), 2U);
    ASSERT_TRUE(slam.process(*frames[2].obs));
    ASSERT_TRUE(slam.process(*frames[3].obs));
    slam.finish();
    EXPECT_EQ(slam.egomotionFailures(), 0U);
    // Measured 0.004 m: the good frames chain as if the others were never given.
    EXPECT_LT(
        maxPoseDifference(slam.egomotionPoses().back().T_world_frame, frames[3].T_first_left),
        0.02);
}

TEST(EntropySlam, anEmptyRunFinishesWithNothing)
{
    EntropySlam slam(robotParameters(true));
    slam.finish();
    EXPECT_EQ(slam.frameCount(), 0U);
    EXPECT_TRUE(slam.slamPoses().empty());
    EXPECT_TRUE(slam.keyframes().empty());
    EXPECT_FALSE(slam.hasEnergy());
}

TEST(EntropySlam, configsWithTheFormerSectionNamesAreStillRead)
{
    EntropySlam::TParameters p;
    p.loadFromConfigFile(
        mrpt::config::CConfigFileMemory("[Stereo]\nblock_size = 7\n[Mapper]\nmap_cell_size = 0.05\n"
                                        "[LoopCloser]\nvertical_patch_px = 24\nmax_candidates = 5\n"
                                        "[OccupancyGrid]\ncell_size = 0.2\n"));
    EXPECT_EQ(p.stereo.block_size, 7);
    EXPECT_DOUBLE_EQ(p.mapper.map_cell_size, 0.05);
    EXPECT_EQ(p.loop_closer.vertical.patch_px, 24);
    EXPECT_EQ(p.loop_closer.max_candidates, 5);
    EXPECT_DOUBLE_EQ(p.occupancy_grid.cell_size, 0.2);
    // Saved under the new names only; read back the same.
    mrpt::config::CConfigFileMemory written;
    p.saveToConfigFile(written);
    // MRPT 2.5 reads defaults back from the object written: re-parse the text.
    const mrpt::config::CConfigFileMemory saved(written.getContent());
    EXPECT_FALSE(saved.sectionExists("Stereo"));
    EXPECT_EQ(saved.read_int("VerticalFromPlanes", "patch_px", 0), 24);
    EXPECT_FALSE(saved.keyExists("LoopCloser", "vertical_patch_px"));
    EntropySlam::TParameters q;
    q.loadFromConfigFile(saved);
    EXPECT_EQ(q.stereo.block_size, 7);
    EXPECT_EQ(q.loop_closer.vertical.patch_px, 24);
    emslam::test::expectThrowContaining(
        [&]
        {
            EntropySlam::TParameters r;
            r.loadFromConfigFile(
                mrpt::config::CConfigFileMemory("[VerticalFromPlanes]\npatch_px = 2\n"));
        },
        {"[VerticalFromPlanes]", "patch_px"});
}

TEST(EntropySlam, badParametersThrowNamingSectionAndKey)
{
    const auto load = [](const std::string& ini)
    {
        EntropySlam::TParameters p;
        p.loadFromConfigFile(mrpt::config::CConfigFileMemory(ini));
    };
    EXPECT_NO_THROW(load("[EntropySlam]\nmap_cell_size = 0.05\n"));
    emslam::test::expectThrowContaining(
        [&] { load("[EntropySlam]\nmap_cell_size = 0.0001\n"); },
        {"[EntropySlam]", "map_cell_size"});
    emslam::test::expectThrowContaining(
        [&] { load("[EntropySlam]\nexport_max_height = nan\n"); },
        {"[EntropySlam]", "export_max_height"});
    emslam::test::expectThrowContaining(
        [&] { load("[SpaceSampler]\nt_min = -1\n"); }, {"[SpaceSampler]", "t_min"});
    emslam::test::expectThrowContaining(
        [&] { load("[Rectifier]\nvalidate_phases = 1\n"); }, {"[Rectifier]", "validate_phases"});
    EntropySlam::TOptions o;
    o.map_cell_size = 0;  // every point
    EXPECT_NO_THROW(o.validate());
    o.map_cell_size = 2000;
    EXPECT_THROW(o.validate(), std::invalid_argument);
}
