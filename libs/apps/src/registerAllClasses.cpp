// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/registerAllClasses.h>
#include <emslam/hwdrivers/registerAllClasses.h>
#include <emslam/sim/registerAllClasses.h>
#include <emslam/slam/registerAllClasses.h>

#include <mrpt/core/initializer.h>

namespace emslam::apps
{
void registerAllClasses()
{
    emslam::slam::registerAllClasses();
    emslam::sim::registerAllClasses();
    emslam::hwdrivers::registerAllClasses();
}
}  // namespace emslam::apps

MRPT_INITIALIZER(emslam_apps_register)
{
    emslam::apps::registerAllClasses();
}
