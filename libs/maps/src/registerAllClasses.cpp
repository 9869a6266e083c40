// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/maps/registerAllClasses.h>

#include <mrpt/core/initializer.h>

namespace emslam::maps
{
void registerAllClasses()
{
    // Nothing to register yet.
}
}  // namespace emslam::maps

MRPT_INITIALIZER(emslam_maps_register)
{
    emslam::maps::registerAllClasses();
}
