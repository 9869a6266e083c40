// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/eval/TrajectoryMetrics.h>
#include <emslam/io/TumTrajectory.h>
#include <emslam/rectify/RectificationStats.h>
#include <emslam/slam/FrameRecord.h>

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace emslam::apps
{
/** Everything report.html shows. \ingroup emslam_apps_grp \sa writeMapperReport() */
struct MapperReportData
{
    std::string title;  //!< e.g. the rawlog's file name
    /** Camera trajectories in the world (first camera) frame. */
    ///@{
    emslam::io::TumTrajectory egomotion, slam;
    ///@}
    /** Optional: each frame's pose when it was processed
     * (EntropySlam::onlinePoses(); empty: not drawn). */
    emslam::io::TumTrajectory online;
    /** Optional ground truth, already expressed in the same world frame
     * (empty: not drawn). */
    emslam::io::TumTrajectory ground_truth;
    std::vector<slam::FrameRecord> frames;  //!< per-frame records: times, matches, energy
    std::vector<emslam::rectify::RectificationStats>
        rectifications;  //!< one per rectification call
    /** Rows of the summary table: (name, value as text). */
    std::vector<std::pair<std::string, std::string>> summary;
    /** Egomotion and SLAM against the ground truth (error over distance and
     * over time); empty: those plots say there is no ground truth. */
    ///@{
    std::optional<eval::TrajectoryMetrics> egomotion_vs_gt, slam_vs_gt;
    ///@}
    /** The map picture, relative to the report's folder; embedded when that
     * file exists there when the report is written. */
    std::string map_image{"map_top.png"};
};

/** Writes `data` as one self-contained HTML file (inline SVG and CSS, no
 * script or network access needed): the summary table, the map picture
 * (`data.map_image`, when present), top (X-Z) and side (X-Y / Z-Y) views of
 * the trajectories, the error over distance (KITTI segment errors, lengths
 * from segmentLengthsFor()) and over time against the ground truth, the
 * matches before / after LWO and the 3D points per frame, the energy drop of
 * each rectification and the energy over the cumulative attempts, the
 * successful / failed attempts per rectification (paper Fig. 20), the time
 * per frame with its rectification peaks (Fig. 17) and links to every file in
 * the report's folder. Throws std::runtime_error naming the file if it cannot
 * be written. \ingroup emslam_apps_grp */
void writeMapperReport(const std::string& file, const MapperReportData& data);

}  // namespace emslam::apps
