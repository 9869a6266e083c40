// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/Trajectory.h>
#include <emslam/slam/IntensityCloud.h>

#include <cstddef>
#include <vector>

namespace emslam::slam
{
/** The map cloud of a run (what map.ply shows) kept per trajectory element, so
 * that its memory is bounded by the trajectory rather than by the sequence.
 *
 * It follows the rectifier's trajectory (emslam::rectify::Trajectory): every
 * accepted frame is appended as a new element with its cloud in its camera
 * frame, and whenever the elements exceed N_max the pairs (2i, 2i+1) are
 * fused, as Trajectory::compress() fuses them after the same append. Once
 * fused, the frames of an element never move relative to one another, so the
 * clouds of a fused element are brought into its first frame with those
 * relative poses and downsampled again at the cell size: one cloud per
 * element, each covering the part of the map its frames saw.
 *
 * The relative poses are read from the trajectory's frame poses
 * (RectificationRunner::framePoses()) once it has compressed too: an AnyTime
 * runner compresses only when it synchronises, so until then the element
 * keeps its frames' clouds apart (see fuse()).
 *
 * worldCloud() places each cloud at the final pose of its frame. For a run
 * without compression it gives exactly the union of the per-frame clouds; with
 * compression the points of fused frames were averaged once more per fusion
 * (in the element's first camera frame) before the final downsampling.
 * \ingroup emslam_slam_grp \sa EntropySlam, emslam::rectify::Trajectory::compress() */
class ElementClouds
{
public:
    /** `n_max`: the trajectory's N_max (0: never compressed); `cell_size`:
     * the downsampling cell of fused clouds and of worldCloud() [m] (≤ 0: every
     * point is kept, and fusing saves nothing). */
    ElementClouds(std::size_t n_max, double cell_size);

    /** Appends an accepted frame as a new element, `cloud` in its camera
     * frame, then compresses as the trajectory does after the same append
     * (more than N_max elements: pairs are fused). */
    void append(std::size_t frame_index, IntensityCloud cloud);

    /** True while some element still holds the clouds of several frames
     * apart (its fusion waits for the trajectory's compression). */
    bool hasPendingFusions() const;

    /** Fuses the clouds of every element the trajectory has compressed too:
     * `poses` are the world poses of the trajectory's frames (any state of
     * rectification: only poses relative to an element's first frame are
     * used, and compression freezes them). An element waits while the frame
     * whose append made it fuse is not in `poses`. */
    void fuse(const std::vector<emslam::rectify::TimedPose>& poses);

    /** The union of the clouds, each placed at its frame's pose in `poses`
     * (world frame), downsampled at the cell size. Throws std::logic_error
     * if a frame has no pose. */
    IntensityCloud worldCloud(const std::vector<emslam::rectify::TimedPose>& poses) const;

    /** A stored cloud in the camera frame of `frame_index` (an element's
     * first frame once fused): what that camera saw, a scan from its pose. */
    struct Scan
    {
        std::size_t frame_index{0};
        IntensityCloud cloud;
    };
    /** Moves every stored cloud out (the elements are left empty). */
    std::vector<Scan> takeScans();
    /** Throws std::logic_error unless the elements hold the same frames as
     * those of `t` (their number, and each one's first frame and count). */
    void requireSameElementsAs(const emslam::rectify::Trajectory& t) const;

    /** Elements (N of the trajectory after the same appends). */
    std::size_t elementCount() const { return m_elements.size(); }
    /** Clouds stored: elementCount() once every pending fusion is done. */
    std::size_t cloudCount() const;
    /** Points in all stored clouds. */
    std::size_t pointCount() const;
    /** Heap memory of the stored clouds [bytes]. */
    std::size_t memoryBytes() const;

private:
    /** The cloud of one frame, or of several fused into the first one. */
    struct FrameCloud
    {
        std::size_t frame_index{0};  //!< the frame the points are expressed in
        IntensityCloud cloud;
    };
    /** One trajectory element: consecutive accepted frames. */
    struct Element
    {
        std::size_t first_frame{0};  //!< the element's frame (its first frame)
        std::size_t frame_count{1};  //!< frames fused into it
        /** The frame whose append last fused this element: its pairs' poses
         * are frozen once the trajectory holds that frame. */
        std::size_t fused_at{0};
        std::vector<FrameCloud> clouds;  //!< first: clouds[0].frame_index == first_frame
    };

    /** Trajectory compression of the elements (clouds kept apart). */
    void compress(std::size_t trigger_frame);

    std::size_t m_n_max;
    double m_cell_size;
    std::vector<Element> m_elements;
};

}  // namespace emslam::slam
