// SPDX-License-Identifier: BSD-3-Clause
#include "SimTestWorlds.h"

#include <emslam/sim/FloorPlan.h>
#include <emslam/sim/StereoSimulator.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using emslam::sim::FloorPlanBand;
using emslam::sim::StereoSimulator;
using emslam::sim::SurfaceSampler;

namespace
{
bool near(double v, double target)
{
    return std::abs(v - target) <= 0.1 + 1e-9;
}
}  // namespace

TEST(FloorPlan, occupiesTheWallsAndObstaclesInTheBandWhereTheCameraSawThem)
{
    // The tiny corridor (scene x in [2, 6], z in [2, 12]) with a block against
    // its left wall; the camera starts at x = 3, z = 3, 1 m up, facing +z.
    mrpt::config::CConfigFileMemory cfg(
        emslam::test::tinyWorldIni("[Element_block]\ntype = box\nmin = 2 0 7\nmax = 2.5 2 7.5\n"));
    StereoSimulator sim;
    sim.load(cfg);
    SurfaceSampler::TParameters p;
    p.spacing = 0.03;
    const auto seen = SurfaceSampler(p).visibleSurfaces(sim, sim.frameCount());
    FloorPlanBand band;  // 0.1 m cells, 0.2 .. 1.5 m above the floor, 6 m
    const auto grid = emslam::sim::floorPlanGrid(seen, band);
    EXPECT_FLOAT_EQ(grid.getResolution(), 0.1F);
    // Grid X = forward = scene z - 3, grid Y = left = scene x - 3 (the camera's
    // right is the scene's -x).
    std::size_t occupied = 0;
    for (unsigned cy = 0; cy < grid.getSizeY(); ++cy)
    {
        for (unsigned cx = 0; cx < grid.getSizeX(); ++cx)
        {
            if (grid.getCell(cx, cy) >= 0.5F)
            {
                continue;
            }
            ++occupied;
            const double gx = grid.idx2x(cx), gy = grid.idx2y(cy);
            const bool wall = near(gy, -1) || near(gy, 3) || near(gx, 9);
            const bool block = gy >= -1.05 && gy <= -0.45 && gx >= 3.95 && gx <= 4.55;
            EXPECT_TRUE(wall || block) << "cell at " << gx << ", " << gy;
            EXPECT_GT(gx, -0.5) << "behind the first camera: never seen";
        }
    }
    // The left wall (scene x = 6, grid Y = 3), 3 m to the side, enters the
    // 77 deg field of view 3.75 m ahead: from there to the end wall every
    // cell next to its line is occupied, on one side or the other.
    for (double gx = 3.85; gx < 8.9; gx += 0.1)
    {
        const bool hit = grid.getPos(gx, 2.95) < 0.5F || grid.getPos(gx, 3.05) < 0.5F;
        EXPECT_TRUE(hit) << gx;
    }
    EXPECT_GT(occupied, 150U);
}

TEST(FloorPlan, refusesAnEmptyBandOrNoSurfaceInIt)
{
    emslam::sim::SurfaceSample s;
    s.position = {0, -5, 1};  // 5 m above the first camera
    s.seen_range = 1;
    FloorPlanBand band;
    EXPECT_THROW(emslam::sim::floorPlanGrid({s}, band), std::invalid_argument);
    band.max_height = 6;
    EXPECT_NO_THROW(emslam::sim::floorPlanGrid({s}, band));
    band.min_height = 7;
    EXPECT_THROW(emslam::sim::floorPlanGrid({s}, band), std::invalid_argument);
}
