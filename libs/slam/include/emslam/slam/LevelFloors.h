// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/PoseGraph.h>
#include <emslam/stereo/VerticalFromPlanes.h>

#include <cstddef>
#include <optional>
#include <vector>

namespace emslam::slam
{
/** What levelFloors() did. */
struct LevelFloorsStats
{
    std::size_t measured{0};  //!< nodes with a vertical measurement
    std::size_t used{0};      //!< of them: within the gate, in the graph (last pass)
    /** Tilt spread of the levelled poses beyond the measurements [deg]
     * (the last gate's). */
    double drift_deg{0};
    double bias_deg{0};  //!< the camera's own tilt of the up it sees, solved [deg]
    /** Keyframes that share one measurement error (last pass): the
     * measurements' information is divided by it. */
    double correlation_time{1};
};

/** Levels a pose graph by the verticals its nodes saw
 * (emslam::stereo::VerticalFromPlanes): each measurement joins the graph as
 * a direction prior, that its node's up be the world up, and the graph is
 * solved with two more unknowns shared by all: the world up (found, not
 * assumed: node 0 stays where it is) and the camera's own bias, the tilt
 * with which it sees every floor in its own frame (stereo's small
 * systematic errors). Without the bias a walk would climb or dive: every
 * camera pulled the same way in its own frame tilts the whole path.
 *
 * A measurement is an outlier (a ramp, stairs seen as one, a tilted table
 * top) when it disagrees with the world up beyond its own covariance plus
 * the pose's: in the first pass `tilt_variance[k]` [rad², per axis], how
 * far the egomotion may have tilted node k; in the next passes the spread
 * the measurements show at the levelled poses beyond their own noise (by
 * the median). The gate is the 99.73 % bulk of a χ²(2); `passes` rounds of
 * gating and solving.
 *
 * `verticals[k]` belongs to node k (nothing: not measured).
 * \ingroup emslam_slam_grp \sa LoopCloser */
LevelFloorsStats levelFloors(
    emslam::rectify::PoseGraph& graph,
    const std::vector<std::optional<emslam::stereo::VerticalMeasurement>>& verticals,
    const std::vector<double>& tilt_variance,
    int passes = 3);

}  // namespace emslam::slam
