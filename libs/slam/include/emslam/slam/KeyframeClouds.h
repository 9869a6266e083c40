// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/slam/IntensityCloud.h>
#include <emslam/slam/KeyframeScan.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace emslam::slam
{
/** The map clouds of a run, one per keyframe in its own camera frame, so
 * that the final map places every keyframe's points at that keyframe's own
 * final pose and fuses them along that camera's rays.
 *
 * Why not one cloud per trajectory element: the rectifier's compression
 * freezes the frames of an element together, but the loop closer and its
 * polish still move every keyframe on its own. Clouds merged per element
 * kept the frozen relative poses, one camera centre for all their rays and
 * a σ shrunk by each merge, and on the hall (seed 1) left the fused map's
 * 90th-percentile error at 0.148 m against 0.079 m per keyframe.
 *
 * Memory: points whose σ is above `max_sigma` (the fusion's
 * `max_observation_sigma`: it never uses them) are not kept; the others are
 * packed in 9 bytes (16-bit coordinates scaled to the scan's farthest
 * coordinate, 16-bit σ scaled to its largest σ, the grey level) instead of
 * 17. Past `max_bytes` the clouds are thinned evenly over the run: only
 * every `stride()`-th keyframe keeps its cloud, the stride doubling each
 * time the budget is reached again. Consecutive keyframes see nearly the
 * same surfaces, so the map loses views of each surface, not surfaces, and
 * the memory and the final fusion's work stay bounded however long the run.
 * \ingroup emslam_slam_grp \sa FusedPointCloud, fuseScans() */
class KeyframeClouds
{
public:
    /** `max_sigma`: points with a larger σ (or none, or non-finite
     * coordinates) are not kept [m]; inf keeps every finite point.
     * `max_bytes`: the memory budget of the packed clouds (0: none). */
    explicit KeyframeClouds(
        double max_sigma = std::numeric_limits<double>::infinity(), std::size_t max_bytes = 0);

    /** Keeps the cloud of keyframe `frame_index`, in its camera frame, if
     * it is the stride()-th keyframe since the last one kept. */
    void append(std::size_t frame_index, const IntensityCloud& cloud);

    /** 1, or the number of keyframes per kept cloud once the budget thinned
     * them. */
    std::size_t stride() const { return m_stride; }

    /** The kept clouds, unpacked, in the order they were appended; the
     * object is left empty. */
    std::vector<KeyframeScan> takeScans();

    /** Keyframes kept. */
    std::size_t size() const { return m_scans.size(); }
    /** Points in all kept clouds. */
    std::size_t pointCount() const;
    /** Heap memory of the kept clouds [bytes]. */
    std::size_t memoryBytes() const;

private:
    /** One keyframe's cloud, packed. */
    struct PackedScan
    {
        std::size_t frame_index{0};
        std::size_t ordinal{0};  //!< keyframes appended before this one
        float scale{1};          //!< [m] per unit of `xyz`
        float sigma_scale{0};    //!< [m] per unit of `sigma` (0: no sigmas)
        std::vector<std::int16_t> xyz;
        std::vector<std::uint16_t> sigma;
        std::vector<std::uint8_t> grey;
    };

    /** Drops the clouds off the doubled stride until within the budget. */
    void thin();

    double m_max_sigma;
    std::size_t m_max_bytes;
    std::size_t m_stride{1};
    std::size_t m_appended{0};  //!< keyframes appended so far
    std::size_t m_bytes{0};     //!< memoryBytes() of the packed points
    std::vector<PackedScan> m_scans;
};

}  // namespace emslam::slam
