// SPDX-License-Identifier: BSD-3-Clause
#include "SimulatedDrive.h"
#include "TestHelpers.h"

#include <emslam/rectify/EnergyAtPoses.h>
#include <emslam/rectify/Trajectory.h>

#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include <iostream>
#include <map>

using namespace emslam;
using namespace emslam::rectify;
using mrpt::poses::CPose3D;

namespace
{
CEntropyVoxelMap::TCreationOptions mapOptions(maps::EnergyType e)
{
    CEntropyVoxelMap::TCreationOptions o;
    o.cell_size = 0.15;
    o.energy = e;
    o.dof = maps::energyDof(e);
    return o;
}

/** The first `n` accepted frames of the hall, exact depth, drifted actions. */
std::vector<test::DrivenFrame> hallFrames(std::size_t n)
{
    test::DriveOptions o;
    o.max_frames = n;
    o.depth_noise = 0.0;
    o.heading_drift_deg_per_m = 1.0;
    return test::driveWorld("config/sim/hall_double_loop.ini", o);
}

Trajectory drivenTrajectory(const std::vector<test::DrivenFrame>& frames, maps::EnergyType e)
{
    Trajectory t(mapOptions(e));
    for (const auto& f : frames)
    {
        t.append(f.action_drifted, f.cloud, f.timestamp, f.frame_index);
    }
    return t;
}

FramePoseLookup lookupOf(const std::vector<TimedPose>& poses)
{
    std::map<std::size_t, CPose3D> by_index;
    for (const auto& p : poses)
    {
        by_index[p.frame_index] = p.T_world_frame;
    }
    return [by_index](std::size_t i) { return by_index.at(i); };
}

}  // namespace

TEST(EnergyAtPoses, atItsOwnFramePosesTheTrajectoryKeepsItsPosesAndEntropy)
{
    const auto frames = hallFrames(60);
    ASSERT_GT(frames.size(), 20u);
    for (const auto energy : {maps::EnergyType::PlanarLowStructured, maps::EnergyType::Structured})
    {
        SCOPED_TRACE(maps::toString(energy));
        Trajectory t = drivenTrajectory(frames, energy);
        t.compress();  // elements of two frames: the lookup uses each one's first frame
        const auto poses = elementPosesAt(t, lookupOf(t.framePoses()));
        ASSERT_EQ(poses.size(), t.size());
        for (std::size_t i = 0; i < t.size(); ++i)
        {
            EXPECT_LT(test::maxPoseDifference(poses[i], t.pose(i)), 1e-9) << "element " << i;
        }
        EXPECT_NEAR(entropyAtElementPoses(t, poses), t.entropy(), 1e-9 * std::abs(t.entropy()));
    }
}

TEST(EnergyAtPoses, onExactDepthTheTruthHasLessEntropyThanADriftedTrajectory)
{
    const auto frames = hallFrames(120);
    const Trajectory t = drivenTrajectory(frames, maps::EnergyType::PlanarLowStructured);
    std::map<std::size_t, CPose3D> truth;
    for (const auto& f : frames)
    {
        truth[f.frame_index] = f.T_world_true;
    }
    const double h_truth =
        entropyAtElementPoses(t, elementPosesAt(t, [&](std::size_t i) { return truth.at(i); }));
    // The trajectory itself holds the drifted actions (1 deg/m of heading drift).
    EXPECT_LT(h_truth, t.entropy() - 0.01);
    // A different map: moving one element changes the entropy.
    auto moved = elementPosesAt(t, [&](std::size_t i) { return truth.at(i); });
    moved[moved.size() / 2] = moved[moved.size() / 2] + CPose3D(0.5, 0, 0, 0, 0, 0);
    EXPECT_GT(entropyAtElementPoses(t, moved), h_truth);
}

TEST(EnergyAtPoses, threeDofPosesAreMadePlanar)
{
    const auto frames = hallFrames(40);
    const Trajectory t = drivenTrajectory(frames, maps::EnergyType::PlanarLowStructured);
    // A lookup that lifts and rolls every frame: a 3DOF trajectory cannot hold it.
    const auto poses = elementPosesAt(
        t,
        [&](std::size_t i)
        {
            const CPose3D p = t.framePoses().at(0).T_world_frame;
            for (const auto& f : frames)
            {
                if (f.frame_index == i)
                {
                    return f.T_world_true + CPose3D(0, 0.2, 0, 0, 0, mrpt::DEG2RAD(5.0));
                }
            }
            return p;
        });
    for (std::size_t i = 1; i < poses.size(); ++i)
    {
        const CPose3D a = poses[i] - poses[i - 1];
        EXPECT_NEAR(a.y(), 0.0, 1e-9);
        EXPECT_NEAR(a.roll(), 0.0, 1e-9);
    }
    test::expectThrowContaining(
        [&] { entropyAtElementPoses(t, {CPose3D()}); }, {"1 poses for", "elements"});
}

TEST(EnergyAtPoses, gridPhasesFollowChangesRevertsAndCompression)
{
    const auto frames = hallFrames(60);
    Trajectory t = drivenTrajectory(frames, maps::EnergyType::Structured);
    t.setGridPhases(3);
    EXPECT_EQ(t.gridPhases(), 3);
    const auto own = [&] { return elementPosesAt(t, lookupOf(t.framePoses())); };
    const double tol = 1e-9 * std::abs(t.entropy());
    EXPECT_NEAR(t.entropy(), entropyAtElementPoses(t, own(), 3), tol);
    EXPECT_GT(std::abs(t.entropy() - entropyAtElementPoses(t, own(), 1)), 1e-6);

    const double before = t.energy();
    const double changed = t.changeActions({{5, t.action(5) + CPose3D(0.1, 0, 0.05, 0.02, 0, 0)}});
    EXPECT_NEAR(changed, entropyAtElementPoses(t, own(), 3), tol);
    EXPECT_NEAR(t.revertLastChange(), before, tol);
    t.changeActions({{7, t.action(7) + CPose3D(0, 0.03, 0, 0, 0.01, 0)}});
    t.commitChange();
    t.compress();
    EXPECT_NEAR(t.entropy(), entropyAtElementPoses(t, own(), 3), tol);
    EXPECT_NEAR(t.recomputeEnergy(), t.entropy(), tol);
    test::expectThrowContaining([&] { t.setGridPhases(0); }, {"setGridPhases", "1..8"});
}

TEST(EnergyAtPoses, resolutionLevelsRebinOnCoarserCellsAndComeBackExactly)
{
    const auto frames = hallFrames(60);
    Trajectory t = drivenTrajectory(frames, maps::EnergyType::PlanarLowStructured);
    t.setGridPhases(2);
    const double fine = t.entropy();
    const double cell = t.map().creationOptions().cell_size;
    t.setResolutionLevel(1);
    EXPECT_DOUBLE_EQ(t.map().creationOptions().cell_size, 2 * cell);
    // Fewer, fuller cells: less entropy, the same as a map built on them.
    EXPECT_LT(t.entropy(), fine - 0.1);
    const auto own = elementPosesAt(t, lookupOf(t.framePoses()));
    EXPECT_NEAR(t.entropy(), entropyAtElementPoses(t, own, 2), 1e-9 * std::abs(fine));
    // Moves on the coarse grid are undone exactly; l_d comes back bit for bit.
    const double before = t.energy();
    t.changeActions({{5, t.action(5) + CPose3D(0.2, 0, 0.1, 0.03, 0, 0)}});
    EXPECT_NEAR(t.revertLastChange(), before, 1e-9 * std::abs(before));
    t.setResolutionLevel(0);
    EXPECT_NEAR(t.entropy(), fine, 1e-9 * std::abs(fine));
    // append() works on l_d: it returns there first.
    t.setResolutionLevel(2);
    t.append(CPose3D(0.1, 0, 0, 0, 0, 0), frames.back().cloud, 99.0);
    EXPECT_EQ(t.resolutionLevel(), 0);
    test::expectThrowContaining([&] { t.setResolutionLevel(5); }, {"setResolutionLevel", "0..4"});
}

TEST(EnergyAtPoses, priorAtPosesIsTheTrajectorysPriorAndZeroAtTheEgomotion)
{
    const auto frames = hallFrames(60);
    Trajectory t = drivenTrajectory(frames, maps::EnergyType::PlanarLowStructured);
    OdometryPrior prior;
    prior.weight = 1e-3;
    t.setOdometryPrior(prior);
    const auto own = [&] { return elementPosesAt(t, lookupOf(t.framePoses())); };
    EXPECT_NEAR(priorAtElementPoses(t, own()), 0.0, 1e-12);  // the actions are the egomotion's
    t.changeActions({{4, t.action(4) + CPose3D(0.05, 0, -0.04, 0.02, 0, 0)}});
    t.commitChange();
    EXPECT_GT(t.priorEnergy(), 1e-4);
    EXPECT_NEAR(priorAtElementPoses(t, own()), t.priorEnergy(), 1e-9 * t.priorEnergy());
    t.setOdometryPrior(OdometryPrior{});
    EXPECT_EQ(priorAtElementPoses(t, own()), 0.0);
    test::expectThrowContaining(
        [&] { priorAtElementPoses(t, {CPose3D()}); }, {"1 poses for", "elements"});
}

TEST(EnergyAtPoses, averagedGridPhasesHideMostOfTheGridPhase)
{
    // The same map moved rigidly by fractions of a cell: the single grid's
    // entropy changes with the phase, the average over 4 phases much less.
    const auto frames = hallFrames(120);
    const Trajectory t = drivenTrajectory(frames, maps::EnergyType::Unstructured);
    const auto base = elementPosesAt(t, lookupOf(t.framePoses()));
    const auto spread = [&](int phases)
    {
        double lo = 1e9, hi = -1e9;
        for (int k = 0; k < 5; ++k)
        {
            std::vector<CPose3D> moved;
            const double d = 0.15 * k / 5 + 0.011;
            for (const auto& p : base)
            {
                moved.push_back(CPose3D(d, 0.7 * d, 0.4 * d, 0, 0, 0) + p);
            }
            const double h = entropyAtElementPoses(t, moved, phases);
            lo = std::min(lo, h);
            hi = std::max(hi, h);
        }
        return hi - lo;
    };
    const double single = spread(1);
    const double averaged = spread(4);
    std::cout << "entropy spread over grid phases: single grid " << single << ", 4 phases "
              << averaged << "\n";
    EXPECT_LT(averaged, 0.5 * single);
}
