// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/maps/CEntropyVoxelMap.h>
#include <emslam/maps/registerAllClasses.h>

#include <mrpt/core/initializer.h>
#include <mrpt/rtti/CObject.h>

namespace emslam::maps
{
void registerAllClasses()
{
    // RTTI registration (needed to deserialize); the INI map type registers
    // itself through MAP_DEFINITION_REGISTER. registerClass() is idempotent.
    mrpt::rtti::registerClass(CLASS_ID(emslam::CEntropyVoxelMap));
}
}  // namespace emslam::maps

MRPT_INITIALIZER(emslam_maps_register)
{
    emslam::maps::registerAllClasses();
}
