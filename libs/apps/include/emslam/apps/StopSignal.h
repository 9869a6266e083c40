// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <string>

namespace emslam::apps
{
/** A process-wide "please stop" flag that SIGINT / SIGTERM / SIGHUP raise while a
 * StopSignalGuard lives, so long loops (grabbing, mapping) can end cleanly
 * and still write what they have. Thread- and signal-safe.
 * \ingroup emslam_apps_grp */
class StopSignal
{
public:
    /** True once a signal arrived or request() was called. */
    static bool requested();
    /** Raises the flag, as a signal does. */
    static void request();
    /** The signal that raised the flag (SIGINT, SIGTERM, SIGHUP), or 0 if none did
     * (not raised, or raised by request()). appMain() exits with 128 + it. */
    static int receivedSignal();
    /** Lowers the flag and forgets the signal (at the start of a run). */
    static void clear();
};

/** Installs the SIGINT / SIGTERM / SIGHUP handlers of StopSignal for its lifetime and
 * restores the previous ones afterwards. Blocking reads are restarted
 * (SA_RESTART), so a signal never turns into a spurious I/O error.
 * \ingroup emslam_apps_grp */
class StopSignalGuard
{
public:
    StopSignalGuard();
    ~StopSignalGuard();
    StopSignalGuard(const StopSignalGuard&) = delete;
    StopSignalGuard& operator=(const StopSignalGuard&) = delete;

private:
    struct Saved;
    Saved* m_saved;
};

/** After a loop that stops early on StopSignal (SIGINT / SIGTERM): if a
 * signal arrived, prints "PROGRAM: interrupted after N of M frames; FILE
 * holds them" on stderr, so RawlogOutput::commit() keeps a complete, readable rawlog of
 * the `written` frames (appMain() then exits 128 + the signal); throws
 * std::runtime_error if no frame was written (nothing worth keeping).
 * Does nothing without a signal. */
void noteInterruption(
    const std::string& program, std::size_t written, std::size_t planned, const std::string& file);

}  // namespace emslam::apps
