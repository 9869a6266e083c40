// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/registerAllClasses.h>

#include <mrpt/core/initializer.h>

namespace emslam::rectify
{
void registerAllClasses()
{
    // No MRPT classes of its own: the rectifier works on emslam::CEntropyVoxelMap.
}
}  // namespace emslam::rectify

MRPT_INITIALIZER(emslam_rectify_register)
{
    emslam::rectify::registerAllClasses();
}
