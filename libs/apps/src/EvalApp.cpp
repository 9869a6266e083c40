// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>
#include <emslam/apps/EvalApp.h>
#include <emslam/io/InputOutputClash.h>
#include <emslam/io/OutputFile.h>
#include <emslam/io/TrajectoryInput.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/core/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <utility>

namespace emslam::apps
{
namespace
{
constexpr const char* PROGRAM = "emslam-eval";

/** "%.3f" or "n/a" for NaN (no drift segment fits). */
std::string fmt(double v, const char* f = "%.4f")
{
    if (!std::isfinite(v))
    {
        return "n/a";
    }
    char buf[64];
    std::snprintf(buf, sizeof(buf), f, v);
    return buf;
}
}  // namespace

EvalApp::EvalApp() : App(PROGRAM) {}

bool EvalApp::parseArguments(int argc, const char** argv)
{
    TCLAP::CmdLine cmd(
        "emslam-eval: an estimated trajectory against ground truth (each TUM, KITTI poses + "
        "times or EuRoC ground-truth CSV, told from the content): ATE RMSE after alignment, "
        "KITTI drift, end-point error, loop gap, path length.",
        ' ', "0.1");
    TCLAP::UnlabeledValueArg<std::string> gt(
        "gt", "Ground-truth trajectory (TUM, KITTI poses or EuRoC CSV)", true, "", "GT", cmd);
    TCLAP::UnlabeledValueArg<std::string> est(
        "est", "Estimated trajectory (TUM, KITTI poses or EuRoC CSV)", true, "", "EST", cmd);
    TCLAP::ValueArg<std::string> gt_format_arg(
        "", "gt-format",
        withDefault("Format of GT: auto (from the content), tum, kitti or euroc", "auto"), false,
        "auto", "auto|tum|kitti|euroc", cmd);
    TCLAP::ValueArg<std::string> est_format_arg(
        "", "est-format",
        withDefault("Format of EST: auto (from the content), tum, kitti or euroc", "auto"), false,
        "auto", "auto|tum|kitti|euroc", cmd);
    TCLAP::ValueArg<std::string> gt_times(
        "", "gt-times",
        "Times file of a KITTI GT (default: found beside it, e.g. sequences/NN/times.txt for "
        "poses/NN.txt)",
        false, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> est_times(
        "", "est-times", "Times file of a KITTI EST (default: found beside it)", false, "", "FILE",
        cmd);
    TCLAP::ValueArg<double> kitti_time_offset(
        "", "kitti-time-offset",
        "UNIX time [s] added to KITTI sequence times (times.txt values below 1e9), as "
        "emslam-import kitti does",
        false, emslam::io::KittiSequence::DEFAULT_TIME_OFFSET, "SECONDS", cmd);
    TCLAP::ValueArg<std::string> align(
        "", "align",
        withDefault("Alignment before the ATE: se3 (rigid), sim3 (with scale) or none", "se3"),
        false, "se3", "se3|sim3|none", cmd);
    TCLAP::ValueArg<std::string> json(
        "", "json", "Also write the metrics to this JSON file", false, "", "FILE", cmd);
    TCLAP::ValueArg<double> max_dt(
        "", "max-dt",
        withDefault(
            "Largest time difference of an associated pose pair [s]",
            mrpt::format("%g", options.max_dt)),
        false, options.max_dt, "SECONDS", cmd);
    TCLAP::ValueArg<long long> step(
        "", "segment-step",
        withDefault(
            "Drift segments start every N matched poses", std::to_string(options.segment_step)),
        false, static_cast<long long>(options.segment_step), "N", cmd);

    if (!parseCommandLine(cmd, argc, argv, {{"--gt", "", 0, "GT"}, {"--est", "", 1, "EST"}}))
    {
        return false;
    }
    m_gt = gt.getValue();
    m_est = est.getValue();
    for (auto [arg, o] :
         {std::pair{&gt_format_arg, &m_gt_options}, {&est_format_arg, &m_est_options}})
    {
        try
        {
            o->format = emslam::io::parseTrajectoryFormat(arg->getValue());
        }
        catch (const std::invalid_argument& e)
        {
            throw std::invalid_argument("--" + arg->getName() + ": " + e.what());
        }
    }
    m_gt_options.times_file = gt_times.getValue();
    m_est_options.times_file = est_times.getValue();
    if (!std::isfinite(kitti_time_offset.getValue()))
    {
        throw std::invalid_argument("--kitti-time-offset must be a finite number of seconds");
    }
    m_gt_options.kitti_time_offset = m_est_options.kitti_time_offset = kitti_time_offset.getValue();
    m_json = json.getValue();
    try
    {
        options.alignment = eval::parseAlignment(align.getValue());
    }
    catch (const std::invalid_argument&)
    {
        throw std::invalid_argument(
            "bad --align value '" + align.getValue() + "': expected se3, sim3 or none");
    }
    options.max_dt = max_dt.getValue();
    if (!(options.max_dt > 0) || !std::isfinite(options.max_dt))
    {
        throw std::invalid_argument("--max-dt must be a positive number of seconds");
    }
    options.segment_step = countOption(step.getValue(), "--segment-step", 1, PROGRAM);
    io::requireOutputsAreNotInputs(
        {{"the JSON output (--json)", m_json}},
        {{"the ground truth", m_gt},
         {"the estimate", m_est},
         {"the ground-truth times (--gt-times)", m_gt_options.times_file},
         {"the estimate's times (--est-times)", m_est_options.times_file}});
    return true;
}

void EvalApp::execute()
{
    const auto gt = io::loadTrajectoryInput(m_gt, "ground-truth", m_gt_options);
    const auto est = io::loadTrajectoryInput(m_est, "estimate", m_est_options);
    io::requireComparableTimes(gt, m_gt, est, m_est);
    gt_format = gt.format;
    est_format = est.format;
    paired_by_index = !gt.timed;
    try
    {
        metrics = eval::TrajectoryMetrics::compute(gt.trajectory, est.trajectory, options);
    }
    catch (const std::runtime_error& e)
    {
        throw std::runtime_error(
            std::string(e.what()) + "; ground truth '" + m_gt + "', estimate '" + m_est + "'");
    }
    const auto& m = metrics;
    std::string lengths = "none";
    if (!m.rel.lengths_m.empty())
    {
        lengths = fmt(m.rel.lengths_m.front(), "%.1f") + ".." +
                  fmt(m.rel.lengths_m.back(), "%.1f") + " m";
    }
    std::printf(
        "formats            ground truth %s, estimate %s%s\n",
        emslam::io::trajectoryFormatName(gt.format).c_str(),
        emslam::io::trajectoryFormatName(est.format).c_str(),
        paired_by_index ? " (no times: paired line by line)" : "");
    std::printf(
        "matched poses      %zu (ground truth %zu, estimate %zu, max dt %g s)\n"
        "alignment          %s (scale %.6f)\n"
        "ATE RMSE           %s m\n"
        "t_rel              %s %%\n"
        "r_rel              %s deg/m\n"
        "drift segments     %zu (lengths %s, every %zu poses)\n"
        "end-point error    %s m\n"
        "loop gap           %s m (first to last estimated pose)\n"
        "path length        %s m (ground truth; estimate %s m)\n",
        m.matched_poses, m.gt_poses, m.est_poses, options.max_dt,
        eval::alignmentName(m.alignment).c_str(), m.align.scale, fmt(m.ate_rmse_m).c_str(),
        fmt(m.rel.t_rel_percent, "%.3f").c_str(), fmt(m.rel.r_rel_deg_per_m, "%.5f").c_str(),
        m.rel.segments, lengths.c_str(), options.segment_step, fmt(m.end_error_m).c_str(),
        fmt(m.loop_gap_m).c_str(), fmt(m.path_length_m, "%.3f").c_str(),
        fmt(m.est_path_length_m, "%.3f").c_str());
    if (!m_json.empty())
    {
        io::OutputFile f(m_json);
        f.text() << m.toJson();
        f.close();
        std::printf("metrics written to '%s'\n", m_json.c_str());
    }
}

}  // namespace emslam::apps
