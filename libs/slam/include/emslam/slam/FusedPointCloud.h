// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/slam/IntensityCloud.h>

#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace emslam::slam
{
/** The map's points of many views fused into one point per voxel, each
 * weighted by its depth uncertainty, and gated by the uncertainty left.
 *
 * Every point comes with σ, the standard deviation of its depth along its
 * viewing ray (DepthNoiseModel), and the position of the camera that saw it.
 * Points of several views falling in one voxel become one point at their
 * mean weighted by 1/σ², with σ_fused = 1/√Σ(1/σ²): n views of equal σ give
 * σ/√n. A voxel whose σ_fused is above `max_sigma` is dropped, and so is
 * every point whose own σ is above `max_observation_sigma` before fusion.
 *
 * **Along the rays.** Depth noise moves a point along its ray, so the points
 * of one surface seen from afar spread over several voxels in depth, and
 * fusing per voxel alone leaves that spread in the map (a wall seen from 4 m
 * with σ = 0.2 m spans ±2 voxels of 0.1 m). With `along_rays`, each point
 * joins the voxel along its own ray, within ±2σ of where it was measured,
 * that holds the most evidence (the largest Σ 1/σ² of the points there;
 * nearer voxels are preferred softly, by exp(−t²/2(2σ)²), so that ties stay
 * near): the precise views of a surface, or the centre of many imprecise
 * ones, gather the points that may belong to it. The joined voxel's point is the
 * weighted mean of its points where they were measured, so symmetric noise
 * averages out instead of being moved. `ray_passes` repeats the assignment
 * with the evidence of the previous one (a mean shift along each ray; a
 * wall seen 40 times with σ = 1.5 voxels settles in 3 to 4 passes).
 *
 * Usage: add() every view, then fuse(); cloud() is the map, and
 * fusedIndexOf() tells which fused point each added point became (−1:
 * dropped), e.g. to insert the views as scans ending on the fused surfaces.
 * \ingroup emslam_slam_grp \sa DepthNoiseModel, KeyframeClouds */
class FusedPointCloud
{
public:
    /** How the points are fused (the `[EntropySlam]` keys `fused_voxel_size`,
     * `max_point_sigma`, `max_observation_sigma`, `fuse_along_rays`). */
    struct TOptions
    {
        double voxel_size{0.1};  //!< [m] one fused point per voxel
        /** [m] voxels whose fused σ is above this are dropped (inf: none). */
        double max_sigma{std::numeric_limits<double>::infinity()};
        /** [m] points whose own σ is above this are not used (inf: all). */
        double max_observation_sigma{std::numeric_limits<double>::infinity()};
        bool along_rays{true};  //!< join the strongest voxel along each ray
        int ray_passes{4};      //!< assignments along the rays (with along_rays)
    };

    /** What fuse() counted. */
    struct Stats
    {
        std::size_t points{0};        //!< added
        std::size_t used_points{0};   //!< finite, σ within max_observation_sigma
        std::size_t moved_points{0};  //!< joined another voxel along their ray
        std::size_t voxels{0};        //!< voxels holding used points
        std::size_t kept_voxels{0};   //!< within max_sigma: cloud().size()
        std::size_t kept_points{0};   //!< used points of the kept voxels
    };

    /** Throws std::invalid_argument for a voxel below 1 mm, a σ limit not
     * above 0 or negative ray_passes. */
    explicit FusedPointCloud(const TOptions& o);

    /** Adds the points of one view, in the world frame, seen from `origin`.
     * Without sigmas (`cloud.hasSigma()` false) each point counts with σ =
     * the voxel size. Returns the index of its first point (points are
     * numbered in the order they are added). */
    std::size_t add(const IntensityCloud& cloud, const mrpt::math::TPoint3D& origin);
    /** Makes room for `points` more points in `views` more views (add() and
     * addView() then never copy what was added). */
    void reserve(std::size_t points, std::size_t views);
    /** Adds a view given in its camera frame, the camera at `T_world_cam`. */
    std::size_t addView(
        const IntensityCloud& cloud_in_camera, const mrpt::poses::CPose3D& T_world_cam);

    /** Fuses the points added so far (again, if called again). */
    void fuse();

    /** The fused points, world frame; their sigma is the fused σ. */
    const IntensityCloud& cloud() const { return m_cloud; }
    /** The index in cloud() of the fused point that added point `i` became,
     * or −1 if it was dropped (unused, or its voxel gated). */
    std::int32_t fusedIndexOf(std::size_t i) const { return m_fused_index.at(i); }
    /** The points added so far. */
    std::size_t pointCount() const { return m_points.size(); }
    /** What the last fuse() counted. */
    const Stats& stats() const { return m_stats; }

private:
    /** add() of `cloud`'s points mapped by `to_world`. */
    template <typename ToWorld>
    std::size_t addPoints(
        const IntensityCloud& cloud, const mrpt::math::TPoint3D& origin, const ToWorld& to_world);

    TOptions m_o;
    std::vector<mrpt::math::TPoint3Df> m_points;
    std::vector<float> m_sigma;
    std::vector<std::uint8_t> m_grey;
    std::vector<std::uint32_t> m_view;  //!< index in m_origins of each point
    std::vector<mrpt::math::TPoint3D> m_origins;
    std::vector<std::int32_t> m_fused_index;
    IntensityCloud m_cloud;
    Stats m_stats;
};

}  // namespace emslam::slam
