// SPDX-License-Identifier: BSD-3-Clause
#include "RaySearch.h"
#include "VoxelKey.h"
#include "VoxelTable.h"

#include <emslam/slam/FusedPointCloud.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace emslam::slam
{
namespace
{
struct VoxelSum
{
    double w{0}, x{0}, y{0}, z{0}, grey{0};
    std::size_t points{0};
};

/** The table of the voxels of `voxel` (voxelKey()s, or VoxelTable::EMPTY:
 * unused points); `slot[i]`: point i's slot in it, or NO_VOXEL. */
VoxelTable tableOf(
    const std::vector<std::uint64_t>& voxel, std::size_t used, std::vector<std::uint32_t>& slot)
{
    VoxelTable voxels(used / 3 + 16);  // KITTI, the hall: 0.3 voxels per point
    slot.assign(voxel.size(), NO_VOXEL);
    for (std::size_t i = 0; i < voxel.size(); ++i)
    {
        if (voxel[i] != VoxelTable::EMPTY)
        {
            slot[i] = static_cast<std::uint32_t>(voxels.insert(voxel[i]));
        }
    }
    if (voxels.capacity() >= NO_VOXEL)
    {
        throw std::length_error("FusedPointCloud: more voxels than 32-bit indices hold");
    }
    if (voxels.grown() > 0)
    {
        // Slots taken before the table grew have moved.
        for (std::size_t i = 0; i < voxel.size(); ++i)
        {
            if (voxel[i] != VoxelTable::EMPTY)
            {
                slot[i] = static_cast<std::uint32_t>(voxels.slotOf(voxel[i]));
            }
        }
    }
    return voxels;
}

/** The 1/σ²-weighted sums of the points per voxel they joined (`slot`, in
 * `voxels`), in the order the points first join them; `sum_of[i]`: the sum
 * point i joined. Counts the points that moved to another voxel. */
std::vector<VoxelSum> sumPerVoxel(
    const std::vector<std::uint32_t>& slot,
    const VoxelTable& voxels,
    const std::vector<mrpt::math::TPoint3Df>& points,
    const std::vector<float>& sigma,
    const std::vector<std::uint8_t>& grey,
    double inv_voxel,
    std::vector<std::uint32_t>& sum_of,
    std::size_t& moved_points)
{
    const std::size_t n = points.size();
    sum_of.assign(n, NO_VOXEL);
    std::vector<std::uint32_t> index_of(voxels.capacity(), NO_VOXEL);
    std::vector<VoxelSum> sums;
    for (std::size_t i = 0; i < n; ++i)
    {
        if (slot[i] == NO_VOXEL)
        {
            continue;
        }
        const auto& p = points[i];
        if (voxels.keyAt(slot[i]) != voxelKey(p.x, p.y, p.z, inv_voxel))
        {
            ++moved_points;
        }
        if (index_of[slot[i]] == NO_VOXEL)
        {
            index_of[slot[i]] = static_cast<std::uint32_t>(sums.size());
            sums.emplace_back();
        }
        VoxelSum& s = sums[index_of[slot[i]]];
        const double w = inverseVariance(sigma[i]);
        s.w += w;
        s.x += w * p.x;
        s.y += w * p.y;
        s.z += w * p.z;
        s.grey += w * grey[i];
        ++s.points;
        sum_of[i] = index_of[slot[i]];
    }
    return sums;
}

}  // namespace

FusedPointCloud::FusedPointCloud(const TOptions& o) : m_o(o)
{
    if (!(m_o.voxel_size >= 0.001) || !std::isfinite(m_o.voxel_size))
    {
        throw std::invalid_argument(
            "FusedPointCloud: voxel size " + std::to_string(m_o.voxel_size) +
            " m: must be at least 0.001 m");
    }
    if (!(m_o.max_sigma > 0) || !(m_o.max_observation_sigma > 0))
    {
        throw std::invalid_argument("FusedPointCloud: the sigma limits must be positive");
    }
    if (m_o.ray_passes < 0)
    {
        throw std::invalid_argument("FusedPointCloud: ray_passes must be >= 0");
    }
}

void FusedPointCloud::reserve(std::size_t points, std::size_t views)
{
    m_points.reserve(m_points.size() + points);
    m_sigma.reserve(m_sigma.size() + points);
    m_grey.reserve(m_grey.size() + points);
    m_view.reserve(m_view.size() + points);
    m_origins.reserve(m_origins.size() + views);
}

std::size_t FusedPointCloud::add(const IntensityCloud& cloud, const mrpt::math::TPoint3D& origin)
{
    return addPoints(cloud, origin, [](const mrpt::math::TPoint3Df& p) { return p; });
}

std::size_t FusedPointCloud::addView(
    const IntensityCloud& cloud_in_camera, const mrpt::poses::CPose3D& T_world_cam)
{
    return addPoints(
        cloud_in_camera, {T_world_cam.x(), T_world_cam.y(), T_world_cam.z()},
        [&](const mrpt::math::TPoint3Df& p)
        {
            double x = 0, y = 0, z = 0;
            T_world_cam.composePoint(p.x, p.y, p.z, x, y, z);
            return mrpt::math::TPoint3Df(
                static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
        });
}

template <typename ToWorld>
std::size_t FusedPointCloud::addPoints(
    const IntensityCloud& cloud, const mrpt::math::TPoint3D& origin, const ToWorld& to_world)
{
    const std::size_t first = m_points.size();
    const auto view = static_cast<std::uint32_t>(m_origins.size());
    m_origins.push_back(origin);
    const bool sigmas = cloud.hasSigma();
    for (std::size_t i = 0; i < cloud.size(); ++i)
    {
        m_points.push_back(to_world(cloud.points[i]));
        m_sigma.push_back(sigmas ? cloud.sigma[i] : static_cast<float>(m_o.voxel_size));
        m_grey.push_back(i < cloud.intensity.size() ? cloud.intensity[i] : 0);
        m_view.push_back(view);
    }
    return first;
}

void FusedPointCloud::fuse()
{
    const std::size_t n = m_points.size();
    const double inv_voxel = 1.0 / m_o.voxel_size;
    m_stats = {};
    m_stats.points = n;
    // The voxel each point is fused in: its own to begin with, as its slot in
    // the table of the voxels holding points (a point only ever joins one).
    std::vector<std::uint32_t> slot;
    VoxelTable voxels(0);
    {
        std::vector<std::uint64_t> voxel(n, VoxelTable::EMPTY);
        for (std::size_t i = 0; i < n; ++i)
        {
            const auto& p = m_points[i];
            if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
                std::isfinite(m_sigma[i]) && m_sigma[i] <= m_o.max_observation_sigma)
            {
                voxel[i] = voxelKey(p.x, p.y, p.z, inv_voxel);
                ++m_stats.used_points;
            }
        }
        voxels = tableOf(voxel, m_stats.used_points, slot);
    }
    // Along the rays: each pass follows the previous pass's evidence (a mean
    // shift along each ray).
    const int passes = m_o.along_rays ? m_o.ray_passes : 0;
    if (passes > 0)
    {
        assignAlongRays(
            {m_points, m_sigma, m_view, m_origins, m_o.voxel_size}, voxels, slot, passes);
    }
    std::vector<std::uint32_t> sum_of;
    const std::vector<VoxelSum> sums = sumPerVoxel(
        slot, voxels, m_points, m_sigma, m_grey, inv_voxel, sum_of, m_stats.moved_points);
    m_stats.voxels = sums.size();

    // Gate the voxels by the uncertainty left.
    m_cloud = IntensityCloud();
    std::vector<std::int32_t> kept(sums.size(), -1);
    for (std::size_t v = 0; v < sums.size(); ++v)
    {
        const VoxelSum& s = sums[v];
        const double sigma = 1.0 / std::sqrt(s.w);
        if (!(sigma <= m_o.max_sigma))
        {
            continue;
        }
        kept[v] = static_cast<std::int32_t>(m_cloud.size());
        m_cloud.points.emplace_back(
            static_cast<float>(s.x / s.w), static_cast<float>(s.y / s.w),
            static_cast<float>(s.z / s.w));
        m_cloud.intensity.push_back(
            static_cast<std::uint8_t>(std::clamp(std::lround(s.grey / s.w), 0L, 255L)));
        m_cloud.sigma.push_back(static_cast<float>(sigma));
        m_stats.kept_points += s.points;
    }
    m_stats.kept_voxels = m_cloud.size();
    m_fused_index.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i)
    {
        if (sum_of[i] != NO_VOXEL)
        {
            m_fused_index[i] = kept[sum_of[i]];
        }
    }
}

}  // namespace emslam::slam
