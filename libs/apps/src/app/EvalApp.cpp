// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>
#include <emslam/apps/EvalApp.h>
#include <emslam/apps/PlyFile.h>
#include <emslam/io/InputFileChecks.h>
#include <emslam/io/InputOutputClash.h>
#include <emslam/io/OutputFile.h>
#include <emslam/io/TrajectoryInput.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

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

/** `"key": object` as a member of an enclosing JSON object (indented). */
std::string jsonMember(const std::string& key, const std::string& object)
{
    std::string out = "  \"" + key + "\": ";
    for (std::size_t i = 0; i < object.size(); ++i)
    {
        out += object[i];
        if (object[i] == '\n' && i + 1 < object.size())
        {
            out += "  ";
        }
    }
    while (!out.empty() && out.back() == '\n')
    {
        out.pop_back();
    }
    return out;
}

/** An MRPT occupancy grid from a (gz-compressed or plain) serialized file. */
mrpt::maps::COccupancyGridMap2D loadGrid(const std::string& file, const std::string& what)
{
    io::requireInputFile(file, what);
    mrpt::maps::COccupancyGridMap2D grid;
    try
    {
        mrpt::io::CFileGZInputStream f(file);
        mrpt::serialization::archiveFrom(f) >> grid;
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error(
            "'" + file + "' is not an MRPT occupancy grid (" +
            emslam::util::shortExceptionMessage(e) + ")");
    }
    return grid;
}

std::vector<mrpt::math::TPoint3Df> loadMapCloud(const std::string& file)
{
    io::requireInputFile(file, "map cloud (--map)");
    return loadPly(file).points;
}
}  // namespace

EvalApp::EvalApp() : App(PROGRAM) {}

/** The command line of emslam-eval, each argument added to `cmd` in the
 * order of its help; defaults from the app's settings. */
struct EvalApp::Arguments
{
    explicit Arguments(const EvalApp& app_defaults) : app(app_defaults) {}

    const EvalApp& app;
    TCLAP::CmdLine cmd{
        "emslam-eval: an estimated trajectory against ground truth (each TUM, KITTI poses + "
        "times or EuRoC ground-truth CSV, told from the content): ATE RMSE after alignment, "
        "KITTI drift, end-point error, loop gap, path length.",
        ' ', "0.1"};
    // One optional multi-argument: TCLAP allows no unlabeled argument after an
    // optional one, and both are optional when only a map is measured.
    TCLAP::UnlabeledMultiArg<std::string> trajectories{
        "trajectories",
        "GT EST: the ground-truth trajectory, then the estimate (each TUM, KITTI poses or EuRoC "
        "CSV)",
        false, "GT EST", cmd};
    TCLAP::ValueArg<std::string> map_arg{
        "",
        "map",
        "A map cloud (PLY, e.g. the mapper's map.ply) to measure against --map-gt; with GT "
        "EST it is first moved by the trajectory's --align alignment",
        false,
        "",
        "MAP.ply",
        cmd};
    TCLAP::ValueArg<std::string> map_gt_arg{
        "",        "map-gt", "The true surfaces (PLY of 'emslam-sim --map-gt-out')", false, "",
        "REF.ply", cmd};
    TCLAP::ValueArg<double> completeness_arg{
        "",
        "completeness-distance",
        withDefault(
            "A true surface sample is covered if a map point is this close [m]",
            mrpt::format("%g", app.map_options.completeness_distance)),
        false,
        app.map_options.completeness_distance,
        "M",
        cmd};
    TCLAP::ValueArg<double> near_arg{
        "",
        "near-range",
        withDefault(
            "Completeness is also given over the samples seen within this depth [m]",
            mrpt::format("%g", app.map_options.near_range)),
        false,
        app.map_options.near_range,
        "M",
        cmd};
    TCLAP::ValueArg<std::string> grid_arg{
        "",
        "grid",
        "An occupancy grid (the mapper's map_grid.gridmap) to compare with --grid-gt",
        false,
        "",
        "MAP.gridmap",
        cmd};
    TCLAP::ValueArg<std::string> grid_gt_arg{
        "",    "grid-gt", "The true floor plan ('emslam-sim --grid-gt-out')",
        false, "",        "PLAN.gridmap",
        cmd};
    TCLAP::ValueArg<long long> grid_tolerance_arg{
        "",
        "grid-tolerance",
        withDefault(
            "An occupied cell matches one of the other grid this many cells away",
            std::to_string(app.grid_tolerance)),
        false,
        app.grid_tolerance,
        "CELLS",
        cmd};
    TCLAP::ValueArg<std::string> gt_format_arg{
        "",
        "gt-format",
        withDefault("Format of GT: auto (from the content), tum, kitti or euroc", "auto"),
        false,
        "auto",
        "auto|tum|kitti|euroc",
        cmd};
    TCLAP::ValueArg<std::string> est_format_arg{
        "",
        "est-format",
        withDefault("Format of EST: auto (from the content), tum, kitti or euroc", "auto"),
        false,
        "auto",
        "auto|tum|kitti|euroc",
        cmd};
    TCLAP::ValueArg<std::string> gt_times{
        "",
        "gt-times",
        "Times file of a KITTI GT (default: found beside it, e.g. sequences/NN/times.txt for "
        "poses/NN.txt)",
        false,
        "",
        "FILE",
        cmd};
    TCLAP::ValueArg<std::string> est_times{
        "",     "est-times", "Times file of a KITTI EST (default: found beside it)", false, "",
        "FILE", cmd};
    TCLAP::ValueArg<double> kitti_time_offset{
        "",
        "kitti-time-offset",
        "UNIX time [s] added to KITTI sequence times (times.txt values below 1e9), as "
        "emslam-import kitti does",
        false,
        emslam::io::KittiSequence::DEFAULT_TIME_OFFSET,
        "SECONDS",
        cmd};
    TCLAP::ValueArg<std::string> align{
        "",
        "align",
        withDefault("Alignment before the ATE: se3 (rigid), sim3 (with scale) or none", "se3"),
        false,
        "se3",
        "se3|sim3|none",
        cmd};
    TCLAP::ValueArg<std::string> json{
        "", "json", "Also write the metrics to this JSON file", false, "", "FILE", cmd};
    TCLAP::ValueArg<double> max_dt{
        "",
        "max-dt",
        withDefault(
            "Largest time difference of an associated pose pair [s]",
            mrpt::format("%g", app.options.max_dt)),
        false,
        app.options.max_dt,
        "SECONDS",
        cmd};
    TCLAP::ValueArg<long long> step{
        "",
        "segment-step",
        withDefault(
            "Drift segments start every N matched poses", std::to_string(app.options.segment_step)),
        false,
        static_cast<long long>(app.options.segment_step),
        "N",
        cmd};
};

bool EvalApp::parseArguments(int argc, const char** argv)
{
    Arguments args(*this);
    if (!parseCommandLine(args.cmd, argc, argv, {{"--gt", "", 0, "GT"}, {"--est", "", 1, "EST"}}))
    {
        return false;
    }
    takeInputs(args);
    takeOptions(args);
    io::requireOutputsAreNotInputs(
        {{"the JSON output (--json)", m_json}},
        {{"the ground truth", m_gt},
         {"the estimate", m_est},
         {"the map cloud (--map)", m_map},
         {"the true surfaces (--map-gt)", m_map_gt},
         {"the grid (--grid)", m_grid},
         {"the true floor plan (--grid-gt)", m_grid_gt},
         {"the ground-truth times (--gt-times)", m_gt_options.times_file},
         {"the estimate's times (--est-times)", m_est_options.times_file}});
    return true;
}

void EvalApp::takeInputs(Arguments& args)
{
    const auto& files = args.trajectories.getValue();
    if (files.size() != 0 && files.size() != 2)
    {
        usageError(
            files.size() == 1 ? "missing required argument <EST> (GT then EST)"
                              : "three or more trajectories: give GT then EST");
    }
    m_gt = files.empty() ? "" : files[0];
    m_est = files.empty() ? "" : files[1];
    m_map = args.map_arg.getValue();
    m_map_gt = args.map_gt_arg.getValue();
    m_grid = args.grid_arg.getValue();
    m_grid_gt = args.grid_gt_arg.getValue();
    for (const auto& [a, b, what] :
         {std::tuple{&m_gt, &m_est, "GT and EST"},
          {&m_map, &m_map_gt, "--map and --map-gt"},
          {&m_grid, &m_grid_gt, "--grid and --grid-gt"}})
    {
        if (a->empty() != b->empty())
        {
            usageError(std::string(what) + " go together");
        }
    }
    if (m_gt.empty() && m_map.empty() && m_grid.empty())
    {
        usageError(
            "missing required arguments <GT>, <EST> (or --map and --map-gt, or --grid and "
            "--grid-gt)");
    }
}

void EvalApp::takeOptions(Arguments& args)
{
    map_options.completeness_distance = args.completeness_arg.getValue();
    map_options.near_range = args.near_arg.getValue();
    if (!(map_options.completeness_distance > 0) ||
        !std::isfinite(map_options.completeness_distance) || !(map_options.near_range > 0))
    {
        usageError("--completeness-distance and --near-range must be positive distances [m]");
    }
    grid_tolerance = static_cast<int>(
        countOption(args.grid_tolerance_arg.getValue(), "--grid-tolerance", 0, PROGRAM));
    for (auto [arg, o] :
         {std::pair{&args.gt_format_arg, &m_gt_options}, {&args.est_format_arg, &m_est_options}})
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
    m_gt_options.times_file = args.gt_times.getValue();
    m_est_options.times_file = args.est_times.getValue();
    if (!std::isfinite(args.kitti_time_offset.getValue()))
    {
        throw std::invalid_argument("--kitti-time-offset must be a finite number of seconds");
    }
    m_gt_options.kitti_time_offset = m_est_options.kitti_time_offset =
        args.kitti_time_offset.getValue();
    m_json = args.json.getValue();
    try
    {
        options.alignment = eval::parseAlignment(args.align.getValue());
    }
    catch (const std::invalid_argument&)
    {
        throw std::invalid_argument(
            "bad --align value '" + args.align.getValue() + "': expected se3, sim3 or none");
    }
    options.max_dt = args.max_dt.getValue();
    if (!(options.max_dt > 0) || !std::isfinite(options.max_dt))
    {
        throw std::invalid_argument("--max-dt must be a positive number of seconds");
    }
    options.segment_step = countOption(args.step.getValue(), "--segment-step", 1, PROGRAM);
}

void EvalApp::execute()
{
    map_accuracy.reset();
    grid_accuracy.reset();
    std::vector<std::string> members;
    std::string json = m_gt.empty() ? std::string("{\n") : evaluateTrajectory();
    if (!m_map.empty())
    {
        members.push_back(evaluateMap());
    }
    if (!m_grid.empty())
    {
        members.push_back(evaluateGrid());
    }
    if (!members.empty())
    {
        // The trajectory's keys stay at the top level, as without a map.
        if (json.size() > 3)
        {
            json.erase(json.size() - 3);  // "\n}\n"
            json += ",\n";
        }
        for (std::size_t k = 0; k < members.size(); ++k)
        {
            json += members[k] + (k + 1 < members.size() ? ",\n" : "\n");
        }
        json += "}\n";
    }
    if (!m_json.empty())
    {
        io::OutputFile f(m_json);
        f.text() << json;
        f.close();
        std::printf("metrics written to '%s'\n", m_json.c_str());
    }
}

std::string EvalApp::evaluateMap()
{
    auto map = loadMapCloud(m_map);
    // SLAM fixes no gauge: the map is in the estimate's frame, which the
    // trajectory's alignment brings onto the truth's, where the surfaces are
    // (with the cameras' orientations: a straight path leaves a turn free).
    const bool aligned = !m_gt.empty() && metrics.alignment != eval::Alignment::None;
    if (aligned)
    {
        metrics.map_align.applyToPoints(map);
    }
    io::requireInputFile(m_map_gt, "true surfaces (--map-gt)");
    const auto truth = loadPly(m_map_gt);
    try
    {
        map_accuracy = eval::MapAccuracy::compute(map, truth, map_options);
    }
    catch (const std::invalid_argument& e)
    {
        throw std::runtime_error(
            std::string(e.what()) + "; map '" + m_map + "', true surfaces '" + m_map_gt + "'");
    }
    const auto& a = *map_accuracy;
    std::printf(
        "map alignment      %s\n",
        aligned ? ("the trajectory's (" + eval::alignmentName(metrics.alignment) + ")").c_str()
                : "none (the map's own frame)");
    std::printf(
        "map accuracy       median %s m, 90th percentile %s m, mean %s m (%zu map points to the "
        "true surface)\n"
        "map completeness   %s %% of %zu true-surface samples within %g m of the map",
        fmt(a.median_m).c_str(), fmt(a.p90_m).c_str(), fmt(a.mean_m).c_str(), a.map_points,
        fmt(100 * a.completeness, "%.1f").c_str(), a.reference_points,
        map_options.completeness_distance);
    if (a.near_reference_points > 0)
    {
        std::printf(
            "; %s %% of the %zu seen within %g m", fmt(100 * a.completeness_near, "%.1f").c_str(),
            a.near_reference_points, map_options.near_range);
    }
    std::printf("\n");
    return jsonMember(
               "map_alignment", aligned ? "\"" + eval::alignmentName(metrics.alignment) + "\""
                                        : std::string("\"none\"")) +
           ",\n" + jsonMember("map_accuracy", a.toJson());
}

std::string EvalApp::evaluateGrid()
{
    const auto estimate = loadGrid(m_grid, "occupancy grid (--grid)");
    const auto truth = loadGrid(m_grid_gt, "true floor plan (--grid-gt)");
    try
    {
        grid_accuracy = eval::OccupancyGridAccuracy::compute(estimate, truth, grid_tolerance);
    }
    catch (const std::invalid_argument& e)
    {
        throw std::runtime_error(
            std::string(e.what()) + "; grid '" + m_grid + "', floor plan '" + m_grid_gt + "'");
    }
    const auto& g = *grid_accuracy;
    std::printf(
        "grid occupied      precision %s, recall %s, F1 %s (%zu occupied cells of %g m, %zu "
        "true; matched within %d cell%s)\n",
        fmt(g.precision, "%.3f").c_str(), fmt(g.recall, "%.3f").c_str(), fmt(g.f1, "%.3f").c_str(),
        g.estimated_occupied, g.cell_size, g.true_occupied, g.tolerance_cells,
        g.tolerance_cells == 1 ? "" : "s");
    return jsonMember("grid_accuracy", g.toJson());
}

std::string EvalApp::evaluateTrajectory()
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
    return m.toJson();
}

}  // namespace emslam::apps
