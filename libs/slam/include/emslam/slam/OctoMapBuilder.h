// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/Trajectory.h>
#include <emslam/slam/KeyframeScan.h>

#include <mrpt/config/CLoadableOptions.h>

#include <octomap/OcTree.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace emslam::slam
{
/** A 3D occupancy map (OctoMap, Hornung et al., Autonomous Robots 2013) of a
 * finished map: `map.bt` of emslam-mapper, what a 3D planner or `octovis`
 * reads. Built on liboctomap's octomap::OcTree directly: the library MRPT's
 * mrpt::maps::COctoMap wraps, whose tree MRPT 2.5 does not expose
 * (COctoMapBase::getOctomap<>() needs a type private to MRPT's sources).
 *
 * Each keyframe's cloud (EntropySlam::keyframeScans(), in its camera frame)
 * is inserted as one scan from the keyframe's final pose: OctoMap marks the
 * voxels its rays cross free and the voxels of its points occupied (a hit
 * counts more than a miss: probabilities 0.7 and 0.4), so free space is
 * carved between the cameras and the surfaces. Rays longer than
 * `max_range` only carve free space up to it: the far points of stereo are
 * too noisy to occupy a voxel.
 * \ingroup emslam_slam_grp \sa OccupancyGridBuilder */
class OctoMapBuilder
{
public:
    /** `[OctoMapBuilder]` */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws std::invalid_argument naming the key of a bad value. */
        void validate() const;

        /** [m] edge of the finest voxels; 0: no map.bt. (Default: 0.1) */
        double resolution{0.1};
        /** [m] longest ray that occupies its end voxel (longer ones only
         * carve free space up to this range). (Default: 6) */
        double max_range{6.0};
    };

    /** What build() inserted. */
    struct Stats
    {
        /** Scans inserted and their points. */
        ///@{
        std::size_t scans{0}, points{0};
        ///@}
    };

    /** A builder with the parameters `p` (validated). */
    explicit OctoMapBuilder(const TParameters& p);

    /** The OctoMap of `scans` (each in the camera frame of its frame index)
     * inserted from their frames' poses in `keyframes` (T_world_frame; world
     * frame = the first camera's). A scan whose frame has no pose is
     * skipped. Throws std::invalid_argument if resolution is 0. */
    std::unique_ptr<octomap::OcTree> build(
        const std::vector<KeyframeScan>& scans,
        const std::vector<emslam::rectify::TimedPose>& keyframes);

    /** What the last build() counted. */
    const Stats& stats() const { return m_stats; }

private:
    TParameters m_p;
    Stats m_stats;
};

}  // namespace emslam::slam
