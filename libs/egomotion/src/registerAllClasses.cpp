// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/egomotion/registerAllClasses.h>

#include <mrpt/core/initializer.h>

namespace emslam::egomotion
{
void registerAllClasses()
{
    // Nothing to register yet.
}
}  // namespace emslam::egomotion

MRPT_INITIALIZER(emslam_egomotion_register)
{
    emslam::egomotion::registerAllClasses();
}
