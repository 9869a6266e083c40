// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/StopSignal.h>
#include <emslam/apps/registerAllClasses.h>
#include <emslam/stereo/ExceptionMessage.h>

#include <iostream>

namespace emslam::apps
{
/** The body of every emslam main(): registers the classes, runs the App's
 * initialize() and run(), and turns an exception into one line on stderr
 * ("<name>: error: <message>") and exit code 1. `--help` exits 0. A run that
 * a signal stopped (StopSignal) and that still wrote its outputs exits with
 * 128 + the signal, as shells report a process the signal killed: 130 after
 * Ctrl-C (SIGINT), 143 after SIGTERM, so scripts can tell it from a full run.
 * \ingroup emslam_apps_grp */
template <class App>
int appMain(const char* name, int argc, char** argv)
{
    try
    {
        registerAllClasses();
        App app;
        app.initialize(argc, argv);
        app.run();
        const int signum = StopSignal::receivedSignal();
        return signum != 0 ? 128 + signum : 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << name << ": error: " << emslam::stereo::shortExceptionMessage(e) << std::endl;
        return 1;
    }
}

}  // namespace emslam::apps
