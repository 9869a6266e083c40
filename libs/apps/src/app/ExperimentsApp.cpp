// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>
#include <emslam/apps/ConfigLookup.h>
#include <emslam/apps/ExperimentReport.h>
#include <emslam/apps/ExperimentsApp.h>
#include <emslam/apps/ProgressLine.h>
#include <emslam/apps/StopSignal.h>
#include <emslam/io/InputOutputClash.h>
#include <emslam/io/OutputPathChecks.h>

#include <mrpt/core/bits_math.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace emslam::apps
{
namespace
{
constexpr const char* PROGRAM = "emslam-experiments";

/** Every (variant, seed) pair, the seeds of one variant together: the table
 * shows a variant's seeds and their median, then the next variant's. */
std::vector<std::pair<const ExperimentVariant*, int>> runsOf(
    const std::vector<ExperimentVariant>& variants, const std::vector<int>& seeds)
{
    std::vector<std::pair<const ExperimentVariant*, int>> runs;
    for (const auto& v : variants)
    {
        for (const int seed : seeds)
        {
            runs.emplace_back(&v, seed);
        }
    }
    return runs;
}
}  // namespace

ExperimentsApp::ExperimentsApp() : App(PROGRAM) {}

bool ExperimentsApp::parseArguments(int argc, const char** argv)
{
    TCLAP::CmdLine cmd(
        "emslam-experiments: the paper's experiments (section 3) in one command. Each "
        "experiment of SUITE.ini names a simulated world and the mapper configurations "
        "(energies) the paper compares on it; every one is rendered, mapped and measured "
        "against the exact ground truth for each seed, and the results are tabulated in "
        "DIR/experiments.md, .json and .html beside the paper's figures.",
        ' ', "0.1");
    TCLAP::UnlabeledValueArg<std::string> suite(
        "suite",
        "Experiment set INI ([Experiments] + one section per experiment), or the name of a "
        "shipped one (paper, rectification: share/emslam/config/experiments)",
        true, "", "SUITE.ini", cmd);
    TCLAP::ValueArg<std::string> out(
        "o", "out", "Output folder (created if needed)", true, "", "DIR", cmd);
    TCLAP::ValueArg<std::string> only(
        "", "only", "Only these experiments (comma-separated section names)", false, "",
        "NAME[,NAME]", cmd);
    TCLAP::ValueArg<std::string> seeds(
        "", "seeds", "World seeds (default: [Experiments] seeds of the suite)", false, "",
        "S[,S...]", cmd);
    TCLAP::ValueArg<std::string> variants(
        "", "variants",
        "Only these variants of the suite ([Experiments] variants; default: all of them)", false,
        "", "NAME[,NAME]", cmd);
    addSetOption(
        cmd,
        "Override a mapper parameter in every run (after the experiment's set and the "
        "variant's): SECTION.key=value");
    TCLAP::SwitchArg quick(
        "", "quick",
        "Smoke run: the first [Experiments] quick_frames frames of each run, and only the "
        "first seed unless --seeds is given",
        cmd);
    TCLAP::SwitchArg exact_depth(
        "", "exact-depth",
        "Feed the mapper the renderer's exact depth (as an RGB-D camera) instead of the stereo "
        "pair: what the method does without stereo noise",
        cmd);
    TCLAP::SwitchArg energy_scan(
        "", "energy-scan",
        "Scan each run's entropy along each dimension of a few actions around the ground truth "
        "(is its minimum at the truth?): energy_scan.csv per run and three scan columns in the "
        "tables",
        cmd);
    addQuietOption(cmd, "No progress lines");
    if (!parseCommandLine(cmd, argc, argv))
    {
        return false;
    }
    m_command = PROGRAM;
    for (int i = 1; i < argc; ++i)
    {
        m_command += std::string(" ") + argv[i];
    }
    m_suite_file = findConfigFile(suite.getValue(), "experiments");
    m_out = out.getValue();
    m_quick = quick.getValue();
    m_exact_depth = exact_depth.getValue();
    m_energy_scan = energy_scan.getValue();
    const ExperimentSuite s = ExperimentSuite::load(m_suite_file);
    m_experiments = s.select(only.getValue());
    m_variants = s.selectVariants(variants.getValue());
    for (auto& v : m_variants)
    {
        v.sets.insert(v.sets.end(), overrides().begin(), overrides().end());
    }
    // Before hours of runs: every configuration must load.
    for (const auto& e : m_experiments)
    {
        for (std::size_t m = 0; m < e.mappers.size(); ++m)
        {
            for (const auto& v : m_variants)
            {
                try
                {
                    experimentMapperParameters(e, m, v.sets);
                }
                catch (const std::exception& ex)
                {
                    throw std::invalid_argument(
                        "[" + e.name + "]" + (v.name.empty() ? "" : " variant '" + v.name + "'") +
                        ": " + ex.what());
                }
            }
        }
    }
    m_seeds = seeds.isSet() ? parseSeedList(seeds.getValue()) : s.seeds;
    if (m_quick && !seeds.isSet())
    {
        m_seeds.resize(1);
    }
    m_quick_frames = s.quick_frames;
    // Before hours of runs: an --out that cannot take the reports fails now.
    io::requireOutputFolder(m_out, "output folder");
    io::requireReplaceableFiles(m_out, {"experiments.md", "experiments.json", "experiments.html"});
    std::vector<io::RolePath> inputs{{"the suite", m_suite_file}};
    for (const auto& e : m_experiments)
    {
        inputs.push_back({"the world of [" + e.name + "]", e.world});
        for (const auto& m : e.mappers)
        {
            inputs.push_back({"a mapper config of [" + e.name + "]", m});
        }
    }
    io::requireOutputsAreNotInputs(
        io::filesOfOutputFolder(
            m_out, {"experiments.md", "experiments.json", "experiments.html"}, "report"),
        inputs);
    return true;
}

void ExperimentsApp::execute()
{
    const auto t_start = std::chrono::steady_clock::now();
    io::createOutputFolder(m_out);
    std::size_t total = 0;
    for (const auto& e : m_experiments)
    {
        total += e.mappers.size() * m_variants.size() * m_seeds.size();
    }
    ExperimentReportInfo info;
    info.command = m_command;
    info.suite_file = m_suite_file;
    info.quick = m_quick;
    info.exact_depth = m_exact_depth;
    m_results.clear();

    StopSignal::clear();
    const StopSignalGuard signals;
    std::size_t k = 0;
    for (const auto& e : m_experiments)
    {
        for (std::size_t m = 0; m < e.mappers.size() && !StopSignal::requested(); ++m)
        {
            for (const auto& [variant, seed] : runsOf(m_variants, m_seeds))
            {
                if (StopSignal::requested())
                {
                    break;
                }
                ++k;
                const std::string mapper = std::filesystem::path(e.mappers[m]).stem().string();
                const std::string what = "[" + std::to_string(k) + "/" + std::to_string(total) +
                                         "] " + e.name + " " + mapper +
                                         (variant->name.empty() ? "" : " " + variant->name) +
                                         " seed " + std::to_string(seed);
                ProgressLine progress(std::string(PROGRAM) + ": " + what, 1, !quiet());
                ExperimentRunOptions opt;
                opt.max_frames = m_quick ? m_quick_frames : 0;
                opt.exact_depth = m_exact_depth;
                opt.energy_scan = m_energy_scan;
                opt.sets = variant->sets;
                opt.variant = variant->name;
                opt.out_dir = m_out + "/runs/" + e.name + "/" + mapper + "/" +
                              (variant->name.empty() ? "" : variant->name + "/") + "seed" +
                              std::to_string(seed);
                opt.on_frame = [&](std::size_t done, std::size_t n)
                {
                    progress.updateFraction(done, static_cast<double>(done) / n);
                    return !StopSignal::requested();
                };
                ExperimentResult r = runExperiment(e, m, seed, opt);
                progress.finish();
                if (r.interrupted)
                {
                    break;  // what finished is written below
                }
                if (!quiet())
                {
                    std::fprintf(
                        stderr,
                        "%s: %s: %s %.3f -> %.3f m (%.2f -> %.2f %% of %.1f m), ATE %.3f -> %.3f "
                        "m, %.0f s\n",
                        PROGRAM, what.c_str(), e.loop ? "loop gap" : "end error", r.egomotion_gap_m,
                        r.slam_gap_m, r.egomotionGapPercent(), r.slamGapPercent(), r.path_m,
                        r.egomotion_ate_m, r.slam_ate_m, r.seconds);
                    if (r.energy_scan)
                    {
                        std::fprintf(
                            stderr,
                            "%s: %s: energy scan: minimum at the truth on %zu of %zu lines, "
                            "median |argmin| %.3f m / %.2f deg, %.1f s\n",
                            PROGRAM, what.c_str(), r.energy_scan->lines_at_truth,
                            r.energy_scan->lines, r.energy_scan->median_abs_argmin_translation_m,
                            mrpt::RAD2DEG(r.energy_scan->median_abs_argmin_rotation_rad),
                            r.energy_scan->seconds);
                    }
                }
                m_results.push_back(std::move(r));
                info.seconds =
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start)
                        .count();
                writeExperimentReports(m_out, m_results, info);
            }
        }
    }
    info.interrupted = StopSignal::requested();
    info.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    writeExperimentReports(m_out, m_results, info);
    if (info.interrupted)
    {
        std::fprintf(
            stderr, "%s: interrupted; the tables hold the %zu finished runs\n", PROGRAM,
            m_results.size());
    }
    std::printf(
        "%s: %zu runs in %.1f min; tables in '%s/experiments.md', .json, .html\n", PROGRAM,
        m_results.size(), info.seconds / 60.0, m_out.c_str());
}

}  // namespace emslam::apps
