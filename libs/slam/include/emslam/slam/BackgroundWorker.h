// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace emslam::slam
{
/** A thread that runs one job whenever it is told there is work: the job
 * takes everything that waits (e.g. the keyframes added since its last
 * run) and returns. notify() never blocks; drain() waits until every
 * notification so far has been served. An exception of the job stops the
 * thread and is rethrown by the next notify(), drain() or stop().
 *
 * Why: the mapper's background work (loop closing) must follow the frames
 * without holding them up, and the caller must be able to wait for it (the
 * end of a run, a bounded lag) without polling.
 * \ingroup emslam_slam_grp */
class BackgroundWorker
{
public:
    /** Starts the thread, which runs `job` whenever work is requested. */
    explicit BackgroundWorker(std::function<void()> job);
    /** Stops the thread after the job it runs (no rethrow). */
    ~BackgroundWorker();
    BackgroundWorker(const BackgroundWorker&) = delete;
    BackgroundWorker& operator=(const BackgroundWorker&) = delete;

    /** There is new work: the job will run (again) after this call. */
    void notify();
    /** Waits until the job has run after the last notify(). */
    void drain();
    /** Waits for the job it runs, ends the thread; drain() first to serve
     * every notification. Idempotent. */
    void stop();
    /** Notifications not served yet (0: idle). Thread-safe. */
    std::uint64_t pending() const;

private:
    void run();
    void rethrowLocked();

    std::function<void()> m_job;
    mutable std::mutex m_mutex;
    std::condition_variable m_wake, m_served;
    std::uint64_t m_requested{0}, m_done{0};
    bool m_stop{false};
    std::exception_ptr m_error;
    std::thread m_thread;
};

}  // namespace emslam::slam
