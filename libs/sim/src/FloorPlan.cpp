// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/sim/FloorPlan.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace emslam::sim
{
mrpt::maps::COccupancyGridMap2D floorPlanGrid(
    const std::vector<SurfaceSample>& seen, const FloorPlanBand& band)
{
    if (!(band.cell_size > 0) || !(band.min_height < band.max_height))
    {
        throw std::invalid_argument(
            "floorPlanGrid: the cell size must be > 0 and min_height < max_height");
    }
    // Grid coordinates (forward z, left −x) of the samples in the band.
    std::vector<std::pair<double, double>> cells;
    double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
    for (const auto& s : seen)
    {
        const double height = -s.position[1];
        if (height < band.min_height || height > band.max_height || s.seen_range > band.max_range)
        {
            continue;
        }
        const double gx = s.position[2], gy = -s.position[0];
        cells.emplace_back(gx, gy);
        x0 = std::min(x0, gx);
        x1 = std::max(x1, gx);
        y0 = std::min(y0, gy);
        y1 = std::max(y1, gy);
    }
    if (cells.empty())
    {
        throw std::invalid_argument("floorPlanGrid: no surface seen inside the height band");
    }
    const double margin = 2 * band.cell_size;
    mrpt::maps::COccupancyGridMap2D grid;
    grid.setSize(
        static_cast<float>(x0 - margin), static_cast<float>(x1 + margin),
        static_cast<float>(y0 - margin), static_cast<float>(y1 + margin),
        static_cast<float>(band.cell_size), 1.0F);  // MRPT cells hold P(free)
    for (const auto& [gx, gy] : cells)
    {
        const int cx = grid.x2idx(gx), cy = grid.y2idx(gy);
        if (cx >= 0 && cy >= 0 && static_cast<unsigned>(cx) < grid.getSizeX() &&
            static_cast<unsigned>(cy) < grid.getSizeY())
        {
            grid.setCell(cx, cy, 0.0F);
        }
    }
    return grid;
}

}  // namespace emslam::sim
