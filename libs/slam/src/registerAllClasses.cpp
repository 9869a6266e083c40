// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/egomotion/registerAllClasses.h>
#include <emslam/maps/registerAllClasses.h>
#include <emslam/rectify/registerAllClasses.h>
#include <emslam/slam/CMapSession.h>
#include <emslam/slam/registerAllClasses.h>
#include <emslam/stereo/registerAllClasses.h>

#include <mrpt/core/initializer.h>
#include <mrpt/maps/registerAllClasses.h>
#include <mrpt/rtti/CObject.h>

namespace emslam::slam
{
void registerAllClasses()
{
    emslam::stereo::registerAllClasses();
    emslam::egomotion::registerAllClasses();
    emslam::maps::registerAllClasses();
    emslam::rectify::registerAllClasses();
    mrpt::maps::registerAllClasses_mrpt_maps();
    mrpt::rtti::registerClass(CLASS_ID(emslam::slam::CMapSession));
}
}  // namespace emslam::slam

MRPT_INITIALIZER(emslam_slam_register)
{
    mrpt::rtti::registerClass(CLASS_ID(emslam::slam::CMapSession));
}
