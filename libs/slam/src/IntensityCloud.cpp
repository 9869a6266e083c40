// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/IntensityCloud.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <unordered_map>

namespace emslam::slam
{
void IntensityCloud::appendTransformed(const IntensityCloud& other, const mrpt::poses::CPose3D& T)
{
    // Grow geometrically: reserving exactly the new size on every call made
    // appending N frames cost O(N^2) (a fresh allocation, page faults and a
    // copy of the whole map per frame: ~2 min on the hall at the end of a run).
    const std::size_t need = points.size() + other.size();
    if (need > points.capacity())
    {
        points.reserve(std::max(need, 2 * points.capacity()));
    }
    for (const auto& p : other.points)
    {
        double x = 0, y = 0, z = 0;
        T.composePoint(p.x, p.y, p.z, x, y, z);
        points.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
    }
    intensity.insert(intensity.end(), other.intensity.begin(), other.intensity.end());
}

std::size_t IntensityCloud::memoryBytes() const
{
    return points.capacity() * sizeof(mrpt::math::TPoint3Df) + intensity.capacity();
}

namespace
{
struct CellSum
{
    double x{0}, y{0}, z{0}, grey{0};
    int n{0};
};

std::uint64_t cellKey(const mrpt::math::TPoint3Df& p, double inv_cell)
{
    // 21 bits per axis: ±10^6 cells, far beyond any stereo range.
    const auto k = [&](float v)
    {
        return static_cast<std::uint64_t>(
                   static_cast<std::int64_t>(std::floor(v * inv_cell)) + (1 << 20)) &
               0x1FFFFF;
    };
    return (k(p.x) << 42) | (k(p.y) << 21) | k(p.z);
}
}  // namespace

IntensityCloud voxelDownsample(const IntensityCloud& cloud, double cell_size)
{
    if (cell_size <= 0)
    {
        return cloud;
    }
    const double inv_cell = 1.0 / cell_size;
    std::unordered_map<std::uint64_t, CellSum> cells;
    cells.reserve(cloud.size() / 4 + 16);
    for (std::size_t i = 0; i < cloud.size(); ++i)
    {
        const auto& p = cloud.points[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        {
            continue;
        }
        CellSum& c = cells[cellKey(p, inv_cell)];
        c.x += p.x;
        c.y += p.y;
        c.z += p.z;
        c.grey += cloud.intensity[i];
        ++c.n;
    }
    IntensityCloud out;
    out.points.reserve(cells.size());
    out.intensity.reserve(cells.size());
    for (const auto& [key, c] : cells)
    {
        const double n = c.n;
        out.points.emplace_back(
            static_cast<float>(c.x / n), static_cast<float>(c.y / n), static_cast<float>(c.z / n));
        out.intensity.push_back(static_cast<std::uint8_t>(std::lround(c.grey / n)));
    }
    return out;
}

IntensityCloud downsampleFrame(const emslam::stereo::StereoFrame& frame, double cell_size)
{
    IntensityCloud all;
    all.points = frame.points;
    all.intensity.reserve(frame.size());
    for (std::size_t i = 0; i < frame.size(); ++i)
    {
        all.intensity.push_back(
            frame.intensity.at<std::uint8_t>(frame.pixels[i].v, frame.pixels[i].u));
    }
    return voxelDownsample(all, cell_size);
}

}  // namespace emslam::slam
