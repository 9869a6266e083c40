// SPDX-License-Identifier: BSD-3-Clause
// emslam-import: KITTI / EuRoC / TUM RGB-D sequence -> rawlog (+ TUM ground truth).
// See doc/apps/emslam-import.md.
#include <emslam/apps/ImportApp.h>
#include <emslam/apps/registerAllClasses.h>

#include <mrpt/core/exceptions.h>

#include <iostream>

int main(int argc, char** argv)
{
    try
    {
        emslam::apps::registerAllClasses();
        emslam::apps::ImportApp app;
        app.initialize(argc, argv);
        app.run();
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << mrpt::exception_to_str(e) << std::endl;
        return 1;
    }
}
