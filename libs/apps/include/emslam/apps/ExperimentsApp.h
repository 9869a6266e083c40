// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/App.h>
#include <emslam/apps/ExperimentRunner.h>
#include <emslam/apps/ExperimentSuite.h>

#include <string>
#include <vector>

namespace emslam::apps
{
/** `emslam-experiments`: every experiment of the paper in one command. For
 * each experiment of the suite INI, each mapper configuration (energy) and
 * each world seed: render the simulated world, map it, measure it against
 * the exact ground truth; then write `experiments.md`, `experiments.json`
 * and `experiments.html` (rewritten after every run), and per run its
 * trajectories, `summary.json` and `report.html` under `runs/`.
 *
 * \code
 * emslam-experiments SUITE.ini --out DIR [--only NAME[,NAME...]] [--seeds 1,2,3]
 *                    [--variants NAME[,NAME...]] [--set Section.key=value ...]
 *                    [--quick] [--exact-depth] [--energy-scan] [--quiet]
 * \endcode
 * - `--variants`: only these of the suite's variants (ExperimentVariant);
 *   `--set`: overrides applied to every run, after the variant's.
 * - `--quick`: only the suite's `quick_frames` first frames of each run and,
 *   unless `--seeds` is given, only the first seed (a smoke test of the
 *   whole chain, a minute).
 * - `--exact-depth`: the mapper gets the renderer's exact depth (an RGB-D
 *   observation) instead of the stereo pair: what the method does without
 *   stereo noise.
 * - `--energy-scan`: each run's final trajectory is scanned around the
 *   ground truth (emslam::rectify::scanEnergy()): `energy_scan.csv` beside
 *   its outputs, its aggregate in summary.json and three scan columns.
 * - Ctrl-C (SIGINT) or SIGTERM: the running run stops, and the tables are
 *   written for the runs that finished.
 * \ingroup emslam_apps_grp \sa ExperimentSuite, runExperiment() */
class ExperimentsApp : public App
{
public:
    ExperimentsApp();

    /** The finished runs of the last run(). */
    const std::vector<ExperimentResult>& results() const { return m_results; }

protected:
    bool parseArguments(int argc, const char** argv) override;
    /** Runs every selected experiment and writes the outputs. */
    void execute() override;

private:
    bool m_quick{false};
    bool m_exact_depth{false};
    bool m_energy_scan{false};
    std::string m_suite_file, m_out, m_command;
    std::vector<ExperimentSpec> m_experiments;
    std::vector<ExperimentVariant> m_variants;
    std::vector<int> m_seeds;
    std::size_t m_quick_frames{0};
    std::vector<ExperimentResult> m_results;
};

}  // namespace emslam::apps
