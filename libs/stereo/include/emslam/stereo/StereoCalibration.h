// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/img/TStereoCamera.h>

#include <string>

namespace emslam::stereo
{
/** Reads MRPT's own TStereoCamera INI form: sections `[<section>_LEFT]`,
 * `[<section>_RIGHT]` and `[<section>_LEFT2RIGHT_POSE]` (as written by
 * `TStereoCamera::saveToConfigFile`). Throws when a section is missing or a
 * camera has a zero size or focal length.
 * \ingroup emslam_stereo_grp \sa io::loadStereoCameraFromIniFile() */
mrpt::img::TStereoCamera loadStereoCameraFromConfig(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section);

/** Throws with a message naming `what` if the calibration is unusable (zero
 * size, non-positive focal length, zero baseline, non-finite numbers). */
void validateStereoCamera(const mrpt::img::TStereoCamera& cam, const std::string& what);

/** Stereo baseline [m]: the norm of the right camera's position in the left frame. */
double baselineOf(const mrpt::img::TStereoCamera& cam);

}  // namespace emslam::stereo
