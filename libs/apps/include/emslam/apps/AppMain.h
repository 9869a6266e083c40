// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/registerAllClasses.h>
#include <emslam/stereo/ExceptionMessage.h>

#include <iostream>

namespace emslam::apps
{
/** The body of every emslam main(): registers the classes, runs the App's
 * initialize() and run(), and turns an exception into one line on stderr
 * ("<name>: error: <message>") and exit code 1. `--help` exits 0.
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
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << name << ": error: " << emslam::stereo::shortExceptionMessage(e) << std::endl;
        return 1;
    }
}

}  // namespace emslam::apps
