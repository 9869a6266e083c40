// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/TrajectoryReader.h>

#include <string>

namespace emslam::io
{
/** A trajectory file named on a command line (`--gt`, `--est`): reads it with
 * emslam::io::loadTrajectory() (TUM, KITTI + times, EuRoC CSV) and says in
 * every error which input it was (`what`: "ground-truth", "estimate") and why:
 * the file does not exist, is a directory, cannot be read (the reader's message
 * names the file and line), holds no pose, or a position beyond
 * MAX_POSITION_M (requirePlausiblePositions()).
 * \ingroup emslam_io_grp \sa requireTimes(), requireComparableTimes() */
emslam::io::LoadedTrajectory loadTrajectoryInput(
    const std::string& file,
    const std::string& what,
    const emslam::io::TrajectoryReadOptions& options);

/** The largest coordinate of a trajectory position [m]: a million km, beyond
 * any UTM or ECEF frame, so only a wrong column or unit reaches it (1e300
 * would make the ATE overflow to "n/a"). \ingroup emslam_io_grp */
constexpr double MAX_POSITION_M = 1e9;

/** Throws std::runtime_error naming `what`, `file`, the pose and its time
 * unless every position of `t` is finite and within ±MAX_POSITION_M.
 * loadTrajectoryInput() checks every trajectory with it.
 * \ingroup emslam_io_grp */
void requirePlausiblePositions(
    const emslam::io::TumTrajectory& t, const std::string& file, const std::string& what);

/** Throws if `t` (read from `file`) is KITTI without times: the message names
 * the times files looked for and the option that gives one (`times_option`).
 * \ingroup emslam_io_grp \sa loadTrajectoryInput() */
void requireTimes(
    const emslam::io::LoadedTrajectory& t,
    const std::string& file,
    const std::string& what,
    const std::string& times_option);

/** Ground truth and estimate can be paired: both have times, or both are KITTI
 * without times (then paired by line index, as the KITTI devkit does). Throws
 * as requireTimes() for the one without times otherwise.
 * \ingroup emslam_io_grp \sa loadTrajectoryInput() */
void requireComparableTimes(
    const emslam::io::LoadedTrajectory& gt,
    const std::string& gt_file,
    const emslam::io::LoadedTrajectory& est,
    const std::string& est_file);

}  // namespace emslam::io
