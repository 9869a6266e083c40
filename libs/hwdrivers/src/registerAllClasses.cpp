// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/hwdrivers/CDigiclopsStereoCamera.h>
#include <emslam/hwdrivers/CSimulatedStereoCamera.h>
#include <emslam/hwdrivers/CStereoImageFolderCamera.h>
#include <emslam/hwdrivers/CVideoStereoCamera.h>
#include <emslam/hwdrivers/registerAllClasses.h>

#include <mrpt/core/initializer.h>

namespace emslam::hwdrivers
{
void registerAllClasses()
{
    CDigiclopsStereoCamera::doRegister();
    CSimulatedStereoCamera::doRegister();
    CStereoImageFolderCamera::doRegister();
    CVideoStereoCamera::doRegister();
}
}  // namespace emslam::hwdrivers

MRPT_INITIALIZER(emslam_hwdrivers_register)
{
    emslam::hwdrivers::registerAllClasses();
}
