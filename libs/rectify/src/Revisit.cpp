// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/maps/WeightedHistogram.h>
#include <emslam/rectify/Revisit.h>

#include <cmath>
#include <unordered_map>
#include <vector>

namespace emslam::rectify
{
bool revisitsAPlace(const Trajectory& t)
{
    const std::size_t n = t.size();
    if (n < 3)
    {
        return false;
    }
    // Path length at every original frame, and where each element's frames
    // begin and end on it: a compressed element spans many frames.
    const std::vector<TimedPose> frames = t.framePoses();
    std::vector<double> path(frames.size(), 0.0);
    for (std::size_t k = 1; k < frames.size(); ++k)
    {
        path[k] = path[k - 1] + (frames[k].T_world_frame.translation() -
                                 frames[k - 1].T_world_frame.translation())
                                    .norm();
    }
    std::vector<double> path_begin(n), path_end(n);
    for (std::size_t i = 0, k = 0; i < n; ++i)
    {
        path_begin[i] = path[k];
        k += t.framesOf(i).size();
        path_end[i] = path[k - 1];
    }
    const auto& map = t.map();
    const double cell = map.creationOptions().cell_size;
    // Two frames that see one cell are at most this far apart.
    const double covisible = 2.0 * t.viewRange() + std::sqrt(3.0) * cell;
    // Per cell, the first and the last element that put a point in it: the
    // pair farthest apart along the path.
    struct Span
    {
        std::size_t first, last;
    };
    std::unordered_map<std::uint64_t, Span> cells;
    const double inv = 1.0 / cell;
    for (std::size_t i = 0; i < n; ++i)
    {
        const auto& pose = t.pose(i);
        for (const auto& p : map.observationCloud(i).points)
        {
            double x = 0, y = 0, z = 0;
            pose.composePoint(p.x, p.y, p.z, x, y, z);
            const auto key = emslam::maps::packCellKey(
                static_cast<std::int32_t>(std::floor(x * inv)),
                static_cast<std::int32_t>(std::floor(y * inv)),
                static_cast<std::int32_t>(std::floor(z * inv)));
            const auto [it, is_new] = cells.try_emplace(key, Span{i, i});
            if (!is_new && it->second.last != i)
            {
                it->second.last = i;
                if (path_begin[i] - path_end[it->second.first] > covisible)
                {
                    return true;
                }
            }
        }
    }
    return false;
}

}  // namespace emslam::rectify
