// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/AnyTimeRectification.h>

#include <stdexcept>

namespace emslam::rectify
{
AnyTimeRectification::AnyTimeRectification(
    const TRectifierOptions& options,
    const emslam::CEntropyVoxelMap::TCreationOptions& map_options,
    const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options)
    : SingleChainRunner(options, map_options, insertion_options)
{
    m_thread = std::thread([this] { run(); });
}

AnyTimeRectification::~AnyTimeRectification()
{
    stopThread();
}

void AnyTimeRectification::stopThread()
{
    if (!m_thread.joinable())
    {
        return;
    }
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_stop = true;
    }
    m_wake.notify_all();
    m_thread.join();
}

void AnyTimeRectification::run()
{
    std::unique_lock<std::mutex> lock(m_mutex);
    const auto can_work = [this]
    { return m_stop || (!m_sync_requested && m_run_open && !m_worker_error); };
    while (true)
    {
        m_wake.wait(lock, can_work);
        if (m_stop)
        {
            return;
        }
        try
        {
            m_rectifier.attempt(m_trajectory, m_current);
            const bool capped =
                m_options.max_attempts > 0 &&
                m_current.attempts >= static_cast<std::size_t>(m_options.max_attempts);
            const bool converged = m_rectifier.consecutiveFailures() >= m_options.nc_max;
            if ((converged && !m_rectifier.refine(m_trajectory)) || capped)
            {
                closeRun();  // converged at l_d: idle until new frames arrive
            }
        }
        catch (...)
        {
            m_worker_error = std::current_exception();
            m_run_open = false;
        }
    }
}

void AnyTimeRectification::closeRun()
{
    if (!m_run_open)
    {
        return;
    }
    m_rectifier.finish(m_trajectory, m_current);
    m_stats.push_back(m_current);
    m_run_open = false;
    m_stable = m_current.converged;
}

void AnyTimeRectification::synchronise()
{
    m_sync_requested = true;
    {
        std::lock_guard<std::mutex> lock(m_mutex);  // the worker is between attempts
        closeRun();
        for (BufferedFrame& f : m_buffer)
        {
            appendFrame(f.action, f.cloud, f.timestamp, f.frame_index, f.covariance);
        }
        m_buffer.clear();
        if (m_trajectory.size() >= 2)
        {
            m_rectifier.begin(m_trajectory, m_current);
            m_run_open = true;
            m_stable = false;
        }
        m_sync_requested = false;
        ++m_syncs;
    }
    m_wake.notify_all();
}

void AnyTimeRectification::rethrowWorkerError()
{
    std::lock_guard<std::mutex> lock(m_mutex);
    if (m_worker_error)
    {
        std::rethrow_exception(m_worker_error);
    }
}

void AnyTimeRectification::internalAddFrame(
    const mrpt::poses::CPose3D& action,
    const emslam::maps::WeightedPointCloud& cloud,
    double timestamp,
    std::size_t frame_index,
    const std::optional<ActionCovariance>& covariance)
{
    rethrowWorkerError();
    m_buffer.push_back({action, keptPart(cloud), timestamp, frame_index, covariance});
    if (m_buffer.size() >= static_cast<std::size_t>(m_options.buffer_size))
    {
        synchronise();
    }
}

void AnyTimeRectification::internalFinish()
{
    rethrowWorkerError();
    if (!m_buffer.empty())
    {
        synchronise();
    }
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        closeRun();
    }
    stopThread();
    rethrowWorkerError();
    // The thread is gone: the final rectification runs here, as in serial
    // mode, under the lock since readers may still poll.
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        if (m_trajectory.size() >= 2)
        {
            const RectificationStats s = m_rectifier.rectify(m_trajectory);
            m_stats.push_back(s);
            m_stable = s.converged;
        }
    }
}

std::vector<RectificationStats> AnyTimeRectification::statistics() const
{
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_stats;
}

RectificationRunner::Progress AnyTimeRectification::progress() const
{
    std::lock_guard<std::mutex> lock(m_mutex);
    return {m_stats.size(), m_stats.empty() ? 0.0 : m_stats.back().energy_after};
}

std::vector<TimedPose> AnyTimeRectification::framePoses() const
{
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_trajectory.framePoses();
}

const Trajectory& AnyTimeRectification::trajectory() const
{
    if (!finished())
    {
        throw std::logic_error("AnyTimeRectification::trajectory() before finish()");
    }
    return m_trajectory;
}

}  // namespace emslam::rectify
