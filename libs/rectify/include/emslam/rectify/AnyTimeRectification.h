// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/SingleChainRunner.h>

#include <atomic>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

namespace emslam::rectify
{
/** AnyTime mode (§2.2.3): rectification attempts run continuously in their
 * own thread while the caller (egomotion) buffers new frames; every S_buf
 * frames the two synchronise. Each record of statistics() covers one period
 * between synchronisations (or up to convergence, if reached first).
 *
 * Thread safety: addFrame() and finish() from one producer thread;
 * mapStable(), statistics() and framePoses() from any thread. An exception
 * in the rectification thread is rethrown by the next addFrame()/finish().
 * The trajectory and the rectifier (SingleChainRunner's m_trajectory and
 * m_rectifier) are guarded by m_mutex; the worker uses the rectifier.
 * \ingroup emslam_rectify_grp \sa RectificationRunner, SingleChainRunner */
class AnyTimeRectification : public SingleChainRunner
{
public:
    /** Starts the rectification thread over an empty trajectory whose map has `map_options` and
     * `insertion_options`. */
    AnyTimeRectification(
        const TRectifierOptions& options,
        const emslam::CEntropyVoxelMap::TCreationOptions& map_options,
        const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options = {});
    /** Stops the thread (without the final rectification of finish()). */
    ~AnyTimeRectification() override;

    AnyTimeRectification(const AnyTimeRectification&) = delete;
    AnyTimeRectification& operator=(const AnyTimeRectification&) = delete;

    bool mapStable() const override { return m_stable.load(); }
    std::vector<RectificationStats> statistics() const override;
    Progress progress() const override;
    std::vector<TimedPose> framePoses() const override;
    const Trajectory& trajectory() const override;

    /** Synchronisations so far. */
    std::size_t synchronisations() const { return m_syncs.load(); }

protected:
    void internalAddFrame(
        const mrpt::poses::CPose3D& action,
        const emslam::maps::WeightedPointCloud& cloud,
        double timestamp,
        std::size_t frame_index,
        const std::optional<ActionCovariance>& covariance) override;
    void internalFinish() override;

private:
    struct BufferedFrame
    {
        mrpt::poses::CPose3D action;
        emslam::maps::WeightedPointCloud cloud;
        double timestamp{0.0};
        std::size_t frame_index{0};
        std::optional<ActionCovariance> covariance;
    };

    void run();
    /** Appends the buffer to the trajectory between two attempts. */
    void synchronise();
    /** Closes the open run (best state restored, statistics recorded). Lock held. */
    void closeRun();
    void stopThread();
    void rethrowWorkerError();

    RectificationStats m_current;             //!< guarded by m_mutex
    bool m_run_open{false};                   //!< guarded by m_mutex
    std::vector<RectificationStats> m_stats;  //!< guarded by m_mutex
    std::vector<BufferedFrame> m_buffer;      //!< producer thread only

    mutable std::mutex m_mutex;
    std::condition_variable m_wake;
    std::atomic<bool> m_stop{false};
    std::atomic<bool> m_sync_requested{false};
    std::atomic<bool> m_stable{false};
    std::atomic<std::size_t> m_syncs{0};
    std::exception_ptr m_worker_error;  //!< guarded by m_mutex
    std::thread m_thread;
};

}  // namespace emslam::rectify
