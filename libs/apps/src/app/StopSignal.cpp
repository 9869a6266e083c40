// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/StopSignal.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <stdexcept>

namespace emslam::apps
{
namespace
{
std::atomic<bool> g_stop_requested{false};
std::atomic<int> g_signal{0};

extern "C" void onStopSignal(int signum)
{
    g_signal.store(signum);
    g_stop_requested.store(true);
}
}  // namespace

bool StopSignal::requested()
{
    return g_stop_requested.load();
}

void StopSignal::request()
{
    g_stop_requested.store(true);
}

int StopSignal::receivedSignal()
{
    return g_signal.load();
}

void StopSignal::clear()
{
    g_stop_requested.store(false);
    g_signal.store(0);
}

struct StopSignalGuard::Saved
{
    struct sigaction old_int
    {
    };
    struct sigaction old_term
    {
    };
    struct sigaction old_hup
    {
    };
};

StopSignalGuard::StopSignalGuard() : m_saved(new Saved)
{
    struct sigaction sa
    {
    };
    sa.sa_handler = onStopSignal;
    sa.sa_flags = SA_RESTART;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &m_saved->old_int);
    sigaction(SIGTERM, &sa, &m_saved->old_term);
    // A dropped ssh session: stop and keep the work, as for SIGTERM.
    sigaction(SIGHUP, &sa, &m_saved->old_hup);
}

StopSignalGuard::~StopSignalGuard()
{
    sigaction(SIGINT, &m_saved->old_int, nullptr);
    sigaction(SIGTERM, &m_saved->old_term, nullptr);
    sigaction(SIGHUP, &m_saved->old_hup, nullptr);
    delete m_saved;
}

void noteInterruption(
    const std::string& program, std::size_t written, std::size_t planned, const std::string& file)
{
    if (!StopSignal::requested())
    {
        return;
    }
    if (written == 0)
    {
        throw std::runtime_error("interrupted before the first frame: nothing written");
    }
    std::fprintf(
        stderr, "%s: interrupted after %zu of %zu frames; '%s' holds them\n", program.c_str(),
        written, planned, file.c_str());
}

}  // namespace emslam::apps
