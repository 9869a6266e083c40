// SPDX-License-Identifier: BSD-3-Clause
#pragma once

namespace emslam::hwdrivers
{
/** Registers the sensors of this library (CDigiclopsStereoCamera,
 * CSimulatedStereoCamera, CStereoImageFolderCamera, CVideoStereoCamera) with MRPT's
 * CGenericSensor factory. Runs automatically when the library is loaded
 * (also as a plugin of the stock rawlog-grabber); mains call it too so that
 * the linker keeps the library. Idempotent.
 * \ingroup emslam_hwdrivers_grp */
void registerAllClasses();

}  // namespace emslam::hwdrivers
