// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/TumTrajectory.h>

#include <string>
#include <vector>

namespace emslam::io
{
/** Which files saveTrajectory() writes.
 * \ingroup emslam_io_grp \sa saveTrajectory() */
enum class TrajectoryOutput
{
    Tum,    //!< TUM only
    Kitti,  //!< KITTI poses + times only
    Both    //!< TUM, and KITTI beside it
};

/** "tum" / "kitti" / "both" (case-insensitive) → TrajectoryOutput. Throws
 * std::invalid_argument naming the value and the valid ones otherwise.
 * \ingroup emslam_io_grp */
TrajectoryOutput parseTrajectoryOutput(const std::string& s);

/** The KITTI poses file written beside a TUM file: its name without the
 * extension, then `_kitti.txt` (`out/trajectory_slam.tum` →
 * `out/trajectory_slam_kitti.txt`). \ingroup emslam_io_grp */
std::string kittiFileBeside(const std::string& tum_file);

/** The files saveTrajectory() writes for `file` and `output`, in its order.
 * \ingroup emslam_io_grp */
std::vector<std::string> trajectoryFiles(const std::string& file, TrajectoryOutput output);

/** Writes `t` to `file` in the chosen format(s) and returns the files
 * written: Tum: `file` (TUM); Kitti: `file` (KITTI poses) and
 * KittiTrajectory::timesFileFor(file); Both: `file` (TUM), then
 * kittiFileBeside(file) and its times file. Throws naming a file that cannot
 * be written. \ingroup emslam_io_grp \sa TumTrajectory, KittiTrajectory */
std::vector<std::string> saveTrajectory(
    const TumTrajectory& t, const std::string& file, TrajectoryOutput output);

}  // namespace emslam::io
