// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/LiveViewSnapshot.h>
#include <emslam/slam/IntensityCloud.h>

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace emslam::apps
{
/** A window that shows a run as it goes (`--viewer` of emslam-mapper and
 * emslam-grabber): an MRPT CDisplayWindow3D with the map points, the
 * egomotion (red) and SLAM (green) trajectories, the current camera as a
 * frustum, the current left image in a corner and a legend with a status
 * line.
 *
 * It never slows the run down: the window lives in the viewer's own thread;
 * push() only swaps the latest snapshot in under a mutex (an older one not
 * yet drawn is dropped) and addMapPoints() only appends. The viewer redraws
 * at most `max_rate_hz` times per second.
 *
 * - No display (DISPLAY unset or not reachable) or a window that cannot be
 *   opened: one warning on stderr naming the cause, and the run goes on
 *   without the viewer (push() and addMapPoints() do nothing).
 * - Closing the window stops the viewer only; the run goes on.
 * - The window closes when the viewer is destroyed (the run's end).
 * \ingroup emslam_apps_grp \sa LiveViewSnapshot, MapperLiveFeed */
class LiveViewer
{
public:
    /** Window and drawing options. */
    struct Options
    {
        std::string title{"emslam"};  //!< window title
        ///@{
        unsigned width{1000};  //!< window size [px]
        unsigned height{700};
        ///@}
        double max_rate_hz{10.0};  //!< redraws per second at most (> 0)
        /** Map points kept for drawing; beyond, the oldest are thinned out. */
        std::size_t max_points{1000000};
    };

    /** Starts the viewer thread, which opens the window; returns at once.
     * Without a usable display it prints a warning and stays disabled. */
    explicit LiveViewer(const Options& options);
    /** Closes the window and joins the thread. */
    ~LiveViewer();
    LiveViewer(const LiveViewer&) = delete;
    LiveViewer& operator=(const LiveViewer&) = delete;

    /** Why no window can be opened here (empty if a display is reachable). */
    static std::string displayProblem();

    /** False once the viewer is disabled: no display, the window failed to
     * open or was closed. */
    bool active() const { return m_active.load(); }
    /** True if the viewer is active and has drawn the last snapshot pushed:
     * a snapshot built now would be shown (producers may skip building one
     * otherwise). */
    bool wantsSnapshot() const { return m_active.load() && !m_has_pending.load(); }
    /** Replaces the snapshot to draw next (never blocks for drawing). */
    void push(LiveViewSnapshot snapshot);
    /** Adds map points (map frame); they are kept, not replaced. */
    void addMapPoints(const slam::IntensityCloud& points);

    /** Snapshots drawn so far (for tests and statistics). */
    std::size_t drawnSnapshots() const { return m_drawn.load(); }
    /** True once the window has been opened and drawn at least once. */
    bool windowShown() const { return m_shown.load(); }

private:
    void run();
    void disable(const std::string& why);

    Options m_options;
    std::thread m_thread;
    mutable std::mutex m_mutex;
    std::condition_variable m_wake;
    std::optional<LiveViewSnapshot> m_pending;  //!< guarded by m_mutex
    slam::IntensityCloud m_new_points;          //!< guarded by m_mutex
    bool m_stop{false};                         //!< guarded by m_mutex
    std::atomic<bool> m_active{true};
    std::atomic<bool> m_has_pending{false};
    std::atomic<bool> m_shown{false};
    std::atomic<std::size_t> m_drawn{0};
};

}  // namespace emslam::apps
