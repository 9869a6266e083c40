// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/eval/MapAccuracy.h>
#include <emslam/slam/IntensityCloud.h>

#include <string>

namespace emslam::apps
{
/** Writes the cloud as a binary little-endian PLY file (x, y, z as float;
 * red, green, blue as the grey level), through a temporary file renamed on
 * success. Throws std::runtime_error naming the file on failure.
 * \ingroup emslam_apps_grp */
void savePly(const emslam::slam::IntensityCloud& cloud, const std::string& file);

/** Writes a reference surface (`emslam-sim --map-gt-out`) as a binary
 * little-endian PLY file: per vertex x, y, z, nx, ny, nz and seen_range (the
 * nearest depth it was seen at [m]) as float, and the sample spacing in a
 * `comment sample_spacing S` header line. Through a temporary file renamed
 * on success; throws std::runtime_error naming the file on failure.
 * \ingroup emslam_apps_grp */
void saveReferencePly(const emslam::eval::ReferenceSurface& surface, const std::string& file);

/** Reads the vertices of a PLY file (ascii or binary little-endian, any
 * scalar property types): x, y, z, and nx, ny, nz, seen_range and the
 * `sample_spacing` comment when present; other properties and elements are
 * skipped. Throws std::runtime_error naming the file and the cause (not a
 * PLY file, big-endian, no x / y / z, a vertex list property, truncated
 * data, a bad number). \ingroup emslam_apps_grp */
emslam::eval::ReferenceSurface loadPly(const std::string& file);

}  // namespace emslam::apps
