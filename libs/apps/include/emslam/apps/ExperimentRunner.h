// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/ExperimentSuite.h>
#include <emslam/io/TumTrajectory.h>
#include <emslam/rectify/EnergyScan.h>
#include <emslam/slam/EntropySlam.h>

#include <cmath>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>

namespace emslam::apps
{
/** What one run (experiment × mapper × seed) measured: one row of the
 * experiments table. Gaps are the end-point errors of the trajectory once
 * anchored to the ground truth at its first pose: on a loop whose ground
 * truth closes this is the paper's loop gap, the distance between the first
 * and last poses. \ingroup emslam_apps_grp \sa runExperiment() */
struct ExperimentResult
{
    /** The experiment's name, title and the paper's figure it reproduces. */
    ///@{
    std::string experiment, title, figure;
    ///@}
    std::string mapper;       //!< the mapper INI's file name
    std::string energy;       //!< e.g. "planar_low_structured"
    std::string label;        //!< the paper's name of the energy, e.g. "Exp. 11"
    std::string variant;      //!< ExperimentVariant::name (empty: the only one)
    int seed{1};              //!< the world's and the egomotion's seed
    bool loop{true};          //!< the ground truth returns to its start (the gap is a loop gap)
    bool interrupted{false};  //!< stopped by Ctrl-C: a partial run

    /** Frames read, stereo observations, failed egomotion steps. */
    ///@{
    std::size_t frames{0}, observations{0}, egomotion_failures{0};
    ///@}
    double path_m{0};           //!< ground-truth path length [m]
    double egomotion_gap_m{0};  //!< end-point error of the egomotion [m]
    double slam_gap_m{0};       //!< end-point error of SLAM (last accepted frame) [m]
    double egomotion_ate_m{0};  //!< ATE RMSE after SE(3) alignment [m]
    double slam_ate_m{0};       //!< ATE RMSE of SLAM after SE(3) alignment [m]
    /** The maps against the true surfaces the frames saw (eval::MapAccuracy,
     * sim::SurfaceSampler out to the mapper's [StereoMatcher] max_range): SLAM's
     * map cloud, and the same keyframe clouds placed by the egomotion.
     * Accuracy median and 90th percentile [m], completeness within 5 cm
     * [0, 1]; NaN when not measured. */
    ///@{
    double slam_map_median_m{NAN}, slam_map_p90_m{NAN}, slam_map_completeness{NAN};
    double egomotion_map_median_m{NAN}, egomotion_map_p90_m{NAN}, egomotion_map_completeness{NAN};
    ///@}
    /** Mean time per frame of the stereo front-end and the egomotion [ms]. */
    ///@{
    double ms_stereo{0}, ms_egomotion{0};  //!< mean per frame [ms]
    ///@}
    /** Rectification calls, their attempts and successes. */
    ///@{
    std::size_t rectifications{0}, attempts{0}, successes{0};
    ///@}
    /** Median and largest time per rectification call [ms]. */
    ///@{
    double rect_median_ms{0}, rect_max_ms{0};  //!< per call [ms]
    ///@}
    /** The paper's entropy (no prior) of the final map's elements placed by
     * the ground truth, by the egomotion and by SLAM (the output
     * trajectory): is the minimum at the truth, and did the search reach it? */
    ///@{
    double entropy_truth{0}, entropy_egomotion{0}, entropy_slam{0};
    ///@}
    /** The same entropy at the rectifier's own element poses, before loop
     * closing moved them (equal to entropy_slam without loop closing). */
    double entropy_rectified{0};
    /** How much the entropy of the same true map changes when the whole map
     * is moved by 1/4, 1/2 and 3/4 of a cell along (1, 1, 1): max − min over
     * the four grid phases. A rectification whose "gain" is smaller than this
     * moves the map against the grid, not towards the truth. */
    double entropy_phase_spread{0};
    /** The energy scan around the ground truth (ExperimentRunOptions::energy_scan). */
    std::optional<emslam::rectify::EnergyScanSummary> energy_scan;
    double seconds{0};  //!< wall time of the run (rendering included, the energy scan not) [s]

    /** The paper's figures for this experiment and energy (NaN: not given). */
    ///@{
    double paper_path_m, paper_observations, paper_egomotion_gap_m, paper_slam_gap_m;
    ///@}

    /** For the pictures: every frame's ground truth and egomotion, SLAM's accepted frames. */
    ///@{
    emslam::io::TumTrajectory ground_truth, egomotion, slam;
    ///@}

    /** Egomotion's gap as a percentage of the path. */
    double egomotionGapPercent() const { return 100.0 * egomotion_gap_m / path_m; }
    /** SLAM's gap as a percentage of the path. */
    double slamGapPercent() const { return 100.0 * slam_gap_m / path_m; }
};

/** The paper's name of an energy: "Exp. 8" (unstructured) ... "Exp. 12"
 * (planar_structured). \ingroup emslam_apps_grp */
std::string paperEnergyLabel(const std::string& energy);

/** How runExperiment() runs. */
struct ExperimentRunOptions
{
    /** `Section.key=value` overrides applied after the spec's `set` (a
     * variant's, the command line's). */
    std::vector<std::string> sets;
    /** ExperimentResult::variant of the result. */
    std::string variant;
    /** Frames rendered and mapped (0: the whole trajectory). */
    std::size_t max_frames{0};
    /** Folder for this run's trajectories, summary.json and report.html
     * (empty: none written). */
    std::string out_dir;
    /** Feed the mapper the renderer's exact depth (as an RGB-D camera would,
     * within the mapper's [StereoMatcher] min_range..max_range) instead of the
     * stereo pair: an oracle that tells what stereo noise costs. */
    bool exact_depth{false};
    /** Scan the final trajectory's entropy around the ground truth
     * (emslam::rectify::scanEnergy()): ExperimentResult::energy_scan, and
     * `energy_scan.csv` in `out_dir`. */
    bool energy_scan{false};
    /** Measure the maps against the true surfaces (ExperimentResult's
     * slam_map_* and egomotion_map_*): some seconds per run. */
    bool map_accuracy{true};
    /** Called after every frame with (frames done, frames in all); return
     * false to stop the run early (Ctrl-C). */
    std::function<bool(std::size_t, std::size_t)> on_frame;
};

/** The mapper parameters of run `mapper_index` of `spec`: its INI, then the
 * spec's `set`, then `sets`. Throws naming the file on an unreadable INI,
 * an unknown key or a bad value, so that a suite can be checked before its
 * first run. \ingroup emslam_apps_grp */
slam::EntropySlam::TParameters experimentMapperParameters(
    const ExperimentSpec& spec, std::size_t mapper_index, const std::vector<std::string>& sets);

/** Renders the world of `spec` with world seed `seed`, maps it with mapper
 * INI `mapper_index` (plus the spec's `set` overrides, then the options') and measures the
 * result against the exact ground truth. Throws naming the file on bad
 * configuration. \ingroup emslam_apps_grp */
ExperimentResult runExperiment(
    const ExperimentSpec& spec,
    std::size_t mapper_index,
    int seed,
    const ExperimentRunOptions& options);

}  // namespace emslam::apps
