// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace emslam::apps
{
/** One experiment of the paper (§3): a simulated world, the mapper
 * configurations (energies) the paper compares on it, and the paper's own
 * figures to put beside ours.
 * \ingroup emslam_apps_grp \sa ExperimentSuite */
struct ExperimentSpec
{
    std::string name;    //!< its INI section, e.g. `hall_double_loop`
    std::string title;   //!< e.g. "Hall double loop (3DOF robot)"
    std::string figure;  //!< the paper's figure, e.g. "Fig. 17"
    std::string world;   //!< world INI (emslam-sim), path resolved
    /** The ground truth returns to its start: the loop gap is the figure. */
    bool loop{true};
    /** Mapper INIs, one run each (path resolved). */
    std::vector<std::string> mappers;
    /** `Section.key=value` overrides applied to every mapper INI. */
    std::vector<std::string> sets;
    /** `Section.key=value` overrides of keys of the world INI (e.g. a lower
     * `Simulation.fps`): one world file, several regimes. */
    std::vector<std::string> world_sets;
    /** The paper's path length [m], observations and egomotion loop gap [m];
     * NaN where the paper gives none. */
    ///@{
    double paper_path_m;
    double paper_observations;
    double paper_egomotion_gap_m;
    ///@}
    /** The paper's SLAM loop gap [m] per mapper (NaN: not given). */
    std::vector<double> paper_slam_gap_m;
};

/** One way of running every experiment of a suite: overrides applied to
 * every mapper INI after the experiment's own `set`, e.g. `paper`
 * (`LoopCloser.enabled=false`: the paper's method alone) beside `full`
 * (none: everything the configs ship). \ingroup emslam_apps_grp */
struct ExperimentVariant
{
    std::string name;               //!< a column of the tables; empty: the only, unnamed one
    std::vector<std::string> sets;  //!< `Section.key=value`
};

/** The experiment set `emslam-experiments` runs, from an INI file:
 * \code
 * [Experiments]
 * experiments = hall_double_loop three_corridors   ; section names, in order
 * seeds = 1 2 3                                    ; world seeds (--seeds overrides)
 * quick_frames = 60                                ; frames per run with --quick
 * variants = paper full                            ; optional: [Variants] keys, in order
 *
 * [Variants]                                       ; needed with `variants`
 * paper = LoopCloser.enabled=false                 ; overrides, after each `set`
 * full =                                           ; none
 *
 * [hall_double_loop]
 * title = Hall double loop (3DOF robot)
 * figure = Fig. 17
 * world = ../sim/hall_double_loop.ini              ; relative to this file
 * loop = true
 * mappers = ../mapper/3dof-low-structured.ini ../mapper/3dof-structured.ini
 * set = Rectifier.mode=serial                      ; optional, for every mapper
 * world_set = Simulation.fps=1.2                   ; optional, keys the world INI has
 * paper_path_m = 129.41
 * paper_observations = 308
 * paper_egomotion_gap_m = 2.03
 * paper_slam_gap_m = 0.11 0.11                     ; one per mapper, '-' if none
 * \endcode
 * \ingroup emslam_apps_grp */
struct ExperimentSuite
{
    std::vector<ExperimentSpec> experiments;  //!< in the order of the file
    std::vector<int> seeds{1, 2, 3};          //!< world seeds of every run (`--seeds` overrides)
    std::size_t quick_frames{60};             //!< frames per run with `--quick`
    /** At least one (without `variants`: one unnamed, with no overrides). */
    std::vector<ExperimentVariant> variants{ExperimentVariant{}};

    /** Reads and checks `file`: unknown sections and keys (with the closest
     * valid name), missing worlds or mapper INIs, list lengths that do not
     * match and bad numbers throw std::invalid_argument naming the file,
     * section and key. */
    static ExperimentSuite load(const std::string& file);

    /** The experiments named in `only` (comma-separated; empty: all), in the
     * suite's order; throws naming an unknown name and the valid ones. */
    std::vector<ExperimentSpec> select(const std::string& only) const;
    /** The variants named in `only` (comma-separated; empty: all), in the
     * suite's order; throws naming an unknown name and the valid ones. */
    std::vector<ExperimentVariant> selectVariants(const std::string& only) const;
};

/** "1,2,3" or "1 2 3" → {1, 2, 3}; throws std::invalid_argument on anything
 * that is not a list of integers. \ingroup emslam_apps_grp */
std::vector<int> parseSeedList(const std::string& text);

}  // namespace emslam::apps
