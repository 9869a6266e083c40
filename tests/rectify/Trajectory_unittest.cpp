// SPDX-License-Identifier: BSD-3-Clause
#include "TestHelpers.h"

#include <emslam/rectify/Action.h>
#include <emslam/rectify/ActionCovariance.h>
#include <emslam/rectify/Trajectory.h>

#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include <array>
#include <random>

using namespace emslam;
using namespace emslam::rectify;
using mrpt::poses::CPose3D;

namespace
{
/** A random blob of points around (0, 0, 3) in the camera frame. */
maps::WeightedPointCloud blob(std::uint64_t seed, std::size_t n = 400)
{
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(-2.f, 2.f);
    maps::WeightedPointCloud c;
    for (std::size_t i = 0; i < n; ++i)
    {
        c.push_back({u(rng), u(rng), 3.f + u(rng)}, 1.f);
    }
    return c;
}

CEntropyVoxelMap::TCreationOptions mapOptions(maps::EnergyType e)
{
    CEntropyVoxelMap::TCreationOptions o;
    o.energy = e;
    o.dof = maps::energyDof(e);
    return o;
}

}  // namespace

TEST(Trajectory, posesAreTheCompositionOfTheActions)
{
    Trajectory t(mapOptions(maps::EnergyType::Unstructured));
    const CPose3D a1(0.3, 0.0, 0.5, mrpt::DEG2RAD(10.0), 0, 0);
    const CPose3D a2(0.1, 0.05, 0.4, 0, mrpt::DEG2RAD(-4.0), mrpt::DEG2RAD(2.0));
    t.append(CPose3D(), blob(1), 0.0, 0);
    t.append(a1, blob(2), 0.1, 1);
    t.append(a2, blob(3), 0.2, 2);
    ASSERT_EQ(t.size(), 3u);
    EXPECT_LT(test::maxPoseDifference(t.pose(2), a1 + a2), 1e-12);
    EXPECT_LT(test::maxPoseDifference(t.map().observationPose(1), a1), 1e-12);
    EXPECT_EQ(t.frameCount(), 3u);
    EXPECT_EQ(t.framePoses()[2].frame_index, 2u);
    EXPECT_DOUBLE_EQ(t.framePoses()[1].timestamp, 0.1);
}

TEST(Trajectory, changingAnActionMovesOnlyTheLaterSegment)
{
    Trajectory t(mapOptions(maps::EnergyType::Structured));
    for (int i = 0; i < 6; ++i)
    {
        t.append(i == 0 ? CPose3D() : CPose3D(0.2, 0, 0.3, 0.05, 0, 0), blob(10 + i), i, i);
    }
    const std::vector<CPose3D> before = {t.pose(0), t.pose(1), t.pose(2)};
    const CPose3D new_a3 = perturbAction(t.action(3), {0.05, -0.02, 0.03, 0.01, 0.02, -0.03});
    const double e = t.changeActions({{3, new_a3}});
    for (int i = 0; i < 3; ++i)
    {
        EXPECT_LT(test::maxPoseDifference(t.pose(i), before[i]), 1e-15) << i;
    }
    EXPECT_LT(
        test::maxPoseDifference(t.pose(5), t.pose(2) + new_a3 + t.action(4) + t.action(5)), 1e-12);
    // The incremental energy equals a from-scratch evaluation at the new poses.
    const auto scratch = t.map().computeEntropiesFromScratch();
    EXPECT_NEAR(e, maps::energyFromTerms(maps::EnergyType::Structured, scratch), 1e-9);

    // Reverting restores the actions, poses and energy.
    const double e_back = t.revertLastChange();
    EXPECT_LT(
        test::maxPoseDifference(t.pose(5), before[2] + t.action(3) + t.action(4) + t.action(5)),
        1e-12);
    EXPECT_NEAR(e_back, t.recomputeEnergy(), 1e-9);
    EXPECT_FALSE(t.canRevert());
    EXPECT_THROW(t.revertLastChange(), std::logic_error);
    EXPECT_THROW(t.changeActions({{6, CPose3D()}}), std::out_of_range);
}

TEST(Trajectory, planarEnergiesKeepActionsPlanar)
{
    Trajectory t(mapOptions(maps::EnergyType::PlanarLowStructured));
    ASSERT_EQ(t.dof(), 3);
    t.append(CPose3D(), blob(1), 0, 0);
    // A 6DOF action: y, pitch and roll components are dropped.
    t.append(
        CPose3D(0.4, 0.1, 0.2, mrpt::DEG2RAD(3.0), mrpt::DEG2RAD(20.0), mrpt::DEG2RAD(2.0)),
        blob(2), 1, 1);
    const CPose3D& a = t.action(1);
    EXPECT_NEAR(a.x(), 0.4, 1e-12);
    EXPECT_NEAR(a.y(), 0.0, 1e-12);
    EXPECT_NEAR(a.z(), 0.2, 1e-12);
    const auto& R = a.getRotationMatrix();
    EXPECT_NEAR(R(1, 1), 1.0, 1e-12);  // a pure rotation about the vertical y axis
    EXPECT_NEAR(R(0, 1), 0.0, 1e-12);
    EXPECT_NEAR(R(1, 0), 0.0, 1e-12);
    // MRPT's pitch is the rotation about y.
    EXPECT_NEAR(std::atan2(R(0, 2), R(0, 0)), mrpt::DEG2RAD(20.0), mrpt::DEG2RAD(1.5));

    // A 3DOF perturbation keeps it planar.
    t.changeActions({{1, perturbAction(a, {0.05, 0, -0.05, 0, 0.03, 0})}});
    EXPECT_NEAR(t.pose(1).y(), 0.0, 1e-12);
    EXPECT_NEAR(t.pose(1).getRotationMatrix()(1, 1), 1.0, 1e-12);
}

TEST(Trajectory, actionsAfterCompressionStartAtTheLastFrame)
{
    Trajectory t(mapOptions(maps::EnergyType::Unstructured));
    const CPose3D step(0.2, 0, 0.3, 0.1, 0, 0);
    for (int i = 0; i < 5; ++i)
    {
        t.append(i == 0 ? CPose3D() : step, blob(20 + i), i, i);
    }
    t.compress();
    ASSERT_EQ(t.size(), 3u);
    t.append(step, blob(30), 5, 5);
    // Frame 5 is one step after frame 4, wherever frame 4 sits in its element.
    CPose3D expected;
    for (int i = 0; i < 5; ++i)
        expected = expected + step;
    const auto poses = t.framePoses();
    ASSERT_EQ(poses.size(), 6u);
    EXPECT_LT(test::maxPoseDifference(poses[5].T_world_frame, expected), 1e-9);
}

TEST(Trajectory, odometryPriorFollowsChangesRevertsAndCompression)
{
    Trajectory t(mapOptions(maps::EnergyType::PlanarLowStructured));
    t.setOdometryPrior({0.01, 0.02, 0.5});
    const CPose3D step(0.1, 0, 0.3, 0, mrpt::DEG2RAD(5.0), 0);
    for (int i = 0; i < 8; ++i)
    {
        t.append(i == 0 ? CPose3D() : step, blob(40 + i), i, i);
    }
    EXPECT_EQ(t.priorEnergy(), 0.0);  // the actions are the egomotion's
    const double e0 = t.energy();
    EXPECT_DOUBLE_EQ(e0, t.entropy());

    const CPose3D moved = perturbAction(t.action(3), {0.02, 0, 0, 0, 0, 0});
    const double e1 = t.changeActions({{3, moved}});
    // (0.02 / 0.02)^2 / 1 step, times weight / 2.
    EXPECT_NEAR(t.priorEnergy(), 0.005, 1e-12);
    EXPECT_NEAR(e1, t.entropy() + 0.005, 1e-12);
    EXPECT_NEAR(t.revertLastChange(), e0, 1e-9);
    EXPECT_NEAR(t.priorEnergy(), 0.0, 1e-20);

    // Compression composes the references as it composes the actions, and the
    // fused action spans two steps.
    t.changeActions({{3, moved}});
    t.commitChange();
    t.compress();
    ASSERT_EQ(t.size(), 4u);
    EXPECT_LT(test::maxPoseDifference(t.referenceAction(1), step + step), 1e-12);
    const OdometryPrior p{0.01, 0.02, 0.5};
    EXPECT_NEAR(t.priorEnergy(), p.cost(t.action(2), t.referenceAction(2), 2), 1e-12);
    EXPECT_NEAR(t.priorEnergy(), 0.0025, 1e-9);
}

TEST(Trajectory, egomotionCovariancePriorIsMahalanobisAndComposesOnCompression)
{
    Trajectory t(mapOptions(maps::EnergyType::Unstructured));
    OdometryPrior prior{0.5, 0.02, 0.5, PriorCovariance::Egomotion};
    t.setOdometryPrior(prior);
    const CPose3D step(0.1, 0.02, 0.3, mrpt::DEG2RAD(5.0), 0, 0);
    ActionCovariance cov;
    cov.setZero();
    const std::array<double, 6> sd{0.01, 0.04, 0.02, 0.001, 0.002, 0.003};
    for (int k = 0; k < 6; ++k)
    {
        cov(k, k) = sd[static_cast<std::size_t>(k)] * sd[static_cast<std::size_t>(k)];
    }
    for (int i = 0; i < 4; ++i)
    {
        t.append(i == 0 ? CPose3D() : step, blob(70 + i), i, i, cov);
    }
    EXPECT_EQ(t.priorEnergy(), 0.0);
    // Two σ along y: the uncertain direction costs what its deviation says.
    t.changeActions({{2, perturbAction(t.action(2), {0, 0.08, 0, 0, 0, 0})}});
    EXPECT_NEAR(t.priorEnergy(), 0.5 * 0.5 * 4.0, 1e-9);
    // Two σ along x, where the egomotion was 4× surer: the same cost.
    t.revertLastChange();
    t.changeActions({{2, perturbAction(t.action(2), {0.02, 0, 0, 0, 0, 0})}});
    EXPECT_NEAR(t.priorEnergy(), 0.5 * 0.5 * 4.0, 1e-9);
    t.revertLastChange();

    // Compression: the fused action's covariance is the composition of its
    // two steps' covariances.
    t.compress();
    ASSERT_EQ(t.size(), 2u);
    const ActionCovariance expected = composeCovariance(step, cov, step, cov);
    for (int r = 0; r < 6; ++r)
    {
        for (int c = 0; c < 6; ++c)
        {
            EXPECT_NEAR(t.referenceCovariance(1)(r, c), expected(r, c), 1e-15);
        }
    }
    // A frame appended after compression starts at the last frame inside the
    // last element: its covariance is carried into the element's frame.
    t.append(step, blob(90), 5, 5, cov);
    const ActionCovariance carried = transportCovariance(step, cov);
    EXPECT_NEAR(t.referenceCovariance(2)(0, 0), carried(0, 0), 1e-15);
    EXPECT_NEAR(t.referenceCovariance(2)(1, 1), carried(1, 1), 1e-15);
}

TEST(Trajectory, twoThreadsKeepTheirSettingAndGiveTheSameEnergies)
{
    // 40 blobs of ~3,000 simplified points: every change is split.
    Trajectory one(mapOptions(maps::EnergyType::Structured));
    Trajectory two(mapOptions(maps::EnergyType::Structured));
    one.setGridPhases(2);
    two.setGridPhases(2);
    two.setThreads(2);
    const CPose3D step(0.1, 0.0, 0.2, mrpt::DEG2RAD(2.0), 0, 0);
    for (std::size_t i = 0; i < 40; ++i)
    {
        one.append(i == 0 ? CPose3D() : step, blob(10 + i, 4000), 0.1 * i, i);
        two.append(i == 0 ? CPose3D() : step, blob(10 + i, 4000), 0.1 * i, i);
    }
    one.compress();
    two.compress();
    one.setGridPhases(3);
    two.setGridPhases(3);
    EXPECT_EQ(two.threads(), 2);
    EXPECT_EQ(one.threads(), 1);
    EXPECT_EQ(two.recomputeEnergy(), one.recomputeEnergy());
    const std::vector<Trajectory::ActionChange> changes{
        {0, CPose3D(0.01, 0, 0, 0.01, 0, 0)}, {3, step + CPose3D(0.05, 0, 0, 0, 0.02, 0)}};
    const double e1 = one.changeActions(changes);
    EXPECT_EQ(two.changeActions(changes), e1);
    const double r1 = one.revertLastChange();
    EXPECT_EQ(two.revertLastChange(), r1);
    EXPECT_THROW(two.setThreads(3), std::exception);
}
