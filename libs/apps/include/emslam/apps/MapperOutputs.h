// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/EnergyScanOutputs.h>
#include <emslam/apps/MapDrawingContent.h>
#include <emslam/apps/MapperReport.h>
#include <emslam/eval/TrajectoryMetrics.h>
#include <emslam/io/FrameStreamGuard.h>
#include <emslam/slam/EntropySlam.h>

#include <optional>
#include <string>
#include <vector>

namespace emslam::apps
{
/** What a mapper run adds to its Mapper's results in summary.json. */
struct MapperRunInfo
{
    std::string rawlog;                   //!< the input's path (rawlog or dataset folder)
    std::string config;                   //!< the config file's path
    std::size_t ignored_observations{0};  //!< observations neither stereo nor RGB-D
    /** Stereo / RGB-D observations skipped (io::FrameStreamGuard), in all
     * and per cause: a bad timestamp, another camera, unusable by the front-end. */
    ///@{
    std::size_t skipped_observations{0};
    std::size_t skipped_bad_stamps{0}, skipped_camera_changes{0}, skipped_unusable{0};
    ///@}
    /** The first few skipped ones of each cause: "record N: cause". */
    std::vector<std::string> skipped_reasons;
    /** FrameStreamGuard::skippedText(), or "". */
    std::string skipped_text;
    /** The first camera change, if any, and the run's closing warning about it. */
    ///@{
    std::optional<io::FrameStreamGuard::CameraChange> camera_change;
    std::string camera_change_warning;
    ///@}
    /** The error that stopped the run early ("record N: cause"), or "". */
    std::string stopped_by_error;
    bool interrupted{false};        //!< stopped by SIGINT / SIGTERM
    std::string input_ended_early;  //!< truncated / corrupt rawlog: where and why
    /** Why the result is degenerate (degenerateRunWarning()), or "". */
    std::string degenerate;
    double seconds{0.0};  //!< wall time of the run
    /** Wall time after the last frame: the final rectification and the
     * loop closer's catching up and polish (EntropySlam::finish()). */
    double seconds_after_last_frame{0.0};
    /** Against the ground truth (--gt), when given; `online_vs_gt` for
     * EntropySlam::onlinePoses() (trajectory_online.tum). */
    ///@{
    std::optional<eval::TrajectoryMetrics> egomotion_vs_gt, slam_vs_gt, online_vs_gt;
    ///@}
    /** The energy scan around the ground truth (--energy-scan), when made. */
    std::optional<MapperEnergyScan> energy_scan;
    /** The session continued (--load-session) or localized in (--localize),
     * and the one written (--save-session); "" for none. */
    ///@{
    std::string session_loaded, session_saved;
    ///@}
    bool localized{false};  //!< --localize
};

/** Distance between the first and last poses of a trajectory [m] (0 if < 2). */
double loopGap(const emslam::io::TumTrajectory& t);
double loopGap(const std::vector<emslam::rectify::TimedPose>& poses);

/** EntropySlam's poses as a TUM trajectory (timestamp, T_world_frame), the
 * form the trajectory files, the metrics and the drawings take. */
emslam::io::TumTrajectory tumTrajectoryOf(const std::vector<emslam::rectify::TimedPose>& poses);

/** What loopGap() of an estimate is called: "loop gap" when the ground truth
 * closes a loop (isClosedLoop()), "start-to-end distance" otherwise and
 * without ground truth (an open path's start-to-end distance is no error). */
std::string startToEndName(const emslam::io::TumTrajectory& ground_truth);

/** Mean time per frame of each stage [ms] (and the slowest frame's total). */
struct StageMeans
{
    /** Per stage, the total, and the slowest frame's total [ms]. */
    ///@{
    double stereo{0}, egomotion{0}, rectification{0}, total{0}, max_total{0};
    ///@}
};
StageMeans stageMeans(const std::vector<slam::FrameRecord>& frames);

/** Sums over every rectification, and the median / max time per call [ms]. */
struct RectificationTotals
{
    /** Attempts, successes, failures, and failures kept by the `ratio` rule. */
    ///@{
    std::size_t attempts{0}, successes{0}, failures{0}, accepted_worse{0};
    ///@}
    /** Calls whose changes `validate_phases` undid. */
    std::size_t rejected_by_validation{0};
    /** Of `failures`, grid successes that `confirm_phases` refused. */
    std::size_t unconfirmed{0};
    /** Calls that `hold_before_revisit` kept from changing anything. */
    std::size_t held_before_revisit{0};
    /** Time in all [s], median and largest per call [ms]. */
    ///@{
    double seconds{0}, median_ms{0}, max_ms{0};
    ///@}
};
RectificationTotals rectificationTotals(const std::vector<emslam::rectify::RectificationStats>& r);

/** stats.csv: one `frame` row per processed frame (times per stage, points,
 * matches before / after LWO, accepted, egomotion ok, energy) and one
 * `rectification` row per rectification (attempts, successes, failures,
 * energies, time). Empty cells where a column does not apply. */
void writeStatsCsv(const slam::EntropySlam& m, const std::string& file);

/** summary.json: frames, accepted, failures, ms per frame per stage,
 * rectification totals, final energy, loop gaps, run info, and the energy
 * scan's aggregate if one was made (energyScanJson()). */
void writeSummaryJson(
    const slam::EntropySlam& m, const MapperRunInfo& info, const std::string& file);

/** What the map drawings of a finished mapper show: the map cloud, the
 * `egomotion` and `slam` trajectories (tumTrajectoryOf() of its poses),
 * `ground_truth` (already in the map frame, see groundTruthInMapFrame(); may
 * be empty), the entropy map, and the `[EntropySlam] export_max_height` cut. The
 * trajectories must outlive the result. */
MapDrawingContent mapDrawingContent(
    const slam::EntropySlam& m,
    const emslam::io::TumTrajectory& egomotion,
    const emslam::io::TumTrajectory& slam,
    const emslam::io::TumTrajectory& ground_truth_in_map);

/** map.3Dscene for the stock SceneViewer3D (see buildMapScene()): the cloud
 * coloured by height, the egomotion (red), SLAM (green) and ground-truth
 * (blue, if not empty) trajectories, the entropy voxels and a legend, turned
 * so that the world's up (−y of the first camera) is the viewer's +Z. */
void writeScene(
    const slam::EntropySlam& m,
    const emslam::io::TumTrajectory& ground_truth,
    const std::string& file);

/** map.bt: the OctoMap of the keyframes' clouds inserted from their final
 * poses (slam::OctoMapBuilder, `[OctoMapBuilder]`), written with OctoMap's
 * OcTree::writeBinary() (maximum-likelihood, pruned: what `octovis` and
 * OcTree::readBinary() open). Nothing when `[OctoMapBuilder] resolution` is 0. */
void writeOctoMap(const slam::EntropySlam& m, const std::string& file);

/** map_top.png: the floor plan of the map with the trajectories (see
 * renderTopView()). */
void writeTopViewPng(
    const slam::EntropySlam& m,
    const emslam::io::TumTrajectory& ground_truth,
    const std::string& file);

/** map_grid.gridmap and map_grid.png: the 2D occupancy grid of the final
 * map (emslam::slam::OccupancyGridBuilder, `[OccupancyGridBuilder]`): an MRPT
 * COccupancyGridMap2D serialized into a gzip file, as MRPT's apps write
 * `.gridmap` files, and its picture (free white, occupied black, unknown
 * grey; forward to the right, left up). Nothing with `cell_size` 0. */
void writeOccupancyGrid(
    const slam::EntropySlam& m, const std::string& gridmap_file, const std::string& png_file);

/** entropy_map.bin: the serialized CEntropyVoxelMap (an MRPT CArchive of one
 * object; read back with `archiveFrom(stream).ReadObject()`). */
void writeEntropyMap(const slam::EntropySlam& m, const std::string& file);

/** entropy_map.3Dscene: the entropy map's 3D cells for SceneViewer3D (see
 * writeEntropyMapScene()), at most 50000. */
void writeEntropyMapView(const slam::EntropySlam& m, const std::string& file);

/** The report data of a finished mapper (ground truth optional). */
MapperReportData makeReportData(
    const slam::EntropySlam& m,
    const MapperRunInfo& info,
    const emslam::io::TumTrajectory& ground_truth);

}  // namespace emslam::apps
