// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/TumTrajectory.h>

#include <mrpt/poses/CPose3D.h>

#include <string>
#include <vector>

namespace emslam::io
{
/** A trajectory in the KITTI odometry text format (Geiger et al., CVPR 2012):
 * a poses file with one pose per line, the 3x4 row-major matrix [R | t] of the
 * camera in the first camera's frame (12 numbers separated by spaces), and a
 * times file with one timestamp [s] per line, as the sequence's `times.txt`.
 *
 * KITTI's own `times.txt` counts seconds from the start of the sequence, while
 * our trajectories carry UNIX times (`emslam-import kitti` adds
 * KittiSequence::DEFAULT_TIME_OFFSET). Reading tells the two apart: times below
 * RELATIVE_TIME_LIMIT are sequence times and get `time_offset` added, larger
 * ones are taken as they are. Writing puts the trajectory's own timestamps
 * (formatTimestamp(): nine decimals, no exponent), so a written trajectory reads
 * back with the same times and poses (to the 17 significant digits written).
 *
 * Where the times file is: timesFileFor() names the one written beside a poses
 * file; findTimesFile() also knows the KITTI layout (`poses/NN.txt` →
 * `sequences/NN/times.txt`).
 * \ingroup emslam_io_grp \sa TumTrajectory, KittiSequence */
class KittiTrajectory
{
public:
    /** Times below this [s] are sequence times, not UNIX times (1e9 s is 2001). */
    static constexpr double RELATIVE_TIME_LIMIT = 1e9;

    /** Reads a poses file: one 3x4 row-major matrix per line, blank lines
     * skipped; the rotation is re-orthonormalized (KITTI writes 7 digits).
     * Throws naming the file and line on a line without 12 numbers or a
     * matrix that is far from a rotation, and on an empty file. */
    static std::vector<mrpt::poses::CPose3D> readPoses(const std::string& file);

    /** Reads a times file: one timestamp [s] per line, finite, in [0, 1e10)
     * and increasing. Throws naming the file and line otherwise, and on an
     * empty file. */
    static std::vector<double> readTimes(const std::string& file);

    /** Reads poses and times into one trajectory; times below
     * RELATIVE_TIME_LIMIT get `time_offset` added. Throws naming both files if
     * their line counts differ. */
    static TumTrajectory load(
        const std::string& poses_file, const std::string& times_file, double time_offset);

    /** Writes the poses file and the times file (overwritten). Throws naming
     * the file that cannot be written. */
    static void save(
        const TumTrajectory& t, const std::string& poses_file, const std::string& times_file);

    /** Formats one pose as a line of 12 numbers (no line end). */
    static std::string formatLine(const mrpt::poses::CPose3D& T);

    /** The times file written beside `poses_file`: its name without the
     * extension and without a trailing `_kitti`, then `_times.txt`
     * (`out/trajectory_slam_kitti.txt` → `out/trajectory_slam_times.txt`). */
    static std::string timesFileFor(const std::string& poses_file);

    /** The first existing times file for `poses_file`: timesFileFor(), then
     * the KITTI layout (`DIR/poses/NN.txt` → `DIR/sequences/NN/times.txt`),
     * then `times.txt` in the same folder. Empty if there is none. */
    static std::string findTimesFile(const std::string& poses_file);

    /** The candidates findTimesFile() tries, in order (for error messages). */
    static std::vector<std::string> timesFileCandidates(const std::string& poses_file);
};

}  // namespace emslam::io
