// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/sim/registerAllClasses.h>

#include <mrpt/core/initializer.h>

namespace emslam::sim
{
void registerAllClasses()
{
    // Nothing to register yet.
}
}  // namespace emslam::sim

MRPT_INITIALIZER(emslam_sim_register)
{
    emslam::sim::registerAllClasses();
}
