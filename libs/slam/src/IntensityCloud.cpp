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
    const bool sigmas = sigma.size() + other.size() == need && other.sigma.size() == other.size();
    if (sigmas)
    {
        sigma.insert(sigma.end(), other.sigma.begin(), other.sigma.end());
    }
    else
    {
        sigma.clear();
    }
    intensity.insert(intensity.end(), other.intensity.begin(), other.intensity.end());
}

std::size_t IntensityCloud::memoryBytes() const
{
    return points.capacity() * sizeof(mrpt::math::TPoint3Df) + intensity.capacity() +
           sigma.capacity() * sizeof(float);
}

namespace
{
struct CellSum
{
    double x{0}, y{0}, z{0}, grey{0};
    double w{0};  //!< sum of the points' weights (1/σ², or 1 each without sigmas)
    int n{0};
};

/** How the sigma of a cell follows from its points'. */
enum class CellSigma
{
    INDEPENDENT,     //!< n independent observations: 1/√Σw
    ONE_OBSERVATION  //!< correlated points of one view: √(n/Σw)
};

/** A point's weight from its sigma; a sigma of 0 counts as 1 mm. */
double weightOf(float sigma)
{
    const double s = std::max(static_cast<double>(sigma), 1e-3);
    return 1.0 / (s * s);
}

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

IntensityCloud downsampleCells(const IntensityCloud& cloud, double cell_size, CellSigma mode)
{
    const bool weighted = cloud.hasSigma();
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
        const double w = weighted ? weightOf(cloud.sigma[i]) : 1.0;
        CellSum& c = cells[cellKey(p, inv_cell)];
        c.x += w * p.x;
        c.y += w * p.y;
        c.z += w * p.z;
        c.grey += w * cloud.intensity[i];
        c.w += w;
        ++c.n;
    }
    IntensityCloud out;
    out.points.reserve(cells.size());
    out.intensity.reserve(cells.size());
    if (weighted)
    {
        out.sigma.reserve(cells.size());
    }
    for (const auto& [key, c] : cells)
    {
        out.points.emplace_back(
            static_cast<float>(c.x / c.w), static_cast<float>(c.y / c.w),
            static_cast<float>(c.z / c.w));
        out.intensity.push_back(static_cast<std::uint8_t>(std::lround(c.grey / c.w)));
        if (weighted)
        {
            const double var = mode == CellSigma::INDEPENDENT ? 1.0 / c.w : c.n / c.w;
            out.sigma.push_back(static_cast<float>(std::sqrt(var)));
        }
    }
    return out;
}
}  // namespace

IntensityCloud voxelDownsample(const IntensityCloud& cloud, double cell_size)
{
    if (cell_size <= 0)
    {
        return cloud;
    }
    return downsampleCells(cloud, cell_size, CellSigma::INDEPENDENT);
}

IntensityCloud downsampleFrame(
    const emslam::stereo::StereoFrame& frame, double cell_size, const DepthNoiseModel& noise)
{
    IntensityCloud all;
    all.points = frame.points;
    all.intensity.reserve(frame.size());
    all.sigma.reserve(frame.size());
    for (std::size_t i = 0; i < frame.size(); ++i)
    {
        all.intensity.push_back(
            frame.intensity.at<std::uint8_t>(frame.pixels[i].v, frame.pixels[i].u));
        all.sigma.push_back(static_cast<float>(noise.sigmaAt(frame.points[i].z)));
    }
    if (cell_size <= 0)
    {
        return all;
    }
    return downsampleCells(all, cell_size, CellSigma::ONE_OBSERVATION);
}

}  // namespace emslam::slam
