// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <string>
#include <vector>

namespace emslam::apps
{
/** The folders that hold the shipped INI files of one `kind` ("mapper",
 * "odometry", "sim", "stereo", ...: the subfolders of config/), in the order
 * they are searched, only those that exist:
 * 1. the install's `share/emslam/config/<kind>`, found from the running
 *    executable (its folder, then the install layout's path from bin/ to the
 *    configs, so the prefix may be moved);
 * 2. the source tree's `config/<kind>`, when the executable lies in the build
 *    tree it was built in (apps and tests run from `build/`).
 * \ingroup emslam_apps_grp \sa findConfigFile() */
std::vector<std::string> shippedConfigDirs(const std::string& kind);

/** The INI file that `name`, as a user typed it, stands for:
 * - `name` itself if it is a path (has a '/') or an existing file: paths are
 *   returned unchanged, so a missing one is reported as the file it names;
 * - else `<dir>/<name>` or `<dir>/<name>.ini` in the first of
 *   shippedConfigDirs(`kind`) that has it (`kitti` or `kitti.ini`);
 * - "" for an empty `name` (no config: the built-in defaults).
 * Throws std::invalid_argument naming `name`, the folders searched and the
 * names shipped in them ("no mapper config 'kiti': not a file, nor a shipped
 * name (3dof-structured, ..., kitti in /usr/share/emslam/config/mapper)").
 * \ingroup emslam_apps_grp */
std::string findConfigFile(const std::string& name, const std::string& kind);

}  // namespace emslam::apps
