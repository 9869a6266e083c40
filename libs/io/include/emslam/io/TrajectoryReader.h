// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/KittiSequence.h>
#include <emslam/io/TrajectoryFormat.h>
#include <emslam/io/TumTrajectory.h>

#include <string>
#include <vector>

namespace emslam::io
{
/** How loadTrajectory() reads a file.
 * \ingroup emslam_io_grp \sa loadTrajectory() */
struct TrajectoryReadOptions
{
    /** The file's format; Auto: detectTrajectoryFormat(). (Default: Auto) */
    TrajectoryFormat format{TrajectoryFormat::Auto};
    /** KITTI only: the times file; empty: KittiTrajectory::findTimesFile().
     * (Default: empty) */
    std::string times_file;
    /** KITTI only: UNIX time [s] added to sequence times (those below
     * KittiTrajectory::RELATIVE_TIME_LIMIT), the offset `emslam-import kitti`
     * gives its observations. (Default: KittiSequence::DEFAULT_TIME_OFFSET) */
    double kitti_time_offset{KittiSequence::DEFAULT_TIME_OFFSET};
};

/** A trajectory read by loadTrajectory(), and how it was read.
 * \ingroup emslam_io_grp \sa loadTrajectory() */
struct LoadedTrajectory
{
    TumTrajectory trajectory;  //!< the poses read
    /** The format read (never Auto). */
    TrajectoryFormat format{TrajectoryFormat::Tum};
    /** False for a KITTI file without a times file: the pose of line i then
     * has time i [s], fit only for pairing by index with another such file. */
    bool timed{true};
    /** KITTI: the times file used. */
    std::string times_file;
    /** KITTI without times: the times files looked for. */
    std::vector<std::string> times_candidates;

    /** For an untimed trajectory: "KITTI poses file 'F' has no times file
     * (none of 'A', 'B' exists)". */
    std::string missingTimesMessage(const std::string& file) const;
};

/** Reads a TUM, KITTI (poses + times) or EuRoC ground-truth file, the format
 * forced by `o.format` or told from the content. Throws naming the file and
 * line on garbled content, and naming the times file if it was given and
 * cannot be read. A KITTI file whose times file is not found is read untimed
 * (LoadedTrajectory::timed); the caller decides whether that is an error.
 * \ingroup emslam_io_grp \sa TrajectoryReadOptions, detectTrajectoryFormat() */
LoadedTrajectory loadTrajectory(const std::string& file, const TrajectoryReadOptions& o = {});

}  // namespace emslam::io
