// SPDX-License-Identifier: BSD-3-Clause
#include "SimulatedDrive.h"
#include "TestHelpers.h"

#include <emslam/rectify/Action.h>
#include <emslam/rectify/EnergyAtPoses.h>
#include <emslam/rectify/EnergyScan.h>
#include <emslam/rectify/Trajectory.h>

#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>

using namespace emslam;
using namespace emslam::rectify;
using mrpt::poses::CPose3D;

namespace
{
/** The first `n` accepted frames of the hall: exact depth, drifted actions. */
const std::vector<test::DrivenFrame>& hallFrames(std::size_t n)
{
    static std::map<std::size_t, std::vector<test::DrivenFrame>> cache;
    auto it = cache.find(n);
    if (it == cache.end())
    {
        test::DriveOptions o;
        o.max_frames = n;
        o.depth_noise = 0.0;
        it = cache.emplace(n, test::driveWorld("config/sim/hall_double_loop.ini", o)).first;
    }
    return it->second;
}

Trajectory drivenTrajectory(const std::vector<test::DrivenFrame>& frames, maps::EnergyType e)
{
    CEntropyVoxelMap::TCreationOptions o;
    o.cell_size = 0.15;
    o.energy = e;
    o.dof = maps::energyDof(e);
    Trajectory t(o);
    for (const auto& f : frames)
    {
        t.append(f.action_drifted, f.cloud, f.timestamp, f.frame_index);
    }
    return t;
}

std::vector<CPose3D> truthOf(const Trajectory& t, const std::vector<test::DrivenFrame>& frames)
{
    std::map<std::size_t, CPose3D> truth;
    for (const auto& f : frames)
    {
        truth[f.frame_index] = f.T_world_true;
    }
    return elementPosesAt(t, [&](std::size_t i) { return truth.at(i); });
}

/** Element poses with action k of the truth perturbed by `offset` along `dimension`. */
std::vector<CPose3D> perturbedPoses(
    const std::vector<CPose3D>& truth, int dof, std::size_t k, int dimension, double offset)
{
    ActionDelta delta{};
    delta[dimension] = offset;
    CPose3D a = perturbAction(k == 0 ? truth[0] : truth[k] - truth[k - 1], delta);
    if (dof == 3)
    {
        a = planarAction(a);
    }
    std::vector<CPose3D> poses = truth;
    poses[k] = (k == 0 ? CPose3D() : truth[k - 1]) + a;
    for (std::size_t i = k + 1; i < truth.size(); ++i)
    {
        poses[i] = poses[i - 1] + (truth[i] - truth[i - 1]);
    }
    return poses;
}

/** The four walls of a room (sampled every 5 cm, off the voxel grid; no floor
 * or ceiling, as the rectifier's vertical band keeps) seen from 48 poses
 * going twice round a circle, facing along it: each half of the trajectory
 * sees every wall. Exact clouds, the true actions; `truth` gets the element
 * poses. */
Trajectory closedRoomTrajectory(maps::EnergyType e, std::vector<CPose3D>& truth)
{
    std::vector<mrpt::math::TPoint3Df> room;
    const double x0 = -2.93, x1 = 3.07, y0 = -1.47, y1 = 1.02, z0 = -3.11, z1 = 2.96;
    const double d = 0.05;
    for (double a = x0; a <= x1; a += d)
    {
        for (double b = y0; b <= y1; b += d)
        {
            room.emplace_back(a, b, z0);
            room.emplace_back(a, b, z1);
        }
    }
    for (double a = z0; a <= z1; a += d)
    {
        for (double b = y0; b <= y1; b += d)
        {
            room.emplace_back(x0, b, a);
            room.emplace_back(x1, b, a);
        }
    }
    CEntropyVoxelMap::TCreationOptions o;
    o.cell_size = 0.15;
    o.energy = e;
    o.dof = maps::energyDof(e);
    Trajectory t(o);
    truth.clear();
    const int n = 48;
    for (int i = 0; i < n; ++i)
    {
        const double phi = 4.0 * M_PI * i / n;
        const CPose3D T(0.1 + std::sin(phi), 0.0, 0.2 + std::cos(phi), 0.0, phi + 0.3, 0.0);
        emslam::maps::WeightedPointCloud cloud;
        for (const auto& p : room)
        {
            double x, y, z;
            T.inverseComposePoint(p.x, p.y, p.z, x, y, z);
            if (z > 0.3 && std::abs(x) < z && std::abs(y) < 0.75 * z)
            {
                cloud.push_back(mrpt::math::TPoint3Df(x, y, z), 1.0f);
            }
        }
        t.append(truth.empty() ? T : T - truth.back(), cloud, i, i);
        truth.push_back(T);
    }
    return t;
}

const EnergyScanLine& lineOf(const EnergyScan& s, std::size_t action, int dimension)
{
    for (const auto& l : s.lines)
    {
        if (l.action == action && l.dimension == dimension)
        {
            return l;
        }
    }
    throw std::runtime_error("no scan line for that action and dimension");
}
}  // namespace

TEST(EnergyScan, chosenActionsAndDimensions)
{
    const Trajectory t3 = drivenTrajectory(hallFrames(60), maps::EnergyType::PlanarLowStructured);
    ASSERT_GE(t3.size(), 30u);
    const std::size_t n = t3.size();
    const auto a = energyScanActions(t3, 7);
    // Spread over a_1..a_{N-1}, the middle included; a_0 not (Exp. 11 is blind to it).
    EXPECT_EQ(a.front(), 1u);
    EXPECT_EQ(a.back(), n - 1);
    EXPECT_NE(std::find(a.begin(), a.end(), n / 2), a.end());
    EXPECT_GE(a.size(), 7u);
    EXPECT_LE(a.size(), 8u);
    EXPECT_EQ(energyScanActions(t3, 1), (std::vector<std::size_t>{1, n / 2}));
    // A Manhattan energy depends on a_0: the rectifier perturbs it, so the scan does.
    const Trajectory t6 = drivenTrajectory(hallFrames(60), maps::EnergyType::Structured);
    EXPECT_EQ(energyScanActions(t6, 7).front(), 0u);
    EXPECT_EQ(actionDimensions(3), (std::vector<int>{0, 2, 4}));
    EXPECT_EQ(actionDimensions(6).size(), 6u);
    EXPECT_EQ(actionDimensionName(4), "theta_y");
}

TEST(EnergyScan, truthEnergyIsTheEntropyAtTheTruthAndTheTrajectoryDoesNotChange)
{
    const auto& frames = hallFrames(60);
    for (const auto energy : {maps::EnergyType::PlanarLowStructured, maps::EnergyType::Structured})
    {
        SCOPED_TRACE(maps::toString(energy));
        Trajectory t = drivenTrajectory(frames, energy);
        t.compress();  // elements of two frames
        const double entropy_before = t.entropy();
        const std::vector<CPose3D> actions_before = t.actions();
        const auto truth = truthOf(t, frames);
        for (const int phases : {1, 2})
        {
            EnergyScanOptions o;
            o.actions = 3;
            o.translation_steps = 2;
            o.rotation_steps = 2;
            o.grid_phases = phases;
            const EnergyScan s = scanEnergy(t, truth, o);
            // Built from scratch, summed in another order than the scan's
            // incremental map: equal up to rounding.
            const double h = entropyAtElementPoses(t, truth, phases);
            EXPECT_NEAR(s.summary.energy_at_truth, h, 1e-12);
            EXPECT_EQ(s.summary.grid_phases, phases);
            const std::size_t dims = actionDimensions(t.dof()).size();
            ASSERT_EQ(s.lines.size(), energyScanActions(t, 3).size() * dims);
            EXPECT_EQ(s.summary.evaluations, 1 + 4 * s.lines.size());
            for (const auto& l : s.lines)
            {
                ASSERT_EQ(l.offsets.size(), 5u);
                EXPECT_EQ(l.offsets[2], 0.0);
                EXPECT_NEAR(l.energies[2], h, 1e-12);
                EXPECT_NEAR(l.energy_at_truth, h, 1e-12);
            }
        }
        // The scan works on its own copy of the map.
        EXPECT_EQ(t.entropy(), entropy_before);
        for (std::size_t i = 0; i < t.size(); ++i)
        {
            EXPECT_EQ(test::maxPoseDifference(t.action(i), actions_before[i]), 0.0) << i;
        }
    }
}

TEST(EnergyScan, eachEnergyIsTheEntropyOfItsPosesFromScratch)
{
    const auto& frames = hallFrames(60);
    for (const auto energy : {maps::EnergyType::PlanarStructured, maps::EnergyType::Unstructured})
    {
        SCOPED_TRACE(maps::toString(energy));
        const Trajectory t = drivenTrajectory(frames, energy);
        const auto truth = truthOf(t, frames);
        EnergyScanOptions o;
        o.actions = 3;
        o.translation_steps = 2;
        o.rotation_steps = 2;
        const EnergyScan s = scanEnergy(t, truth, o);
        const std::size_t k = t.size() / 2;
        for (const int d : actionDimensions(t.dof()))
        {
            SCOPED_TRACE(actionDimensionName(d));
            const EnergyScanLine& l = lineOf(s, k, d);
            // Default steps: a quarter cell, 1 degree.
            const double s1 = d >= 3 ? mrpt::DEG2RAD(1.0) : 0.25 * 0.15;
            EXPECT_NEAR(l.offsets[3], s1, 1e-15);
            EXPECT_NEAR(l.offsets[0], -2 * s1, 1e-15);
            for (const std::size_t j : {0u, 3u})
            {
                const double h =
                    entropyAtElementPoses(t, perturbedPoses(truth, t.dof(), k, d, l.offsets[j]));
                EXPECT_NEAR(l.energies[j], h, 1e-9 * h) << "offset " << l.offsets[j];
                EXPECT_NE(l.energies[j], l.energy_at_truth);
            }
            EXPECT_NEAR(
                l.curvature, (l.energies[3] + l.energies[1] - 2 * l.energies[2]) / (s1 * s1),
                1e-9 * std::abs(l.curvature));
            EXPECT_NEAR(
                l.slope, (l.energies[3] - l.energies[1]) / (2 * s1),
                1e-9 * std::abs(l.slope) + 1e-12);
        }
        // The first scanned action moves every element after it.
        const EnergyScanLine& first = lineOf(s, 1, 0);
        EXPECT_NEAR(
            first.energies[4],
            entropyAtElementPoses(t, perturbedPoses(truth, t.dof(), 1, 0, first.offsets[4])),
            1e-9 * first.energies[4]);
    }
}

TEST(EnergyScan, inARoomOfWallsTheTranslationMinimumIsAtTheTruth)
{
    // Exact data, a double loop in a room: moving the middle action along x
    // or z moves the second loop's walls off the first's. (Going round only
    // once, the minimum along x was 0.30 m away, 0.26 m with a floor and a
    // ceiling: what only the moved half sees can then shrink the map.)
    for (const auto energy :
         {maps::EnergyType::PlanarLowStructured, maps::EnergyType::Unstructured})
    {
        SCOPED_TRACE(maps::toString(energy));
        std::vector<CPose3D> truth;
        const Trajectory t = closedRoomTrajectory(energy, truth);
        EnergyScanOptions o;
        o.actions = 1;  // a_1 and the middle one
        const EnergyScan s = scanEnergy(t, truth, o);
        const double step = 0.25 * 0.15;
        for (const int d : {0, 2})
        {
            const EnergyScanLine& l = lineOf(s, t.size() / 2, d);
            SCOPED_TRACE(actionDimensionName(d));
            ASSERT_EQ(l.offsets.size(), 17u);
            EXPECT_LE(std::abs(l.argmin_offset), step + 1e-12);
            // Two cells away the map is clearly worse than at the truth.
            EXPECT_GT(l.energies.front(), l.energy_at_truth + 0.01);
            EXPECT_GT(l.energies.back(), l.energy_at_truth + 0.01);
            EXPECT_EQ(l.truthIsMinimum(), l.argmin_offset == 0.0);
            EXPECT_LE(l.min_energy, l.energy_at_truth);
        }
        // The summary counts what the lines say.
        std::size_t at_truth = 0;
        for (const auto& l : s.lines)
        {
            at_truth += l.truthIsMinimum() ? 1 : 0;
        }
        EXPECT_DOUBLE_EQ(s.summary.fraction_at_truth, double(at_truth) / s.lines.size());
        const std::size_t dims = actionDimensions(t.dof()).size();
        ASSERT_EQ(s.summary.dimensions.size(), dims);
        EXPECT_EQ(s.summary.dimensions[0].lines, 2u);
        EXPECT_EQ(s.summary.lines, 2 * dims);
        EXPECT_FALSE(std::isnan(s.summary.median_abs_argmin_rotation_rad));
    }
}

TEST(EnergyScan, badArgumentsThrow)
{
    const auto& frames = hallFrames(20);
    const Trajectory t = drivenTrajectory(frames, maps::EnergyType::PlanarLowStructured);
    test::expectThrowContaining([&] { scanEnergy(t, {CPose3D()}); }, {"scanEnergy", "1 poses for"});
    const auto truth = truthOf(t, frames);
    EnergyScanOptions o;
    o.grid_phases = 9;
    test::expectThrowContaining([&] { scanEnergy(t, truth, o); }, {"grid_phases"});
    o = {};
    o.translation_steps = 0;
    test::expectThrowContaining([&] { scanEnergy(t, truth, o); }, {"translation_steps"});
    o = {};
    o.rotation_step_deg = 0;
    test::expectThrowContaining([&] { scanEnergy(t, truth, o); }, {"rotation_step_deg"});
    o = {};
    o.actions = 0;
    test::expectThrowContaining([&] { scanEnergy(t, truth, o); }, {"actions"});
}
