// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/util/ConfigRenames.h>

#include <vector>

namespace emslam::slam
{
/** The INI names the mapper's, odometry's and stereo's sections and keys had
 * before each section took the name of the component it configures. Old
 * configs are still read (util::withCurrentNames()); the apps warn once per
 * old name. \ingroup emslam_slam_grp */
inline const std::vector<emslam::util::ConfigRename>& configRenames()
{
    static const std::vector<emslam::util::ConfigRename> renames{
        {"Stereo", "", "StereoMatcher", ""},
        {"Egomotion", "", "EgomotionEstimator", ""},
        {"Mapper", "", "EntropySlam", ""},
        {"SpaceSampling", "", "SpaceSampler", ""},
        {"OccupancyGrid", "", "OccupancyGridBuilder", ""},
        {"OctoMap", "", "OctoMapBuilder", ""},
        {"LoopCloser", "vertical_patch_px", "VerticalFromPlanes", "patch_px"},
        {"LoopCloser", "vertical_max_angle_deg", "VerticalFromPlanes", "max_angle_deg"},
        {"LoopCloser", "vertical_min_patches", "VerticalFromPlanes", "min_patches"},
    };
    return renames;
}
}  // namespace emslam::slam
