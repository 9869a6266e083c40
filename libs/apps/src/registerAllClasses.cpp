// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/registerAllClasses.h>
#include <emslam/egomotion/registerAllClasses.h>
#include <emslam/hwdrivers/registerAllClasses.h>
#include <emslam/maps/registerAllClasses.h>
#include <emslam/rectify/registerAllClasses.h>
#include <emslam/sim/registerAllClasses.h>
#include <emslam/stereo/registerAllClasses.h>

#include <mrpt/core/initializer.h>
#include <mrpt/maps/registerAllClasses.h>

namespace emslam::apps
{
void registerAllClasses()
{
    emslam::stereo::registerAllClasses();
    emslam::egomotion::registerAllClasses();
    emslam::maps::registerAllClasses();
    emslam::sim::registerAllClasses();
    emslam::hwdrivers::registerAllClasses();
    emslam::rectify::registerAllClasses();
    mrpt::maps::registerAllClasses_mrpt_maps();
}
}  // namespace emslam::apps

MRPT_INITIALIZER(emslam_apps_register)
{
    emslam::apps::registerAllClasses();
}
