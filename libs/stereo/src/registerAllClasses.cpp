// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/stereo/registerAllClasses.h>

#include <mrpt/core/initializer.h>
#include <mrpt/obs/registerAllClasses.h>

namespace emslam::stereo
{
void registerAllClasses()
{
    // Rawlog reading needs MRPT's observation classes registered; with
    // --as-needed linking their own initializers may never run.
    mrpt::obs::registerAllClasses_mrpt_obs();
}
}  // namespace emslam::stereo

MRPT_INITIALIZER(emslam_stereo_register)
{
    emslam::stereo::registerAllClasses();
}
