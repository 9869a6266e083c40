// SPDX-License-Identifier: BSD-3-Clause
// Test helper: a simulator world driven along its trajectory, with the exact
// depth of each space-sampled frame as its cloud and drift injected into the
// true actions, as an egomotion front-end would deliver them.
#pragma once

#include <emslam/maps/WeightedPointCloud.h>

#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <string>
#include <vector>

namespace emslam::test
{
struct DriveOptions
{
    int width{80};  //!< rendered depth size (small: tests stay fast)
    int height{60};
    double focal_px{50.0};
    double max_depth{8.0};                 //!< [m] points farther are dropped
    double depth_noise{0.005};             //!< σ_z = depth_noise · z² [m] (stereo-like)
    double t_min{0.15};                    //!< space sampling [m]
    double theta_min_deg{5.0};             //!< space sampling [deg]
    double scale_error{0.015};             //!< relative translation error of every action
    double heading_drift_deg_per_m{0.05};  //!< yaw bias per metre travelled
    double turn_scale_error{0.01};         //!< relative error of every turn about y
    double keep_y_min{-1e9};  //!< points kept if keep_y_min <= y <= keep_y_max (camera frame)
    double keep_y_max{1e9};
    std::uint64_t seed{7};
    std::size_t max_frames{0};  //!< 0: the whole trajectory
};

struct DrivenFrame
{
    double timestamp{0.0};
    std::size_t frame_index{0};
    mrpt::poses::CPose3D T_world_true;       //!< ground truth (world = first camera)
    mrpt::poses::CPose3D action_drifted;     //!< from the previous accepted frame
    emslam::maps::WeightedPointCloud cloud;  //!< camera frame
};

/** Accepted frames of `world_ini` (a path relative to the source tree). */
std::vector<DrivenFrame> driveWorld(const std::string& world_ini, const DriveOptions& o);

/** Poses obtained by composing the drifted actions. */
std::vector<mrpt::poses::CPose3D> composeActions(const std::vector<DrivenFrame>& frames);

/** RMSE of the position error after aligning the first poses (the world is
 * the first camera frame for both, so no further alignment). */
double positionRmse(
    const std::vector<mrpt::poses::CPose3D>& est, const std::vector<DrivenFrame>& truth);

/** Distance between the first and the last pose. */
double loopGap(const std::vector<mrpt::poses::CPose3D>& poses);
}  // namespace emslam::test
