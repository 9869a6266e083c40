// SPDX-License-Identifier: BSD-3-Clause
// The Manhattan-world energy straightens an acyclic trajectory (paper
// Fig. 18, top): along three corridors with heading drift, the first and the
// last corridors come out parallel.
#include "PaperRectifierOptions.h"
#include "SimulatedDrive.h"

#include <emslam/rectify/SerialRectification.h>

#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

using namespace emslam;
using namespace emslam::rectify;

namespace
{
/** Heading of a camera pose about the vertical axis [rad] (optical frame:
 * y down, z forward). */
double headingOf(const mrpt::poses::CPose3D& p)
{
    const auto R = p.getRotationMatrix();
    return std::atan2(R(0, 2), R(2, 2));
}

/** Direction [rad] of the line fitted (principal axis) to the horizontal
 * positions of the frames `idx`. */
double lineDirection(
    const std::vector<mrpt::poses::CPose3D>& p, const std::vector<std::size_t>& idx)
{
    double mx = 0, mz = 0;
    for (const auto i : idx)
    {
        mx += p[i].x();
        mz += p[i].z();
    }
    mx /= static_cast<double>(idx.size());
    mz /= static_cast<double>(idx.size());
    double sxx = 0, szz = 0, sxz = 0;
    for (const auto i : idx)
    {
        const double dx = p[i].x() - mx, dz = p[i].z() - mz;
        sxx += dx * dx;
        szz += dz * dz;
        sxz += dx * dz;
    }
    return 0.5 * std::atan2(2 * sxz, sxx - szz);
}

/** The frames driving straight along the first corridor (true heading that
 * of frame 0) and along the last one (heading turned by 180°), from the
 * ground truth. */
struct Corridors
{
    std::vector<std::size_t> first, last;
};
Corridors findCorridors(const std::vector<test::DrivenFrame>& truth)
{
    Corridors c;
    const double h0 = headingOf(truth.front().T_world_true);
    bool turned = false;
    for (std::size_t i = 0; i < truth.size(); i++)
    {
        const double d = std::abs(mrpt::math::wrapToPi(headingOf(truth[i].T_world_true) - h0));
        turned = turned || d > mrpt::DEG2RAD(1.0);
        if (!turned && d < mrpt::DEG2RAD(0.1))
        {
            c.first.push_back(i);
        }
        if (turned && std::abs(d - M_PI) < mrpt::DEG2RAD(0.1))
        {
            c.last.push_back(i);
        }
    }
    return c;
}

/** Angle [deg] between the first and the last corridor of a trajectory:
 * between the lines fitted to the positions of the frames in each. They
 * are parallel in truth. (The line through a corridor's frames measures
 * the corridor's direction in the map; a single frame's heading would add
 * the few-degree jitter that compressed elements keep inside them.) */
double corridorAngleDeg(const std::vector<mrpt::poses::CPose3D>& est, const Corridors& c)
{
    const double d = lineDirection(est, c.last) - lineDirection(est, c.first);
    // Lines, not vectors: angles are modulo 180°.
    return mrpt::RAD2DEG(std::abs(mrpt::math::wrapToPi(2 * d)) / 2);
}

std::vector<mrpt::poses::CPose3D> rectifiedPoses(
    maps::EnergyType energy, const std::vector<test::DrivenFrame>& f, std::uint64_t seed)
{
    CEntropyVoxelMap::TCreationOptions map;
    map.cell_size = 0.15;
    map.energy = energy;
    map.dof = 3;
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.seed = seed;
    // Floor and ceiling carry no alignment information in the XZ plane and
    // reward folding the corridors onto each other: keep the walls.
    opt.vertical_band = true;
    SerialRectification slam(opt, map);
    for (const auto& fr : f)
    {
        slam.addFrame(fr.action_drifted, fr.cloud, fr.timestamp, fr.frame_index);
    }
    slam.finish();
    std::vector<mrpt::poses::CPose3D> poses;
    for (const auto& p : slam.framePoses())
    {
        poses.push_back(p.T_world_frame);
    }
    return poses;
}
}  // namespace

TEST(ThreeCorridors, manhattanEnergyMakesFirstAndLastCorridorsParallel)
{
    test::DriveOptions drive;
    drive.heading_drift_deg_per_m = 0.15;

    const auto frames = test::driveWorld("config/sim/three_corridors.ini", drive);
    ASSERT_GT(frames.size(), 200u);
    const Corridors corridors = findCorridors(frames);
    ASSERT_GT(corridors.first.size(), 50u);
    ASSERT_GT(corridors.last.size(), 50u);

    const double ego = corridorAngleDeg(test::composeActions(frames), corridors);
    std::cout << "frames " << frames.size() << ", angle between first and last corridor [deg]: "
              << "egomotion " << ego << "\n";
    EXPECT_GT(ego, 3.0);
    // The target for Exp. 12 (parallel within 1°), for several
    // rectifier seeds; Exp. 11 has no reason to reach it and is only printed.
    for (std::uint64_t seed = 1; seed <= 5; seed++)
    {
        const double manhattan = corridorAngleDeg(
            rectifiedPoses(maps::EnergyType::PlanarStructured, frames, seed), corridors);
        const double low = corridorAngleDeg(
            rectifiedPoses(maps::EnergyType::PlanarLowStructured, frames, seed), corridors);
        std::cout << "  seed " << seed << ": planar_structured " << manhattan
                  << ", planar_low_structured " << low << "\n";
        EXPECT_LT(manhattan, 1.0) << "rectifier seed " << seed;
    }
}
