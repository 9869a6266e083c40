// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>
#include <emslam/apps/ConfigValidation.h>
#include <emslam/apps/EnergyScanOutputs.h>
#include <emslam/apps/ExperimentRunner.h>
#include <emslam/apps/MapperOutputs.h>
#include <emslam/apps/MapperReport.h>
#include <emslam/eval/MapAccuracy.h>
#include <emslam/eval/TrajectoryMetrics.h>
#include <emslam/maps/EntropyEnergy.h>
#include <emslam/rectify/EnergyAtPoses.h>
#include <emslam/sim/ExactDepthFrame.h>
#include <emslam/sim/StereoSimulator.h>
#include <emslam/sim/SurfaceSampler.h>
#include <emslam/slam/EntropySlam.h>
#include <emslam/slam/ScanFusion.h>
#include <emslam/stereo/RangeScanConversion.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <limits>
#include <map>
#include <stdexcept>

namespace emslam::apps
{
namespace
{
/** max − min of the entropy of the map at `poses` moved rigidly by k/4 of a
 * cell along (1, 1, 1), k = 0..3: the same geometry on four grid phases. */
double gridPhaseSpread(
    const emslam::rectify::Trajectory& t,
    const std::vector<mrpt::poses::CPose3D>& poses,
    double cell_size)
{
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    for (int k = 0; k < 4; ++k)
    {
        const auto shift = emslam::rectify::Trajectory::gridPhaseShift(k, 4, cell_size);
        std::vector<mrpt::poses::CPose3D> moved;
        for (const auto& p : poses)
        {
            moved.push_back(shift + p);
        }
        const double h = emslam::rectify::entropyAtElementPoses(t, moved);
        lo = std::min(lo, h);
        hi = std::max(hi, h);
    }
    return hi - lo;
}

emslam::sim::StereoSimulator loadWorld(
    const std::string& file, const std::vector<std::string>& sets, int seed)
{
    try
    {
        mrpt::config::CConfigFileMemory cfg;
        loadConfig(cfg, file, sets);
        cfg.write("World", "seed", seed);
        emslam::sim::StereoSimulator sim;
        sim.load(cfg);
        return sim;
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error("world '" + file + "': " + emslam::util::shortExceptionMessage(e));
    }
}

slam::EntropySlam::TParameters loadMapper(
    const std::string& file, const std::vector<std::string>& sets)
{
    try
    {
        mrpt::config::CConfigFileMemory cfg;
        loadConfig(cfg, file, sets);
        slam::EntropySlam::TParameters reference;
        mrpt::config::CConfigFileMemory known;
        reference.saveToConfigFile(known);
        requireKnownConfigEntries(cfg, known);
        slam::EntropySlam::TParameters p;
        p.loadFromConfigFile(cfg);
        return p;
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error(
            "mapper config '" + file + "': " + emslam::util::shortExceptionMessage(e));
    }
}

/** The keyframe clouds placed at `poses` (frame index → T_world_frame),
 * fused and gated as the map cloud is. */
std::vector<mrpt::math::TPoint3Df> cloudAt(
    const std::vector<slam::KeyframeScan>& scans,
    const std::vector<emslam::rectify::TimedPose>& poses,
    const slam::FusedPointCloud::TOptions& fusion)
{
    return slam::fuseScans(scans, poses, fusion).cloud().points;
}

/** ExperimentResult's map figures: SLAM's map and the egomotion's against
 * the surfaces the first `frames` frames saw, each map moved by its
 * trajectory's alignment to the ground truth (as emslam-eval --map). */
void measureMaps(
    const emslam::sim::StereoSimulator& sim,
    std::size_t frames,
    const slam::EntropySlam& mapper,
    const MapperRunInfo& info,
    ExperimentResult& r)
{
    emslam::sim::SurfaceSampler::TParameters sp;
    sp.spacing = 0.03;  // 5 cm completeness: a few samples within reach
    sp.max_range = mapper.parameters().stereo.max_range;
    eval::ReferenceSurface ref;
    ref.spacing = sp.spacing;
    for (const auto& s : emslam::sim::SurfaceSampler(sp).visibleSurfaces(sim, frames))
    {
        ref.points.emplace_back(s.position[0], s.position[1], s.position[2]);
        ref.normals.emplace_back(s.normal[0], s.normal[1], s.normal[2]);
        ref.seen_range.push_back(s.seen_range);
    }
    if (ref.points.empty() || mapper.mapCloud().size() == 0)
    {
        return;
    }
    auto slam_cloud = mapper.mapCloud().points;
    if (info.slam_vs_gt)
    {
        info.slam_vs_gt->map_align.applyToPoints(slam_cloud);
    }
    const auto slam_map = eval::MapAccuracy::compute(slam_cloud, ref);
    r.slam_map_median_m = slam_map.median_m;
    r.slam_map_p90_m = slam_map.p90_m;
    r.slam_map_completeness = slam_map.completeness;
    auto ego_cloud = cloudAt(
        mapper.keyframeScans(), mapper.egomotionPoses(),
        mapper.parameters().mapper.fusionOptions());
    if (!ego_cloud.empty())
    {
        if (info.egomotion_vs_gt)
        {
            info.egomotion_vs_gt->map_align.applyToPoints(ego_cloud);
        }
        const auto ego_map = eval::MapAccuracy::compute(ego_cloud, ref);
        r.egomotion_map_median_m = ego_map.median_m;
        r.egomotion_map_p90_m = ego_map.p90_m;
        r.egomotion_map_completeness = ego_map.completeness;
    }
}

void writeRunOutputs(
    const std::string& dir,
    const slam::EntropySlam& m,
    const MapperRunInfo& info,
    const emslam::io::TumTrajectory& ground_truth)
{
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir))
    {
        throw std::runtime_error("cannot create folder '" + dir + "'");
    }
    ground_truth.saveToFile(dir + "/groundtruth.tum");
    tumTrajectoryOf(m.egomotionPoses()).saveToFile(dir + "/trajectory_egomotion.tum");
    tumTrajectoryOf(m.slamPoses()).saveToFile(dir + "/trajectory_slam.tum");
    writeSummaryJson(m, info, dir + "/summary.json");
    writeMapperReport(dir + "/report.html", makeReportData(m, info, ground_truth));
}
/** The run's description: experiment, mapper, seed and the paper's figures. */
ExperimentResult describeRun(
    const ExperimentSpec& spec,
    std::size_t mapper_index,
    int seed,
    const ExperimentRunOptions& options,
    const slam::EntropySlam::TParameters& p)
{
    const std::string& mapper_file = spec.mappers[mapper_index];
    ExperimentResult r;
    r.experiment = spec.name;
    r.title = spec.title;
    r.figure = spec.figure;
    r.mapper = std::filesystem::path(mapper_file).filename().string();
    r.energy = emslam::maps::toString(p.map.energy);
    r.label = paperEnergyLabel(r.energy);
    r.variant = options.variant;
    r.seed = seed;
    r.loop = spec.loop;
    r.paper_path_m = spec.paper_path_m;
    r.paper_observations = spec.paper_observations;
    r.paper_egomotion_gap_m = spec.paper_egomotion_gap_m;
    r.paper_slam_gap_m = spec.paper_slam_gap_m.at(mapper_index);
    return r;
}

/** Renders and maps the frames (all, or options.max_frames) until
 * options.on_frame says stop; returns the true poses of the frames rendered
 * and fills r's ground truth. */
std::vector<mrpt::poses::CPose3D> mapSimulatedFrames(
    const emslam::sim::StereoSimulator& sim,
    slam::EntropySlam& mapper,
    const slam::EntropySlam::TParameters& p,
    const ExperimentRunOptions& options,
    ExperimentResult& r)
{
    const std::size_t n =
        options.max_frames == 0 ? sim.frameCount() : std::min(options.max_frames, sim.frameCount());
    std::vector<mrpt::poses::CPose3D> truth;
    for (std::size_t i = 0; i < n; ++i)
    {
        const auto f = sim.renderFrame(i, options.exact_depth);
        r.ground_truth.add(f.t, f.T_first_left);
        truth.push_back(f.T_first_left);
        if (options.exact_depth)
        {
            mapper.process(*emslam::stereo::toRangeScan(
                emslam::sim::exactDepthFrame(f, p.stereo.min_range, p.stereo.max_range)));
        }
        else
        {
            mapper.process(*f.obs);
        }
        if (options.on_frame && !options.on_frame(i + 1, n))
        {
            r.interrupted = i + 1 < n;
            break;
        }
    }
    return truth;
}

/** The trajectories against the ground truth (into r and the run info). */
MapperRunInfo measureTrajectories(
    const ExperimentSpec& spec,
    std::size_t mapper_index,
    int seed,
    const ExperimentRunOptions& options,
    ExperimentResult& r)
{
    const std::string& mapper_file = spec.mappers[mapper_index];
    const eval::TrajectoryMetrics::Options metric_options;
    MapperRunInfo info;
    std::string world_sets;
    for (const auto& w : spec.world_sets)
    {
        world_sets += ", " + w;
    }
    info.rawlog = "simulated: " + spec.world + " (seed " + std::to_string(seed) + world_sets +
                  (options.exact_depth ? ", exact depth" : "") + ")";
    info.config = mapper_file;
    info.interrupted = r.interrupted;
    info.egomotion_vs_gt =
        eval::TrajectoryMetrics::compute(r.ground_truth, r.egomotion, metric_options);
    info.slam_vs_gt = eval::TrajectoryMetrics::compute(r.ground_truth, r.slam, metric_options);
    std::vector<mrpt::poses::CPose3D> gt_poses;
    for (const auto& tp : r.ground_truth.poses)
    {
        gt_poses.push_back(tp.pose);
    }
    r.path_m = eval::pathLength(gt_poses);
    r.egomotion_gap_m = info.egomotion_vs_gt->end_error_m;
    r.slam_gap_m = info.slam_vs_gt->end_error_m;
    r.egomotion_ate_m = info.egomotion_vs_gt->ate_rmse_m;
    r.slam_ate_m = info.slam_vs_gt->ate_rmse_m;
    return info;
}

/** Mean stage times and the rectifications' totals. */
void recordTimes(const slam::EntropySlam& mapper, ExperimentResult& r)
{
    const StageMeans ms = stageMeans(mapper.frames());
    r.ms_stereo = ms.stereo;
    r.ms_egomotion = ms.egomotion;
    const RectificationTotals rt = rectificationTotals(mapper.rectifications());
    r.rectifications = mapper.rectifications().size();
    r.attempts = rt.attempts;
    r.successes = rt.successes;
    r.rect_median_ms = rt.median_ms;
    r.rect_max_ms = rt.max_ms;
}

/** The entropy of the final trajectory's elements at the true, egomotion,
 * SLAM and rectified poses. */
void measureEntropies(
    const emslam::rectify::Trajectory& traj,
    const std::vector<mrpt::poses::CPose3D>& truth,
    double cell_size,
    ExperimentResult& r)
{
    const auto& ego = r.egomotion.poses;
    const auto& out = r.slam.poses;
    const auto at_truth =
        emslam::rectify::elementPosesAt(traj, [&](std::size_t i) { return truth.at(i); });
    r.entropy_truth = emslam::rectify::entropyAtElementPoses(traj, at_truth);
    r.entropy_phase_spread = gridPhaseSpread(traj, at_truth, cell_size);
    r.entropy_egomotion = emslam::rectify::entropyAtElementPoses(
        traj, emslam::rectify::elementPosesAt(traj, [&](std::size_t i) { return ego.at(i).pose; }));
    r.entropy_slam = emslam::rectify::entropyAtElementPoses(
        traj, emslam::rectify::elementPosesAt(traj, [&](std::size_t i) { return out.at(i).pose; }));
    std::vector<mrpt::poses::CPose3D> rectified_elements;
    for (std::size_t i = 0; i < traj.size(); ++i)
    {
        rectified_elements.push_back(traj.pose(i));
    }
    r.entropy_rectified = emslam::rectify::entropyAtElementPoses(traj, rectified_elements);
}
}  // namespace

std::string paperEnergyLabel(const std::string& energy)
{
    const auto e = emslam::maps::energyTypeFromString(energy);
    return "Exp. " + std::to_string(8 + static_cast<int>(e));
}

slam::EntropySlam::TParameters experimentMapperParameters(
    const ExperimentSpec& spec, std::size_t mapper_index, const std::vector<std::string>& sets)
{
    if (mapper_index >= spec.mappers.size())
    {
        throw std::out_of_range("runExperiment: no mapper " + std::to_string(mapper_index));
    }
    std::vector<std::string> all = spec.sets;
    all.insert(all.end(), sets.begin(), sets.end());
    return loadMapper(spec.mappers[mapper_index], all);
}

ExperimentResult runExperiment(
    const ExperimentSpec& spec,
    std::size_t mapper_index,
    int seed,
    const ExperimentRunOptions& options)
{
    const auto t_start = std::chrono::steady_clock::now();
    const slam::EntropySlam::TParameters p =
        experimentMapperParameters(spec, mapper_index, options.sets);
    const emslam::sim::StereoSimulator sim = loadWorld(spec.world, spec.world_sets, seed);
    ExperimentResult r = describeRun(spec, mapper_index, seed, options, p);

    slam::EntropySlam mapper(p);
    const std::vector<mrpt::poses::CPose3D> truth = mapSimulatedFrames(sim, mapper, p, options, r);
    mapper.finish();

    r.frames = mapper.frameCount();
    r.observations = mapper.acceptedCount();
    r.egomotion_failures = mapper.egomotionFailures();
    r.egomotion = tumTrajectoryOf(mapper.egomotionPoses());
    r.slam = tumTrajectoryOf(mapper.slamPoses());
    MapperRunInfo info = measureTrajectories(spec, mapper_index, seed, options, r);
    recordTimes(mapper, r);
    const auto& traj = mapper.trajectory();
    if (!traj.empty())
    {
        measureEntropies(traj, truth, p.map.cell_size, r);
    }
    if (options.map_accuracy)
    {
        measureMaps(sim, r.frames, mapper, info, r);
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    info.seconds = r.seconds;
    if (options.energy_scan && !traj.empty())
    {
        info.energy_scan = scanMapperEnergy(mapper, [&](std::size_t i) { return truth.at(i); });
        r.energy_scan = info.energy_scan->scan.summary;
    }
    if (!options.out_dir.empty())
    {
        writeRunOutputs(options.out_dir, mapper, info, r.ground_truth);
        if (info.energy_scan)
        {
            writeEnergyScanCsv(info.energy_scan->scan, options.out_dir + "/energy_scan.csv");
        }
    }
    return r;
}

}  // namespace emslam::apps
