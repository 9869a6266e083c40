// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/maps/WeightedHistogram.h>
#include <emslam/maps/WeightedPointCloud.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace emslam::maps
{
double WeightedPointCloud::totalWeight() const
{
    double s = 0;
    for (float w : weights)
    {
        s += w;
    }
    return s;
}

bool WeightedPointCloud::hasIntegralWeights() const
{
    constexpr float MAX_W = 16777216.0f;  // 2^24: every integer below is a float
    for (float w : weights)
    {
        if (!(w >= 0 && w <= MAX_W && static_cast<float>(static_cast<std::int32_t>(w)) == w))
        {
            return false;
        }
    }
    return true;
}

void sortByCell(WeightedPointCloud& cloud, double cell_size)
{
    ASSERTMSG_(cell_size > 0, "sortByCell(): cell_size must be > 0");
    ASSERTMSG_(cloud.weights.size() == cloud.points.size(), "sortByCell(): one weight per point");
    const double inv = 1.0 / cell_size;
    std::vector<std::pair<std::uint64_t, std::size_t>> order(cloud.size());
    for (std::size_t i = 0; i < cloud.size(); i++)
    {
        const auto& p = cloud.points[i];
        order[i] = {
            packCellKey(
                static_cast<std::int32_t>(std::floor(p.x * inv)),
                static_cast<std::int32_t>(std::floor(p.y * inv)),
                static_cast<std::int32_t>(std::floor(p.z * inv))),
            i};
    }
    std::stable_sort(
        order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    WeightedPointCloud sorted;
    sorted.points.reserve(cloud.size());
    sorted.weights.reserve(cloud.size());
    for (const auto& [key, i] : order)
    {
        sorted.push_back(cloud.points[i], cloud.weights[i]);
    }
    cloud = std::move(sorted);
}

WeightedPointCloud simplifyCloud(
    const std::vector<mrpt::math::TPoint3Df>& points,
    const std::vector<float>& weights,
    double cell_size)
{
    ASSERTMSG_(cell_size > 0, "simplifyCloud(): cell_size must be > 0");
    ASSERTMSG_(
        weights.empty() || weights.size() == points.size(),
        "simplifyCloud(): weights must be empty or have one entry per point");
    WeightedPointCloud out;
    if (points.empty())
    {
        return out;
    }
    // Bounding box (finite points only).
    double mn[3] = {
        std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
        std::numeric_limits<double>::max()};
    for (const auto& p : points)
    {
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
        {
            mn[0] = std::min<double>(mn[0], p.x);
            mn[1] = std::min<double>(mn[1], p.y);
            mn[2] = std::min<double>(mn[2], p.z);
        }
    }
    // Accumulators per occupied cell. Run once per inserted observation, not
    // in the rectifier's loop: std::unordered_map (reserved) is fine here.
    struct Acc
    {
        double sx{0}, sy{0}, sz{0}, w{0};
        std::uint64_t key{0};
    };
    std::vector<Acc> acc;
    std::unordered_map<std::uint64_t, std::size_t> index;
    index.reserve(points.size() / 4 + 16);
    const double inv = 1.0 / cell_size;
    for (std::size_t i = 0; i < points.size(); i++)
    {
        const auto& p = points[i];
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
        {
            continue;
        }
        const double w = weights.empty() ? 1.0 : static_cast<double>(weights[i]);
        if (!(w > 0))
        {
            continue;
        }
        const auto cx = static_cast<std::int32_t>((p.x - mn[0]) * inv);
        const auto cy = static_cast<std::int32_t>((p.y - mn[1]) * inv);
        const auto cz = static_cast<std::int32_t>((p.z - mn[2]) * inv);
        const std::uint64_t key = packCellKey(cx, cy, cz);
        auto [it, is_new] = index.try_emplace(key, acc.size());
        if (is_new)
        {
            acc.emplace_back();
            acc.back().key = key;
        }
        Acc& a = acc[it->second];
        a.sx += w * p.x;
        a.sy += w * p.y;
        a.sz += w * p.z;
        a.w += w;
    }
    std::sort(acc.begin(), acc.end(), [](const Acc& a, const Acc& b) { return a.key < b.key; });
    out.points.reserve(acc.size());
    out.weights.reserve(acc.size());
    for (const auto& a : acc)
    {
        out.push_back(
            mrpt::math::TPoint3Df(
                static_cast<float>(a.sx / a.w), static_cast<float>(a.sy / a.w),
                static_cast<float>(a.sz / a.w)),
            static_cast<float>(a.w));
    }
    return out;
}

}  // namespace emslam::maps
