// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/hwdrivers/registerAllClasses.h>
#include <emslam/sim/registerAllClasses.h>
#include <emslam/slam/registerAllClasses.h>

#include <gtest/gtest.h>

int main(int argc, char** argv)
{
    ::testing::InitGoogleTest(&argc, argv);
    // Every library's classes (the suites read rawlogs of all of them).
    emslam::slam::registerAllClasses();
    emslam::sim::registerAllClasses();
    emslam::hwdrivers::registerAllClasses();
    return RUN_ALL_TESTS();
}
