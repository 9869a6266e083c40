// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/slam/IntensityCloud.h>

#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <unordered_map>

namespace emslam::slam
{
/** The fused map of a live view: views come one at a time, their points are
 * summed per voxel weighted by 1/σ² (as FusedPointCloud does, without the
 * search along the rays), and a voxel is handed out once, when its fused σ
 * first falls to `max_sigma`: the points a viewer adds and keeps. One entry
 * per voxel, so the memory is that of the map, not of the sequence.
 * \ingroup emslam_slam_grp \sa FusedPointCloud */
class StreamingVoxelFusion
{
public:
    /** `voxel_size` [m] (≥ 0.001), `max_sigma` [m] (> 0; inf: a voxel is
     * handed out at its first point), `max_observation_sigma` [m]: points
     * above it are not used. */
    StreamingVoxelFusion(double voxel_size, double max_sigma, double max_observation_sigma);

    /** Adds a view (`cloud` in its camera frame, the camera at
     * `T_world_cam`; points without sigma count with σ = the voxel size)
     * and returns the voxels that became certain enough with it, world
     * frame: each one's weighted mean, grey level and fused σ. */
    IntensityCloud add(const IntensityCloud& cloud, const mrpt::poses::CPose3D& T_world_cam);

    /** The voxels holding points so far (shown or not). */
    std::size_t voxelCount() const { return m_voxels.size(); }

private:
    struct Voxel
    {
        double w{0}, x{0}, y{0}, z{0}, grey{0};
        bool handed_out{false};
    };
    double m_inv_voxel, m_voxel_size, m_max_sigma, m_max_observation_sigma;
    std::unordered_map<std::uint64_t, Voxel> m_voxels;
};

}  // namespace emslam::slam
