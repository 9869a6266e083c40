// SPDX-License-Identifier: BSD-3-Clause
#include "PoseIndex.h"

#include <emslam/slam/ScanFusion.h>

#include <stdexcept>
#include <unordered_map>

namespace emslam::slam
{
FusedPointCloud fuseScans(
    const std::vector<KeyframeScan>& scans,
    const std::vector<emslam::rectify::TimedPose>& poses,
    const FusedPointCloud::TOptions& options)
{
    const PoseIndex index = indexPoses(poses);
    FusedPointCloud fused(options);
    std::size_t points = 0;
    for (const auto& s : scans)
    {
        points += s.cloud.size();
    }
    fused.reserve(points, scans.size());
    for (const auto& s : scans)
    {
        if (const auto it = index.find(s.frame_index); it != index.end())
        {
            fused.addView(s.cloud, *it->second);
        }
    }
    fused.fuse();
    return fused;
}

std::vector<KeyframeScan> scansOnFusedSurfaces(
    const std::vector<KeyframeScan>& scans,
    const std::vector<emslam::rectify::TimedPose>& poses,
    const FusedPointCloud& fused)
{
    const PoseIndex index = indexPoses(poses);
    const IntensityCloud& map = fused.cloud();
    std::vector<KeyframeScan> out;
    std::size_t next = 0;  // the fused cloud's number of the scan's first point
    for (const auto& s : scans)
    {
        const auto it = index.find(s.frame_index);
        if (it == index.end())
        {
            continue;
        }
        if (next + s.cloud.size() > fused.pointCount())
        {
            throw std::logic_error("scansOnFusedSurfaces: the scans are not those fused");
        }
        const mrpt::poses::CPose3D& T_world_cam = *it->second;
        KeyframeScan g;
        g.frame_index = s.frame_index;
        for (std::size_t i = 0; i < s.cloud.size(); ++i, ++next)
        {
            const std::int32_t f = fused.fusedIndexOf(next);
            if (f < 0)
            {
                continue;
            }
            const auto& p = map.points[static_cast<std::size_t>(f)];
            double x = 0, y = 0, z = 0;
            T_world_cam.inverseComposePoint(p.x, p.y, p.z, x, y, z);
            g.cloud.points.emplace_back(
                static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
            g.cloud.intensity.push_back(map.intensity[static_cast<std::size_t>(f)]);
            g.cloud.sigma.push_back(map.sigma[static_cast<std::size_t>(f)]);
        }
        out.push_back(std::move(g));
    }
    if (next != fused.pointCount())
    {
        throw std::logic_error("scansOnFusedSurfaces: the scans are not those fused");
    }
    return out;
}

}  // namespace emslam::slam
