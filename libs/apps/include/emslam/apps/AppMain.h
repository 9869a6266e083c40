// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/StopSignal.h>
#include <emslam/apps/registerAllClasses.h>
#include <emslam/slam/FrameMemoryPolicy.h>
#include <emslam/util/ExceptionMessage.h>

#include <csignal>
#include <iostream>
#include <type_traits>

namespace emslam::apps
{
/** True for an App with `int exitCode() const` (its verdict on a finished run). */
template <class App, class = void>
struct HasExitCode : std::false_type
{
};
template <class App>
struct HasExitCode<App, std::void_t<decltype(std::declval<const App&>().exitCode())>>
    : std::true_type
{
};

/** The body of every emslam main(): keeps frame buffers in the process
 * (keepFrameBuffersInProcess()), registers the classes, runs the App's
 * initialize() and run(), and turns an exception into one line on stderr
 * ("<name>: error: <message>") and exit code 1. `--help` exits 0. A run that
 * a signal stopped (StopSignal) and that still wrote its outputs exits with
 * 128 + the signal, as shells report a process the signal killed: 130 after
 * Ctrl-C (SIGINT), 143 after SIGTERM, so scripts can tell it from a full run.
 * Otherwise an App with `exitCode()` decides (e.g. EXIT_DEGENERATE), else 0.
 * SIGPIPE is ignored: stdout piped into a reader that quits (`| head`,
 * `| true`) loses the rest of the console text, never the run or its exit
 * code (the outputs are files).
 * \ingroup emslam_apps_grp */
template <class App>
int appMain(const char* name, int argc, char** argv)
{
    try
    {
        std::signal(SIGPIPE, SIG_IGN);
        emslam::slam::keepFrameBuffersInProcess();
        registerAllClasses();
        App app;
        app.initialize(argc, argv);
        app.run();
        const int signum = StopSignal::receivedSignal();
        if (signum != 0)
        {
            return 128 + signum;
        }
        if constexpr (HasExitCode<App>::value)
        {
            return app.exitCode();
        }
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << name << ": error: " << emslam::util::shortExceptionMessage(e) << std::endl;
        return 1;
    }
}

}  // namespace emslam::apps
