// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/TumTrajectory.h>
#include <emslam/rectify/EnergyAtPoses.h>
#include <emslam/rectify/EnergyScan.h>
#include <emslam/slam/EntropySlam.h>

#include <string>

namespace emslam::apps
{
/** What `--energy-scan` measures on a finished mapper. */
struct MapperEnergyScan
{
    /** The scan around the ground truth. */
    emslam::rectify::EnergyScan scan;
    /** The same entropy (the scan's grid phases) with the elements placed by
     * the egomotion and by SLAM [nats]: beside the scan's energy at the truth,
     * is the minimum at the truth, and did the search reach it? */
    ///@{
    double entropy_egomotion{0}, entropy_slam{0};
    ///@}
    /** The odometry prior's cost at the truth, the egomotion and SLAM
     * (0 when it is off): does the prior keep the rectifier from the truth? */
    ///@{
    double prior_truth{0}, prior_egomotion{0}, prior_slam{0};
    ///@}
};

/** The energy scan of a finished mapper: its final trajectory's observations
 * placed by `T_world_frame` (the ground truth, in the map frame) and scanned
 * with the default EnergyScanOptions on the trajectory's own grid phases.
 * \ingroup emslam_apps_grp \sa emslam::rectify::scanEnergy() */
MapperEnergyScan scanMapperEnergy(
    const slam::EntropySlam& m, const emslam::rectify::FramePoseLookup& T_world_frame);

/** The ground-truth pose of each frame of `m` (as in Mapper::frames()) in the
 * map frame: the ground-truth pose nearest the frame's timestamp, relative
 * to that of frame 0 (the map frame is the first camera's). The lookup
 * throws naming the frame and `--gt` when a frame has no ground-truth pose
 * within `max_dt` [s]; `m` and `ground_truth` must outlive it.
 * \ingroup emslam_apps_grp */
emslam::rectify::FramePoseLookup groundTruthFramePoses(
    const slam::EntropySlam& m, const emslam::io::TumTrajectory& ground_truth, double max_dt);

/** energy_scan.csv: one row per scanned line (action, dimension):
 * `action` (k: elements k..N-1 move), `elements_moved`, `dimension` (x, y, z,
 * theta_x, theta_y, theta_z: the action's own frame, the camera's: y is
 * vertical), `unit` (m or deg), `step`, `energy_at_truth` [nats],
 * `argmin_offset` [unit], `min_minus_truth` (E at the minimum − E(0), ≤ 0),
 * `truth_is_min` (1/0), `curvature` [nats/unit²] and `slope` [nats/unit] at
 * the smallest step, then `dE_-K` .. `dE_+K`: E(k·step) − E(0) (empty where a
 * line has fewer steps). Throws naming the file if it cannot be written.
 * \ingroup emslam_apps_grp */
void writeEnergyScanCsv(const emslam::rectify::EnergyScan& scan, const std::string& file);

/** The `energy_scan` object of summary.json: the aggregate and the entropies
 * at the egomotion and SLAM, rotations in degrees. \ingroup emslam_apps_grp */
std::string energyScanJson(const MapperEnergyScan& s);

}  // namespace emslam::apps
