// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/BackgroundWorker.h>

#include <utility>

namespace emslam::slam
{
BackgroundWorker::BackgroundWorker(std::function<void()> job) : m_job(std::move(job))
{
    m_thread = std::thread([this] { run(); });
}

BackgroundWorker::~BackgroundWorker()
{
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_stop = true;
    }
    m_wake.notify_all();
    if (m_thread.joinable())
    {
        m_thread.join();
    }
}

void BackgroundWorker::run()
{
    std::unique_lock<std::mutex> lock(m_mutex);
    while (true)
    {
        m_wake.wait(lock, [this] { return m_stop || m_requested != m_done; });
        if (m_stop)
        {
            return;
        }
        const std::uint64_t serving = m_requested;
        lock.unlock();
        std::exception_ptr error;
        try
        {
            m_job();
        }
        catch (...)
        {
            error = std::current_exception();
        }
        lock.lock();
        m_done = serving;
        m_served.notify_all();
        if (error)
        {
            m_error = error;
            m_done = m_requested;  // nobody waits for a thread that is gone
            m_stop = true;
            return;
        }
    }
}

void BackgroundWorker::rethrowLocked()
{
    if (m_error)
    {
        std::exception_ptr e = m_error;
        m_error = nullptr;
        std::rethrow_exception(e);
    }
}

void BackgroundWorker::notify()
{
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        rethrowLocked();
        ++m_requested;
    }
    m_wake.notify_one();
}

void BackgroundWorker::drain()
{
    std::unique_lock<std::mutex> lock(m_mutex);
    m_served.wait(lock, [this] { return m_done == m_requested || m_stop; });
    rethrowLocked();
}

void BackgroundWorker::stop()
{
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_stop = true;
    }
    m_wake.notify_all();
    if (m_thread.joinable())
    {
        m_thread.join();
    }
    std::lock_guard<std::mutex> lock(m_mutex);
    rethrowLocked();
}

std::uint64_t BackgroundWorker::pending() const
{
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_requested - m_done;
}

}  // namespace emslam::slam
