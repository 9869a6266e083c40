// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/maps/CEntropyVoxelMap.h>
#include <emslam/maps/WeightedPointCloud.h>
#include <emslam/rectify/RectificationStats.h>
#include <emslam/rectify/RectifierOptions.h>
#include <emslam/rectify/Trajectory.h>

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

namespace emslam::rectify
{
/** Drives global rectification as frames arrive, in serial or AnyTime mode
 * (§2.2.3), with trajectory compression (§2.2.4) whenever N > N_max. The
 * caller feeds accepted frames (after space sampling) and reads the
 * trajectory at the end.
 *
 * - Serial: addFrame() appends; every S_rec accepted frames it rectifies to
 *   convergence before returning (the robot waits).
 * - AnyTime: a second thread runs rectification attempts continuously on the
 *   trajectory; addFrame() only fills a buffer and, every S_buf frames,
 *   synchronises (pauses the thread between two attempts, appends the
 *   buffer, compresses if needed, resumes). The thread idles while the map is
 *   stable (NC_max consecutive failures) and no frames are waiting.
 *
 * finish() ends either mode with one last rectification to convergence.
 * \ingroup emslam_rectify_grp */
class RectificationRunner
{
public:
    virtual ~RectificationRunner() = default;

    /** Adds an accepted frame: `action` = its pose in the previous accepted
     * frame (first frame: its world pose, usually the identity), `cloud` in
     * its own camera frame, `covariance` the egomotion's uncertainty of
     * `action` if known (Trajectory::append()). Throws std::logic_error
     * after finish(). */
    void addFrame(
        const mrpt::poses::CPose3D& action,
        const emslam::maps::WeightedPointCloud& cloud,
        double timestamp,
        std::size_t frame_index,
        const std::optional<ActionCovariance>& covariance = std::nullopt);

    /** Syncs pending frames, runs the final rectification and stops any
     * thread. The trajectory is final afterwards; further addFrame() calls
     * throw. Idempotent (once it has returned; a finish() that threw may be
     * called again). */
    void finish();

    /** INC ≥ NC_max: the last rectification converged and nothing changed
     * since (AnyTime: the thread's current view). Thread-safe. */
    virtual bool mapStable() const = 0;

    /** How far rectification has got, without copying the statistics. */
    struct Progress
    {
        std::size_t rectifications{0};  //!< records in statistics()
        double energy{0.0};             //!< energy_after of the last one (0: none yet)
    };
    /** Cheap and thread-safe: for progress displays called every frame. */
    virtual Progress progress() const = 0;

    /** Statistics of every rectification so far (a copy; thread-safe). */
    virtual std::vector<RectificationStats> statistics() const = 0;

    /** World poses of every accepted frame at the current state (a copy;
     * thread-safe; in AnyTime mode buffered frames are not yet included). */
    virtual std::vector<TimedPose> framePoses() const = 0;

    /** The trajectory; only valid after finish(). */
    virtual const Trajectory& trajectory() const = 0;

protected:
    /** The mode's addFrame(), called only before finish(). */
    virtual void internalAddFrame(
        const mrpt::poses::CPose3D& action,
        const emslam::maps::WeightedPointCloud& cloud,
        double timestamp,
        std::size_t frame_index,
        const std::optional<ActionCovariance>& covariance) = 0;
    /** The mode's finish(), called until one call returns. */
    virtual void internalFinish() = 0;
    /** True once finish() has returned. */
    bool finished() const { return m_finished; }

private:
    bool m_finished{false};
};

/** Creates the runner of `options.mode` on a trajectory whose map has
 * `map_options`. \ingroup emslam_rectify_grp */
std::unique_ptr<RectificationRunner> createRectificationRunner(
    const TRectifierOptions& options,
    const emslam::CEntropyVoxelMap::TCreationOptions& map_options,
    const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options = {});

}  // namespace emslam::rectify
