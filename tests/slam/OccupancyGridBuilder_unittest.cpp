// SPDX-License-Identifier: BSD-3-Clause
// The occupancy grid of a known room (10 m x 6 m, walls, floor and ceiling,
// points with 2 cm noise, a few strays and a wall hidden behind another)
// seen from a walk inside it: the walls it saw are its occupied cells, the
// room is free, outside is unknown.
#include <emslam/slam/OccupancyGridBuilder.h>

#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

using emslam::slam::IntensityCloud;
using emslam::slam::OccupancyGridBuilder;
using mrpt::poses::CPose3D;

namespace
{
/** The first camera 1 m above the floor (y = +1) under a 3 m ceiling
 * (y = −2); walls at x = ±3 and z = 0, 10 (first camera frame). */
struct Room
{
    IntensityCloud cloud;
    std::vector<std::pair<double, double>> wall_xz;  // noise-free wall samples
    std::vector<emslam::rectify::TimedPose> keyframes;

    Room()
    {
        std::mt19937 rng(5);
        std::normal_distribution<float> noise(0.0f, 0.02f);
        const auto add = [&](double x, double y, double z)
        {
            cloud.points.emplace_back(
                static_cast<float>(x) + noise(rng), static_cast<float>(y) + noise(rng),
                static_cast<float>(z) + noise(rng));
            cloud.intensity.push_back(128);
        };
        for (double y = -2.0; y <= 1.001; y += 0.1)
        {
            for (double z = 0.05; z < 10; z += 0.1)
            {
                add(-3, y, z);
                add(3, y, z);
                wall_xz.emplace_back(-3, z);
                wall_xz.emplace_back(3, z);
            }
            for (double x = -2.95; x < 3; x += 0.1)
            {
                add(x, y, 0);
                add(x, y, 10);
                wall_xz.emplace_back(x, 0);
                wall_xz.emplace_back(x, 10);
            }
        }
        for (double x = -2.95; x < 3; x += 0.1)
        {
            for (double z = 0.05; z < 10; z += 0.1)
            {
                add(x, 1.0, z);   // floor
                add(x, -2.0, z);  // ceiling
            }
        }
        // A wall behind the right wall, never in sight.
        for (double y = -0.5; y <= 0.001; y += 0.1)
        {
            for (double z = 2.05; z < 8; z += 0.1)
            {
                add(3.6, y, z);
            }
        }
        // Strays inside the room at obstacle height: one point each.
        for (int i = 0; i < 20; ++i)
        {
            add(-2 + 0.2 * i, 0.0, 3 + 0.2 * i);
        }
        // A walk down the middle and back, then looking at each side wall.
        const auto yaw = [](double deg) { return mrpt::DEG2RAD(deg); };
        for (double z = 1; z <= 9; z += 1)
        {
            keyframes.push_back({0, 0, CPose3D(0, 0, z, 0, 0, 0)});         // +z
            keyframes.push_back({0, 0, CPose3D(0, 0, z, 0, yaw(180), 0)});  // -z
            keyframes.push_back({0, 0, CPose3D(0, 0, z, 0, yaw(90), 0)});   // +x
            keyframes.push_back({0, 0, CPose3D(0, 0, z, 0, yaw(-90), 0)});  // -x
        }
    }
};

std::pair<int, int> cellOf(const mrpt::maps::COccupancyGridMap2D& g, double x, double z)
{
    const auto q = OccupancyGridBuilder::gridPoint({x, 0, z});
    return {g.x2idx(q.x), g.y2idx(q.y)};
}

bool isOccupied(const mrpt::maps::COccupancyGridMap2D& g, int cx, int cy)
{
    return g.getCell(cx, cy) < 0.2f;
}
}  // namespace

TEST(OccupancyGridBuilder, theWallsAreOccupiedTheRoomFreeAndOutsideUnknown)
{
    const Room room;
    OccupancyGridBuilder builder{OccupancyGridBuilder::TParameters{}};
    const auto grid = builder.build(room.cloud, room.keyframes);
    EXPECT_NEAR(grid.getResolution(), 0.1, 1e-6);

    // Occupied cells against the cells of the true walls: F1, a cell counting
    // as right within one cell of the other set (a wall on a cell border
    // lands on either side of it).
    std::set<std::pair<int, int>> truth, found;
    for (const auto& [x, z] : room.wall_xz)
    {
        truth.insert(cellOf(grid, x, z));
    }
    for (int cy = 0; cy < static_cast<int>(grid.getSizeY()); ++cy)
    {
        for (int cx = 0; cx < static_cast<int>(grid.getSizeX()); ++cx)
        {
            if (isOccupied(grid, cx, cy))
            {
                found.insert({cx, cy});
            }
        }
    }
    const auto near = [](const std::set<std::pair<int, int>>& in, std::pair<int, int> c)
    {
        for (int dy = -1; dy <= 1; ++dy)
        {
            for (int dx = -1; dx <= 1; ++dx)
            {
                if (in.count({c.first + dx, c.second + dy}))
                {
                    return true;
                }
            }
        }
        return false;
    };
    std::size_t right = 0, recalled = 0;
    for (const auto& c : found)
    {
        right += near(truth, c);
    }
    for (const auto& c : truth)
    {
        recalled += near(found, c);
    }
    const double precision = double(right) / double(found.size());
    const double recall = double(recalled) / double(truth.size());
    const double f1 = 2 * precision * recall / (precision + recall);
    std::printf(
        "occupied %zu (true %zu), precision %.3f recall %.3f F1 %.3f; free %zu, rays %zu\n",
        found.size(), truth.size(), precision, recall, f1, builder.stats().free,
        builder.stats().rays);
    EXPECT_GE(f1, 0.85);
    EXPECT_EQ(builder.stats().occupied, found.size());
    EXPECT_LE(found.size(), 2 * truth.size() + truth.size() / 5);  // walls at most 2 cells thick

    // Floor and ceiling are outside the height band; the strays are single points.
    const auto [mx, my] = cellOf(grid, 0.55, 5.05);
    EXPECT_GT(grid.getCell(mx, my), 0.9f);  // free: seen through
    const auto [sx, sy] = cellOf(grid, -1.0, 4.0);
    EXPECT_FALSE(isOccupied(grid, sx, sy));
    // Behind the walls no ray goes: unknown, even where points are.
    const auto [ox, oy] = cellOf(grid, 3.15, 5.0);
    EXPECT_FLOAT_EQ(grid.getCell(ox, oy), 0.5f);
    const auto [bx, by] = cellOf(grid, 3.6, 5.05);
    EXPECT_FLOAT_EQ(grid.getCell(bx, by), 0.5f);
    // The grid is seen from above: +X forward (z), +Y left (−x).
    const auto [fx, fy] = cellOf(grid, 0, 9.5);
    const auto [lx, ly] = cellOf(grid, -2.5, 5);
    EXPECT_GT(fx, mx);
    EXPECT_GT(ly, my);
    EXPECT_EQ(lx, cellOf(grid, 0, 5).first);
}

TEST(OccupancyGridBuilder, aNarrowViewSeesOnlyAheadAndBadParametersAreRefused)
{
    const Room room;
    OccupancyGridBuilder::TParameters p;
    p.fov_deg = 20;
    OccupancyGridBuilder builder(p);
    // One keyframe at the room's middle looking forward (+z).
    const auto grid = builder.build(room.cloud, {{0, 0, CPose3D(0, 0, 5, 0, 0, 0)}});
    const auto ahead = cellOf(grid, 0, 8);
    const auto behind = cellOf(grid, 0, 2);
    const auto aside = cellOf(grid, 2, 5.5);
    EXPECT_GT(grid.getCell(ahead.first, ahead.second), 0.9f);
    EXPECT_FLOAT_EQ(grid.getCell(behind.first, behind.second), 0.5f);
    EXPECT_FLOAT_EQ(grid.getCell(aside.first, aside.second), 0.5f);
    EXPECT_EQ(
        builder.stats().rays,
        1u + static_cast<std::size_t>(std::ceil(mrpt::DEG2RAD(20.0) * p.max_range / p.cell_size)));

    for (const auto& [field, value] :
         std::vector<std::pair<double OccupancyGridBuilder::TParameters::*, double>>{
             {&OccupancyGridBuilder::TParameters::cell_size, -0.1},
             {&OccupancyGridBuilder::TParameters::cell_size, 0.001},
             {&OccupancyGridBuilder::TParameters::max_height, -1.0},
             {&OccupancyGridBuilder::TParameters::fov_deg, 0},
             {&OccupancyGridBuilder::TParameters::max_range, std::nan("")}})
    {
        OccupancyGridBuilder::TParameters bad;
        bad.*field = value;
        EXPECT_THROW(bad.validate(), std::invalid_argument) << value;
    }
    OccupancyGridBuilder::TParameters off;
    off.cell_size = 0;
    EXPECT_THROW(OccupancyGridBuilder(off).build(room.cloud, {}), std::invalid_argument);
}
