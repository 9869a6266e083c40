// SPDX-License-Identifier: BSD-3-Clause
#include "VoxelKey.h"

#include <emslam/slam/StreamingVoxelFusion.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace emslam::slam
{
StreamingVoxelFusion::StreamingVoxelFusion(
    double voxel_size, double max_sigma, double max_observation_sigma)
    : m_inv_voxel(1.0 / voxel_size),
      m_voxel_size(voxel_size),
      m_max_sigma(max_sigma),
      m_max_observation_sigma(max_observation_sigma)
{
    if (!(voxel_size >= 0.001) || !std::isfinite(voxel_size) || !(max_sigma > 0) ||
        !(max_observation_sigma > 0))
    {
        throw std::invalid_argument(
            "StreamingVoxelFusion: voxel size " + std::to_string(voxel_size) +
            " m must be >= 0.001 m and the sigma limits positive");
    }
}

IntensityCloud StreamingVoxelFusion::add(
    const IntensityCloud& cloud, const mrpt::poses::CPose3D& T_world_cam)
{
    const bool sigmas = cloud.hasSigma();
    std::vector<std::uint64_t> touched;
    for (std::size_t i = 0; i < cloud.size(); ++i)
    {
        const double sigma = sigmas ? cloud.sigma[i] : m_voxel_size;
        const auto& c = cloud.points[i];
        if (!(sigma <= m_max_observation_sigma) || !std::isfinite(c.x) || !std::isfinite(c.y) ||
            !std::isfinite(c.z))
        {
            continue;
        }
        double x = 0, y = 0, z = 0;
        T_world_cam.composePoint(c.x, c.y, c.z, x, y, z);
        const std::uint64_t key = voxelKey(x, y, z, m_inv_voxel);
        Voxel& v = m_voxels[key];
        if (v.handed_out)
        {
            continue;  // the viewer keeps the point it was given
        }
        const double s = std::max(sigma, 1e-3);
        const double w = 1.0 / (s * s);
        v.w += w;
        v.x += w * x;
        v.y += w * y;
        v.z += w * z;
        v.grey += w * (i < cloud.intensity.size() ? cloud.intensity[i] : 0);
        touched.push_back(key);
    }
    IntensityCloud out;
    for (const std::uint64_t key : touched)
    {
        Voxel& v = m_voxels[key];
        const double sigma = 1.0 / std::sqrt(v.w);
        if (v.handed_out || !(sigma <= m_max_sigma))
        {
            continue;
        }
        v.handed_out = true;
        out.points.emplace_back(
            static_cast<float>(v.x / v.w), static_cast<float>(v.y / v.w),
            static_cast<float>(v.z / v.w));
        out.intensity.push_back(
            static_cast<std::uint8_t>(std::clamp(std::lround(v.grey / v.w), 0L, 255L)));
        out.sigma.push_back(static_cast<float>(sigma));
    }
    return out;
}

}  // namespace emslam::slam
