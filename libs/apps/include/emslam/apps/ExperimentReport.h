// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/ExperimentRunner.h>

#include <string>
#include <vector>

namespace emslam::apps
{
/** What the three experiment files say besides the rows. */
struct ExperimentReportInfo
{
    std::string command;      //!< the command line that made them
    std::string suite_file;   //!< the experiment INI
    bool quick{false};        //!< --quick: partial trajectories
    bool exact_depth{false};  //!< --exact-depth: the renderer's depth, not stereo
    bool interrupted{false};  //!< Ctrl-C: only the finished runs
    double seconds{0};        //!< wall time so far [s]
};

/** Writes `DIR/experiments.md`, `DIR/experiments.json` and
 * `DIR/experiments.html` (each through a `.partial` file): one row per run,
 * plus a median row per experiment and energy over its seeds, with the
 * paper's figures beside ours; the HTML page adds an inline SVG top view of
 * the ground truth, egomotion and SLAM trajectories per experiment and
 * energy (first seed), like the paper's figures. Throws naming the file if
 * one cannot be written. \ingroup emslam_apps_grp */
void writeExperimentReports(
    const std::string& dir,
    const std::vector<ExperimentResult>& results,
    const ExperimentReportInfo& info);

/** The column keys of experiments.json's rows, in table order (what a test
 * checks the files against). \ingroup emslam_apps_grp */
std::vector<std::string> experimentColumnKeys();

}  // namespace emslam::apps
