// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/TumTrajectory.h>

#include <string>

namespace emslam::io
{
/** A trajectory in a EuRoC MAV ground-truth CSV file (Burri et al., IJRR
 * 2016): comma-separated rows that start with a timestamp in nanoseconds and a
 * position [m], then a quaternion. Two column orders exist:
 * - `mav0/state_groundtruth_estimate0/data.csv` (17 columns:
 *   `#timestamp, p_RS_R_x, p_RS_R_y, p_RS_R_z, q_RS_w, q_RS_x, q_RS_y, q_RS_z`,
 *   velocity and biases): the body (IMU) pose, quaternion **w first**;
 * - a camera-pose file `timestamp_ns,x,y,z,qx,qy,qz,qw` (8 columns), as
 *   EurocSequence reads: quaternion **w last**.
 *
 * A `#` header naming the columns decides the order (`q_RS_w` or `qw`
 * before the x component: w first); without one, 8 columns are w last and
 * more are w first. Only the first 8 columns are used.
 * \ingroup emslam_io_grp \sa TumTrajectory, EurocSequence */
class EurocTrajectory
{
public:
    /** Reads the file; timestamps become seconds (ns · 1e-9), quaternions are
     * normalized. Throws naming the file and line on a row with fewer than 8
     * fields, a field that is not a number, a zero quaternion, and on a file
     * without rows. */
    static TumTrajectory load(const std::string& file);
};

}  // namespace emslam::io
