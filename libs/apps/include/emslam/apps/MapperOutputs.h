// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/Mapper.h>
#include <emslam/apps/TrajectoryMetrics.h>

#include <optional>
#include <string>
#include <vector>

namespace emslam::apps
{
/** What a mapper run adds to its Mapper's results in summary.json. */
struct MapperRunInfo
{
    std::string rawlog;
    std::string config;
    std::size_t ignored_observations{0};  //!< observations neither stereo nor RGB-D
    bool interrupted{false};              //!< stopped by SIGINT / SIGTERM
    std::string input_ended_early;        //!< truncated / corrupt rawlog: where and why
    double seconds{0.0};                  //!< wall time of the run
    /** Against the ground truth (--gt), when given. */
    std::optional<TrajectoryMetrics> egomotion_vs_gt, slam_vs_gt;
};

/** Distance between the first and last poses of a trajectory [m] (0 if < 2). */
double loopGap(const emslam::stereo::TumTrajectory& t);

/** What loopGap() of an estimate is called: "loop gap" when the ground truth
 * closes a loop (isClosedLoop()), "start-to-end distance" otherwise and
 * without ground truth (an open path's start-to-end distance is no error). */
std::string startToEndName(const emslam::stereo::TumTrajectory& ground_truth);

/** Mean time per frame of each stage [ms] (and the slowest frame's total). */
struct StageMeans
{
    double stereo{0}, egomotion{0}, rectification{0}, total{0}, max_total{0};
};
StageMeans stageMeans(const std::vector<MapperFrameRecord>& frames);

/** Sums over every rectification, and the median / max time per call [ms]. */
struct RectificationTotals
{
    std::size_t attempts{0}, successes{0}, failures{0}, accepted_worse{0};
    double seconds{0}, median_ms{0}, max_ms{0};
};
RectificationTotals rectificationTotals(const std::vector<emslam::rectify::RectificationStats>& r);

/** stats.csv: one `frame` row per processed frame (times per stage, points,
 * matches before / after LWO, accepted, egomotion ok, energy) and one
 * `rectification` row per rectification (attempts, successes, failures,
 * energies, time). Empty cells where a column does not apply. */
void writeStatsCsv(const Mapper& m, const std::string& file);

/** summary.json: frames, accepted, failures, ms per frame per stage,
 * rectification totals, final energy, loop gaps, run info. */
void writeSummaryJson(const Mapper& m, const MapperRunInfo& info, const std::string& file);

/** map.3Dscene for the stock SceneViewer3D: the map cloud, the egomotion
 * (red) and SLAM (green) trajectories and a camera frustum at the start,
 * turned so that the world's up (−y of the first camera) is the viewer's +Z. */
void writeScene(const Mapper& m, const std::string& file);

/** entropy_map.bin: the serialized CEntropyVoxelMap (an MRPT CArchive of one
 * object; read back with `archiveFrom(stream).ReadObject()`). */
void writeEntropyMap(const Mapper& m, const std::string& file);

/** The report data of a finished mapper (ground truth optional). */
MapperReportData makeReportData(
    const Mapper& m, const MapperRunInfo& info, const emslam::stereo::TumTrajectory& ground_truth);

}  // namespace emslam::apps
