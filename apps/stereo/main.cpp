// SPDX-License-Identifier: BSD-3-Clause
// emslam-stereo: the stereo front-end on an image pair or a rawlog.
#include <emslam/apps/StereoApp.h>
#include <emslam/apps/registerAllClasses.h>

#include <mrpt/core/exceptions.h>

#include <iostream>

int main(int argc, char** argv)
{
    try
    {
        emslam::apps::registerAllClasses();
        emslam::apps::StereoApp app;
        app.initialize(argc, argv);
        app.run();
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "emslam-stereo: error: " << mrpt::exception_to_str(e) << "\n";
        return 1;
    }
}
