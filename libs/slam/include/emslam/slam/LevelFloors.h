// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/PoseGraph.h>
#include <emslam/stereo/VerticalFromPlanes.h>

#include <cstddef>
#include <limits>
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
    /** The camera's own tilt of the up it sees, solved [deg], at most
     * `max_bias`; NaN while it is not observable (bias_observable). */
    double bias_deg{std::numeric_limits<double>::quiet_NaN()};
    /** Whether the measurements tell the bias from the world up (then it
     * was solved and applied; otherwise it is held at zero). */
    bool bias_observable{false};
    /** Keyframes that share one measurement error (last pass): the
     * measurements' information is divided by it. */
    double correlation_time{1};
    /** relevelFloors(): the first node the next solve must free (the node
     * count: none). */
    std::size_t first_changed{0};
};

/** The default bound of the camera's bias in levelFloors() [rad]: 3 degrees,
 * far beyond what a calibrated stereo rig's floors are tilted by.
 * \ingroup emslam_slam_grp */
constexpr double DEFAULT_MAX_CAMERA_BIAS = 3.0 * 3.14159265358979323846 / 180.0;

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
 * The bias is a tilt of at most `max_bias` [rad] (PoseGraph::DirectionFrame::
 * max_bias), and it is solved only where the data observe it: a camera that
 * has only moved straight (or turned about one axis fixed in its frame)
 * sees the world up and its own bias as one direction. Each pass takes the
 * information the agreeing measurements give on the bias, the world up
 * marginalised, at the current poses (the 2×2 Schur complement of their
 * normal equations); the bias is observable when its smallest eigenvalue
 * is at least (3 / max_bias)², i.e. the data alone know it to a third of
 * its bound. Until then it is held at zero and not reported.
 *
 * `verticals[k]` belongs to node k (nothing: not measured).
 * \ingroup emslam_slam_grp \sa LoopCloser */
LevelFloorsStats levelFloors(
    emslam::rectify::PoseGraph& graph,
    const std::vector<std::optional<emslam::stereo::VerticalMeasurement>>& verticals,
    const std::vector<double>& tilt_variance,
    int passes = 3,
    double max_bias = DEFAULT_MAX_CAMERA_BIAS);

/** levelFloors() for a graph that grows, without its solves of the poses
 * (the online levelling of LoopCloser): one pass of gating at the current
 * poses, the agreeing measurements replacing the graph's direction priors,
 * then the world up (and the bias, once observed) solved with every node
 * held. The poses move in the caller's own solves, local or not, which
 * count the priors (PoseGraph::optimize()): each keyframe is levelled when
 * its neighbourhood is solved anyway, and no solve of the whole graph is
 * needed for it.
 *
 * The gate is that of levelFloors()' later passes (the spread the
 * measurements show beyond their own noise, by the median; information
 * divided by the correlation time) plus `pose_tilt_variance[k]` [rad², per
 * axis]: how far node k may be tilted beyond that spread, e.g. the
 * egomotion's chain since the last node a solve levelled (nothing: 0).
 * The first call (no priors in the graph) starts the world up at the mean
 * measured up. The measurements of nodes before `regate_from` (those gated
 * before) keep their decision and prior, unless every node is to be solved
 * again (below): a decision flipping on an old node would make the next
 * solve reach back to it, every time.
 *
 * The next solve must free LevelFloorsStats::first_changed on: the first
 * node whose prior came or went, or every node (1) when the world up and
 * the bias moved beyond their own noise since `levelled_for`, the
 * direction frame the held nodes were last solved with (the priors would
 * gain more than the 99.73 % bulk of a χ²(4) at the held poses): a bias
 * observed only after the first turns must level what came before. Why: a full levelFloors() of a
 * long run's graph is three solves of every keyframe, seconds after the last frame; and the online
 * estimate would stay tilted until then.
 * \ingroup emslam_slam_grp */
LevelFloorsStats relevelFloors(
    emslam::rectify::PoseGraph& graph,
    const std::vector<std::optional<emslam::stereo::VerticalMeasurement>>& verticals,
    const std::vector<double>& pose_tilt_variance,
    const emslam::rectify::PoseGraph::DirectionFrame& levelled_for,
    std::size_t regate_from,
    double max_bias = DEFAULT_MAX_CAMERA_BIAS);

}  // namespace emslam::slam
