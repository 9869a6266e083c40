// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/slam/DepthNoiseModel.h>
#include <emslam/stereo/StereoFrame.h>

#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <string>
#include <vector>

namespace emslam::slam
{
/** A point cloud with one grey level per point: what the mapper keeps of each
 * accepted frame to draw the final map (the entropy map holds only weighted
 * voxel centroids, without appearance).
 * \ingroup emslam_slam_grp */
struct IntensityCloud
{
    std::vector<mrpt::math::TPoint3Df> points;  //!< [m]
    std::vector<std::uint8_t> intensity;        //!< grey level of each point
    /** Standard deviation of each point's depth along its viewing ray [m]
     * (DepthNoiseModel); empty when unknown. */
    std::vector<float> sigma;

    /** Number of points. */
    std::size_t size() const { return points.size(); }
    /** No point. */
    bool empty() const { return points.empty(); }
    /** True if every point has its sigma. */
    bool hasSigma() const { return !points.empty() && sigma.size() == points.size(); }
    /** Appends `other`'s points moved by `T` (p' = T ⊕ p), with their
     * sigmas while both clouds have them (else the sigmas are dropped). */
    void appendTransformed(const IntensityCloud& other, const mrpt::poses::CPose3D& T);
    /** Heap memory used [bytes]. */
    std::size_t memoryBytes() const;
};

/** One point per occupied cell of size `cell_size` [m] (centroid, mean grey
 * level); `cell_size` ≤ 0 returns the cloud as is. Non-finite points are
 * dropped. With sigmas the points are independent observations: the
 * centroid is weighted by 1/σ² and its sigma is 1/√Σ(1/σ²).
 * \ingroup emslam_slam_grp */
IntensityCloud voxelDownsample(const IntensityCloud& cloud, double cell_size);

/** The frame's 3D points reduced to one point per occupied cell of size
 * `cell_size` [m] (centroid weighted by 1/σ², mean grey level of the points'
 * pixels), in the camera frame: bounds the memory a frame costs in the final
 * map. Each point's sigma is `noise` at its depth; a cell's sigma is that of
 * one observation (√(n / Σ 1/σ²)): neighbouring pixels of one frame share
 * their matching error, so n of them are not n independent measurements.
 * `cell_size` ≤ 0 keeps every point. \ingroup emslam_slam_grp */
IntensityCloud downsampleFrame(
    const emslam::stereo::StereoFrame& frame, double cell_size, const DepthNoiseModel& noise);

}  // namespace emslam::slam
