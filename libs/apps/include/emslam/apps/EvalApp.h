// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/App.h>
#include <emslam/eval/MapAccuracy.h>
#include <emslam/eval/OccupancyGridAccuracy.h>
#include <emslam/eval/TrajectoryMetrics.h>
#include <emslam/io/TrajectoryReader.h>

#include <optional>
#include <string>

namespace emslam::apps
{
/** `emslam-eval`: measures an estimated trajectory against ground truth (see
 * TrajectoryMetrics): ATE RMSE after alignment, KITTI translational /
 * rotational drift, end-point error, loop gap, path length, matched poses.
 * Prints them and optionally writes them as JSON. Each file is TUM, KITTI
 * poses (with a times file, found beside it or given) or a EuRoC ground-truth
 * CSV, told from its content (emslam::io::loadTrajectory()) or forced.
 * With `--map` / `--map-gt` it also measures a map cloud against the true
 * surfaces (eval::MapAccuracy), with `--grid` / `--grid-gt` an occupancy
 * grid against the true floor plan (eval::OccupancyGridAccuracy); GT and EST
 * are then optional.
 *
 * \code
 * emslam-eval [GT EST] [--gt-format auto|tum|kitti|euroc]
 *   [--est-format auto|tum|kitti|euroc] [--gt-times TIMES] [--est-times TIMES]
 *   [--kitti-time-offset SECONDS] [--align se3|sim3|none] [--json OUT.json]
 *   [--max-dt SECONDS] [--segment-step N]
 *   [--map MAP.ply --map-gt REF.ply [--completeness-distance M] [--near-range M]]
 *   [--grid MAP.gridmap --grid-gt PLAN.gridmap [--grid-tolerance CELLS]]
 * \endcode
 * It has no INI parameters. \ingroup emslam_apps_grp \sa TrajectoryMetrics */
class EvalApp : public App
{
public:
    EvalApp();

    /** Options of the evaluation; tests may edit them between initialize() and run(). */
    eval::TrajectoryMetrics::Options options;
    eval::MapAccuracy::Options
        map_options;  //!< options of `--map` (completeness distance, near range)
    /** Cells of tolerance of the grid comparison. (Default: 1) */
    int grid_tolerance{1};

    // ---- Result of run() ----
    /** The trajectory metrics (ATE, KITTI segment errors, end error, loop gap). */
    eval::TrajectoryMetrics metrics;
    /** The formats read. */
    ///@{
    emslam::io::TrajectoryFormat gt_format{emslam::io::TrajectoryFormat::Tum};
    emslam::io::TrajectoryFormat est_format{emslam::io::TrajectoryFormat::Tum};
    ///@}
    /** True if both were KITTI without times, paired line by line. */
    bool paired_by_index{false};
    /** The map against the true surfaces (--map), the grid against the
     * true floor plan (--grid); unset when not asked for. */
    ///@{
    std::optional<eval::MapAccuracy> map_accuracy;
    std::optional<eval::OccupancyGridAccuracy> grid_accuracy;
    ///@}

protected:
    bool parseArguments(int argc, const char** argv) override;
    /** Reads both trajectories, computes and prints the metrics, writes the
     * JSON file. Throws with a message naming the file and the cause on a
     * missing, unreadable or empty trajectory, or when no timestamps match. */
    void execute() override;

private:
    struct Arguments;
    /** The inputs named (GT EST, --map/--map-gt, --grid/--grid-gt), checked to come in pairs. */
    void takeInputs(Arguments& args);
    /** The measuring options, checked. */
    void takeOptions(Arguments& args);
    /** Trajectory part of execute(): prints the metrics, returns their JSON. */
    std::string evaluateTrajectory();
    /** --map / --grid parts: print the figures, return their JSON members. */
    std::string evaluateMap();
    std::string evaluateGrid();

    std::string m_gt, m_est, m_json;
    std::string m_map, m_map_gt, m_grid, m_grid_gt;
    emslam::io::TrajectoryReadOptions m_gt_options, m_est_options;
};

}  // namespace emslam::apps
