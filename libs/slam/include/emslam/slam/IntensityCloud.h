// SPDX-License-Identifier: BSD-3-Clause
#pragma once

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

    /** Number of points. */
    std::size_t size() const { return points.size(); }
    /** No point. */
    bool empty() const { return points.empty(); }
    /** Appends `other`'s points moved by `T` (p' = T ⊕ p). */
    void appendTransformed(const IntensityCloud& other, const mrpt::poses::CPose3D& T);
    /** Heap memory used [bytes]. */
    std::size_t memoryBytes() const;
};

/** One point per occupied cell of size `cell_size` [m] (centroid, mean grey
 * level); `cell_size` ≤ 0 returns the cloud as is. Non-finite points are
 * dropped. \ingroup emslam_slam_grp */
IntensityCloud voxelDownsample(const IntensityCloud& cloud, double cell_size);

/** The frame's 3D points reduced to one point per occupied cell of size
 * `cell_size` [m] (centroid, mean grey level of the points' pixels), in the
 * camera frame: bounds the memory a frame costs in the final map.
 * `cell_size` ≤ 0 keeps every point. \ingroup emslam_slam_grp */
IntensityCloud downsampleFrame(const emslam::stereo::StereoFrame& frame, double cell_size);

}  // namespace emslam::slam
