// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <string>

namespace emslam::io
{
/** The trajectory text formats we read.
 * \ingroup emslam_io_grp \sa detectTrajectoryFormat(), loadTrajectory() */
enum class TrajectoryFormat
{
    /** Told from the file's content (detectTrajectoryFormat()). */
    Auto,
    /** TUM: `t tx ty tz qx qy qz qw` (TumTrajectory). */
    Tum,
    /** KITTI: 12 numbers, a 3x4 row-major pose, plus a times file (KittiTrajectory). */
    Kitti,
    /** EuRoC ground-truth CSV: `timestamp_ns,p,q,...` (EurocTrajectory). */
    Euroc
};

/** "auto" / "tum" / "kitti" / "euroc" (case-insensitive) → TrajectoryFormat.
 * Throws std::invalid_argument naming the value and the valid ones otherwise.
 * \ingroup emslam_io_grp */
TrajectoryFormat parseTrajectoryFormat(const std::string& s);

/** TrajectoryFormat → "auto" / "tum" / "kitti" / "euroc". \ingroup emslam_io_grp */
std::string trajectoryFormatName(TrajectoryFormat f);

/** Tells the format of a trajectory file from its first data line (blank and
 * `#` lines skipped, except a EuRoC header naming `p_RS_R_x` or `q_RS_w`):
 * comma-separated with an integer timestamp of at least 1e12 (nanoseconds):
 * Euroc; 12 numbers: Kitti; 8 numbers: Tum. Never returns Auto. Throws
 * naming the file (and the line) if it cannot be opened, holds no data line,
 * or its first data line fits none of them.
 * \ingroup emslam_io_grp */
TrajectoryFormat detectTrajectoryFormat(const std::string& file);

}  // namespace emslam::io
