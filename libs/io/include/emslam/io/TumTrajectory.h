// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <iosfwd>
#include <string>
#include <vector>

namespace emslam::io
{
/** One timestamped pose of a trajectory: `pose` is the pose of the tracked
 * frame (a camera) in the trajectory's reference frame.
 * \ingroup emslam_io_grp \sa TumTrajectory */
struct TumPose
{
    /** Time [s]. */
    double t{0.0};
    /** Pose of the tracked frame in the reference frame (metres, rotation). */
    mrpt::poses::CPose3D pose;
};

/** A timestamp [s] as fixed-point text with nine decimals (nanoseconds), never
 * in exponent notation: `1700000000.200000000`, `0.100000000`. The digits are
 * those of the shortest text that reads back to the same double, padded with
 * zeros (a double holds a UNIX time to ~0.2 µs), so reading it back is exact.
 * \ingroup emslam_io_grp \sa TumTrajectory */
std::string formatTimestamp(double t);

/** A trajectory in the TUM RGB-D benchmark text format (Sturm et al., IROS
 * 2012): one pose per line, `timestamp tx ty tz qx qy qz qw`, separated by
 * spaces (or tabs, or commas when reading). Lines that are empty or start with
 * `#` are comments.
 *
 * Writing never uses exponent notation: the timestamp gets nine decimals
 * (nanoseconds, formatTimestamp()), every other number the shortest fixed-point
 * form that reads back to the same `double`, so a write/read round trip is
 * exact (timestamps to 1 ns; the rotation up to its quaternion conversion,
 * ~1e-16). Quaternions are written with `qw >= 0`; reading normalizes them.
 * \ingroup emslam_io_grp \sa TumPose */
class TumTrajectory
{
public:
    TumTrajectory() = default;
    /** A trajectory of the poses `p`. */
    explicit TumTrajectory(std::vector<TumPose> p) : poses(std::move(p)) {}

    /** The poses, in file order. */
    std::vector<TumPose> poses;

    /** Number of poses. */
    std::size_t size() const { return poses.size(); }
    /** No pose. */
    bool empty() const { return poses.empty(); }
    /** Appends pose `pose` at time `t` [s]. */
    void add(double t, const mrpt::poses::CPose3D& pose) { poses.push_back({t, pose}); }

    /** Writes all poses to a text file (overwritten). Throws
     * std::runtime_error naming the file and the OS reason if it cannot be
     * written (see OutputFile). */
    void saveToFile(const std::string& file) const;

    /** Writes all poses to a stream, one line each. */
    void writeTo(std::ostream& out) const;

    /** Replaces the poses by those of a TUM file. Throws naming the file and
     * the line number on a missing file, a line without 8 numbers, a
     * non-finite number, or a zero quaternion. */
    void loadFromFile(const std::string& file);

    /** Convenience: `TumTrajectory t; t.loadFromFile(file); return t;` */
    static TumTrajectory fromFile(const std::string& file);

    /** Formats one pose as a TUM line (no line end). */
    static std::string formatLine(const TumPose& p);
};

}  // namespace emslam::io
