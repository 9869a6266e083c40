// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/slam/IntensityCloud.h>

#include <string>

namespace emslam::apps
{
/** Writes the cloud as a binary little-endian PLY file (x, y, z as float;
 * red, green, blue as the grey level), through a temporary file renamed on
 * success. Throws std::runtime_error naming the file on failure.
 * \ingroup emslam_apps_grp */
void savePly(const emslam::slam::IntensityCloud& cloud, const std::string& file);

}  // namespace emslam::apps
