// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/EnergyScanOutputs.h>
#include <emslam/apps/EntropyVoxelObject.h>
#include <emslam/apps/MapScene.h>
#include <emslam/apps/MapStyle.h>
#include <emslam/apps/MapTopView.h>
#include <emslam/apps/MapperOutputs.h>
#include <emslam/io/AtomicFile.h>
#include <emslam/io/AtomicTextFile.h>
#include <emslam/io/GzOutputStream.h>
#include <emslam/io/ImageOutput.h>
#include <emslam/io/Json.h>
#include <emslam/io/OutputFile.h>
#include <emslam/maps/EntropyEnergy.h>
#include <emslam/slam/OccupancyGridBuilder.h>
#include <emslam/slam/OctoMapBuilder.h>

#include <mrpt/core/bits_math.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace emslam::apps
{
namespace
{
/** A JSON object nested one level: indented, without the final line end. */
std::string nestedJson(const std::string& object)
{
    std::string out;
    for (std::size_t i = 0; i < object.size(); ++i)
    {
        out += object[i];
        if (object[i] == '\n' && i + 1 < object.size())
        {
            out += "  ";
        }
    }
    while (!out.empty() && (out.back() == '\n' || out.back() == ' '))
    {
        out.pop_back();
    }
    return out;
}

std::string jsonStringArray(const std::vector<std::string>& items)
{
    std::string out = "[";
    for (std::size_t i = 0; i < items.size(); ++i)
    {
        out += (i > 0 ? ", " : "") + io::jsonString(items[i]);
    }
    return out + "]";
}

/** summary.json's camera_change: null, or where the camera first changed and
 * whether it changed for good. */
std::string cameraChangeJson(const MapperRunInfo& info)
{
    if (!info.camera_change)
    {
        return "null";
    }
    const auto& c = *info.camera_change;
    return "{\"record\": " + std::to_string(c.record) +
           ", \"from\": " + io::jsonString(c.from.toString()) +
           ", \"to\": " + io::jsonString(c.to.toString()) +
           ", \"for_good\": " + (c.for_good ? "true" : "false") +
           ", \"runs\": " + std::to_string(c.runs) +
           ", \"frames_before\": " + std::to_string(c.used_before) +
           ", \"warning\": " + io::jsonString(info.camera_change_warning) + "}";
}

/** summary.json's "unreliable": null, or the reasons as a list of strings. */
std::string unreliableJson(const std::vector<std::string>& reasons)
{
    if (reasons.empty())
    {
        return "null";
    }
    std::string out = "[";
    for (std::size_t k = 0; k < reasons.size(); ++k)
    {
        out += (k > 0 ? ", " : "") + io::jsonString(reasons[k]);
    }
    return out + "]";
}

std::string fixed(double v, int decimals)
{
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
    return buf;
}

}  // namespace

namespace
{
double distance(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b)
{
    return (b.asTPose().translation() - a.asTPose().translation()).norm();
}
}  // namespace

double loopGap(const emslam::io::TumTrajectory& t)
{
    return t.size() < 2 ? 0.0 : distance(t.poses.front().pose, t.poses.back().pose);
}

double loopGap(const std::vector<emslam::rectify::TimedPose>& poses)
{
    // Straight from the poses: no TUM copy of the whole trajectory.
    return poses.size() < 2 ? 0.0
                            : distance(poses.front().T_world_frame, poses.back().T_world_frame);
}

emslam::io::TumTrajectory tumTrajectoryOf(const std::vector<emslam::rectify::TimedPose>& poses)
{
    emslam::io::TumTrajectory t;
    t.poses.reserve(poses.size());
    for (const auto& p : poses)
    {
        t.add(p.timestamp, p.T_world_frame);
    }
    return t;
}

std::string startToEndName(const emslam::io::TumTrajectory& ground_truth)
{
    return eval::isClosedLoop(ground_truth) ? "loop gap" : "start-to-end distance";
}

StageMeans stageMeans(const std::vector<slam::FrameRecord>& frames)
{
    StageMeans m;
    for (const auto& f : frames)
    {
        m.stereo += f.ms_stereo;
        m.egomotion += f.ms_egomotion;
        m.rectification += f.ms_rectification;
        m.total += f.ms_total;
        m.max_total = std::max(m.max_total, f.ms_total);
    }
    const double n = frames.empty() ? 1.0 : static_cast<double>(frames.size());
    m.stereo /= n;
    m.egomotion /= n;
    m.rectification /= n;
    m.total /= n;
    return m;
}

RectificationTotals rectificationTotals(const std::vector<emslam::rectify::RectificationStats>& r)
{
    RectificationTotals t;
    std::vector<double> ms;
    for (const auto& s : r)
    {
        t.attempts += s.attempts;
        t.successes += s.successes;
        t.failures += s.failures;
        t.accepted_worse += s.accepted_worse;
        t.rejected_by_validation += s.rejected_by_validation ? 1 : 0;
        t.unconfirmed += s.unconfirmed;
        t.held_before_revisit += s.held_before_revisit ? 1 : 0;
        t.seconds += s.seconds;
        ms.push_back(1e3 * s.seconds);
    }
    if (!ms.empty())
    {
        std::sort(ms.begin(), ms.end());
        t.median_ms = ms[ms.size() / 2];
        t.max_ms = ms.back();
    }
    return t;
}

void writeStatsCsv(const slam::EntropySlam& m, const std::string& file)
{
    io::AtomicTextFile f(file);
    auto& o = f.stream();
    o << "type,index,timestamp,ms_stereo,ms_egomotion,ms_rectification,ms_total,points,"
         "matches_before_lwo,matches_after_lwo,accepted,egomotion_ok,energy,"
         "elements,frames,attempts,successes,accepted_worse,failures,energy_before,"
         "energy_after,seconds,converged,sigma_x_m,sigma_y_m,sigma_z_m,sigma_rx_deg,"
         "sigma_ry_deg,sigma_rz_deg\n";
    for (const auto& r : m.frames())
    {
        o << "frame," << r.index << ',' << fixed(r.timestamp, 6) << ',' << fixed(r.ms_stereo, 3)
          << ',' << fixed(r.ms_egomotion, 3) << ',' << fixed(r.ms_rectification, 3) << ','
          << fixed(r.ms_total, 3) << ',' << r.points << ',' << r.initial_matches << ','
          << r.final_matches << ',' << (r.accepted ? 1 : 0) << ',' << (r.egomotion_ok ? 1 : 0)
          << ',' << io::jsonNumber(r.energy) << ",,,,,,,,,,";
        for (std::size_t k = 0; k < r.step_sigma.size(); ++k)
        {
            const double v = k < 3 ? r.step_sigma[k] : mrpt::RAD2DEG(r.step_sigma[k]);
            o << ',';
            if (std::isfinite(v))
            {
                o << fixed(v, k < 3 ? 6 : 5);
            }
        }
        o << '\n';
    }
    std::size_t k = 0;
    for (const auto& s : m.rectifications())
    {
        o << "rectification," << k++ << ",,,,,,,,,,,," << s.elements << ',' << s.frames << ','
          << s.attempts << ',' << s.successes << ',' << s.accepted_worse << ',' << s.failures << ','
          << io::jsonNumber(s.energy_before) << ',' << io::jsonNumber(s.energy_after) << ','
          << fixed(s.seconds, 6) << ',' << (s.converged ? 1 : 0) << ",,,,,,\n";
    }
    f.commit();
}

namespace
{
/** The mean milliseconds per frame of each stage, a JSON object. */
void writeStageTimesJson(std::ostream& j, const StageMeans& ms)
{
    j << "{\"stereo\": " << io::jsonNumber(ms.stereo)
      << ", \"egomotion\": " << io::jsonNumber(ms.egomotion)
      << ", \"stereo_plus_egomotion\": " << io::jsonNumber(ms.stereo + ms.egomotion)
      << ", \"rectification\": " << io::jsonNumber(ms.rectification)
      << ", \"total\": " << io::jsonNumber(ms.total)
      << ", \"max_total\": " << io::jsonNumber(ms.max_total) << "}";
}

/** The rectifier's calls, attempts and times, a JSON object. */
void writeRectificationJson(
    std::ostream& j, const slam::EntropySlam& m, const RectificationTotals& rt)
{
    j << "{\"calls\": " << m.rectifications().size() << ", \"attempts\": " << rt.attempts
      << ", \"successes\": " << rt.successes << ", \"failures\": " << rt.failures
      << ", \"accepted_worse\": " << rt.accepted_worse
      << ", \"rejected_by_validation\": " << rt.rejected_by_validation
      << ", \"unconfirmed\": " << rt.unconfirmed
      << ", \"held_before_revisit\": " << rt.held_before_revisit
      << ", \"seconds\": " << io::jsonNumber(rt.seconds)
      << ", \"median_ms_per_call\": " << io::jsonNumber(rt.median_ms)
      << ", \"max_ms_per_call\": " << io::jsonNumber(rt.max_ms) << "}";
}

/** The loop closer's counts, costs and times, a JSON object. */
void writeLoopClosingJson(std::ostream& j, const slam::EntropySlam& m)
{
    const auto& lc = m.loopCloser().stats();
    j << "{\"enabled\": " << (m.parameters().loop_closer.enabled ? "true" : "false")
      << ", \"candidates\": " << lc.candidates << ", \"registrations\": " << lc.registrations
      << ", \"registered\": " << lc.registered << ", \"loop_edges\": " << lc.loop_edges
      << ", \"local_registrations\": " << lc.local_registrations
      << ", \"local_edges\": " << lc.local_edges
      << ", \"verticals_measured\": " << lc.verticals_measured
      << ", \"verticals_used\": " << lc.verticals_used
      << ", \"vertical_drift_deg\": " << io::jsonNumber(lc.vertical_drift_deg)
      << ", \"vertical_bias_deg\": " << io::jsonNumber(lc.vertical_bias_deg)
      << ", \"vertical_correlation_time\": " << io::jsonNumber(lc.vertical_correlation_time)
      << ", \"level_resolves\": " << lc.level_resolves << ", \"rounds\": " << lc.rounds
      << ", \"initial_cost\": " << io::jsonNumber(lc.initial_cost)
      << ", \"final_cost\": " << io::jsonNumber(lc.final_cost)
      << ", \"dropped_edges\": " << lc.dropped_edges
      << ", \"refused_groups\": " << lc.refused_groups
      << ", \"contradicting_groups\": " << lc.contradicting_groups
      << ", \"contradicting_edges\": " << lc.contradicting_edges
      << ", \"contradicting_keyframes\": " << lc.contradicting_keyframes
      << ", \"refused_edges\": " << lc.refused_edges
      << ", \"withdrawn_edges\": " << lc.withdrawn_edges
      << ", \"local_solves\": " << lc.local_solves
      << ", \"latency_ms_mean\": " << io::jsonNumber(lc.latency_ms_mean)
      << ", \"latency_ms_max\": " << io::jsonNumber(lc.latency_ms_max)
      << ", \"new_loops\": " << lc.new_loops
      << ", \"new_loop_latency_ms_mean\": " << io::jsonNumber(lc.new_loop_latency_ms_mean)
      << ", \"new_loop_latency_ms_max\": " << io::jsonNumber(lc.new_loop_latency_ms_max)
      << ", \"new_loop_wait_m_mean\": " << io::jsonNumber(lc.new_loop_wait_m_mean)
      << ", \"new_loop_wait_m_max\": " << io::jsonNumber(lc.new_loop_wait_m_max)
      << ", \"place_candidates\": " << lc.place_candidates
      << ", \"place_index_bytes\": " << lc.place_index_bytes
      << ", \"place_ms\": " << io::jsonNumber(lc.place_ms)
      << ", \"place_visited_max\": " << lc.place_visited_max
      << ", \"drift_scale\": " << io::jsonNumber(lc.drift_scale)
      << ", \"kept_bytes\": " << lc.kept_bytes << ", \"unreliable\": "
      << (lc.unreliable.empty() ? std::string("null") : io::jsonString(lc.unreliable))
      << ", \"polish_ms\": " << io::jsonNumber(lc.polish_ms)
      << ", \"polish_solve_ms\": " << io::jsonNumber(lc.polish_solve_ms)
      << ", \"polish_level_ms\": " << io::jsonNumber(lc.polish_level_ms)
      << ", \"ms\": " << io::jsonNumber(lc.ms) << "}";
}
/** The members only a run with ground truth has (each after a comma). */
void writeGroundTruthMeasuresJson(std::ostream& j, const MapperRunInfo& info)
{
    if (info.egomotion_vs_gt)
    {
        j << ",\n  \"egomotion_vs_gt\": " << nestedJson(info.egomotion_vs_gt->toJson());
    }
    if (info.online_vs_gt)
    {
        j << ",\n  \"online_vs_gt\": " << nestedJson(info.online_vs_gt->toJson());
    }
    if (info.slam_vs_gt)
    {
        j << ",\n  \"slam_vs_gt\": " << nestedJson(info.slam_vs_gt->toJson());
    }
    if (info.energy_scan)
    {
        j << ",\n  \"energy_scan\": " << energyScanJson(*info.energy_scan);
    }
}
}  // namespace

namespace
{
/** The session continued or localized in, and the one saved (null: none). */
std::string sessionJson(const slam::EntropySlam& m, const MapperRunInfo& info)
{
    if (info.session_loaded.empty() && info.session_saved.empty())
    {
        return "null";
    }
    std::ostringstream j;
    j << "{\"loaded\": "
      << (info.session_loaded.empty() ? "null" : io::jsonString(info.session_loaded))
      << ", \"use\": "
      << (info.session_loaded.empty() ? "null"
          : info.localized            ? "\"localize\""
                                      : "\"continue\"")
      << ", \"session_frames\": " << m.sessionFrames() << ", \"located_at_frame\": ";
    if (const auto& r = m.relocalization())
    {
        j << r->frame_index << ", \"frames_before_located\": " << r->frames_before
          << ", \"locating_registrations\": " << r->fix.tried
          << ", \"agreeing_registrations\": " << r->fix.agreeing;
    }
    else
    {
        j << "null";
    }
    j << ", \"saved\": "
      << (info.session_saved.empty() ? "null" : io::jsonString(info.session_saved)) << "}";
    return j.str();
}
}  // namespace

void writeSummaryJson(
    const slam::EntropySlam& m, const MapperRunInfo& info, const std::string& file)
{
    const StageMeans ms = stageMeans(m.frames());
    const RectificationTotals rt = rectificationTotals(m.rectifications());
    const auto& p = m.parameters();
    std::ostringstream j;
    j << "{\n"
      << "  \"rawlog\": " << io::jsonString(info.rawlog) << ",\n"
      << "  \"config\": " << io::jsonString(info.config) << ",\n"
      << "  \"energy\": " << io::jsonString(emslam::maps::toString(p.map.energy)) << ",\n"
      << "  \"dof\": " << p.map.dof << ",\n"
      << "  \"mode\": "
      << io::jsonString(
             p.mapper.egomotion_only ? std::string("egomotion_only")
                                     : emslam::rectify::toString(p.rectifier.mode))
      << ",\n"
      << "  \"frames\": " << m.frameCount() << ",\n"
      << "  \"accepted_frames\": " << m.acceptedCount() << ",\n"
      << "  \"egomotion_failures\": " << m.egomotionFailures() << ",\n"
      << "  \"guided_steps\": " << m.guidedSteps() << ",\n"
      << "  \"guided_fallbacks\": " << m.guidedFallbacks() << ",\n"
      << "  \"ignored_observations\": " << info.ignored_observations << ",\n"
      << "  \"skipped_observations\": " << info.skipped_observations << ",\n"
      << "  \"skipped_bad_stamps\": " << info.skipped_bad_stamps << ",\n"
      << "  \"skipped_camera_changes\": " << info.skipped_camera_changes << ",\n"
      << "  \"skipped_unusable\": " << info.skipped_unusable << ",\n"
      << "  \"skipped_reasons\": " << jsonStringArray(info.skipped_reasons) << ",\n"
      << "  \"camera_change\": " << cameraChangeJson(info) << ",\n"
      << "  \"stopped_by_error\": "
      << (info.stopped_by_error.empty() ? "null" : io::jsonString(info.stopped_by_error)) << ",\n"
      << "  \"interrupted\": " << (info.interrupted ? "true" : "false") << ",\n"
      << "  \"input_ended_early\": "
      << (info.input_ended_early.empty() ? "null" : io::jsonString(info.input_ended_early)) << ",\n"
      << "  \"degenerate\": "
      << (info.degenerate.empty() ? "null" : io::jsonString(info.degenerate)) << ",\n"
      << "  \"image_width\": " << m.imageWidth() << ",\n"
      << "  \"image_height\": " << m.imageHeight() << ",\n"
      << "  \"ms_per_frame\": ";
    writeStageTimesJson(j, ms);
    j << ",\n"
      << "  \"rectification\": ";
    writeRectificationJson(j, m, rt);
    j << ",\n"
      << "  \"loop_closing\": ";
    writeLoopClosingJson(j, m);
    j << ",\n"
      << "  \"session\": " << sessionJson(m, info) << ",\n"
      << "  \"unreliable\": " << unreliableJson(m.unreliableReasons()) << ",\n"
      << "  \"trajectory_elements\": " << m.trajectoryElements() << ",\n"
      << "  \"compressions\": " << m.compressions() << ",\n"
      << "  \"final_energy\": " << io::jsonNumber(m.finalEnergy()) << ",\n"
      << "  \"final_entropy\": " << io::jsonNumber(m.finalEntropy()) << ",\n"
      << "  \"map_points\": " << m.mapCloud().size() << ",\n"
      << "  \"map_fusion\": {\"points\": " << m.fusionStats().points
      << ", \"used_points\": " << m.fusionStats().used_points
      << ", \"moved_points\": " << m.fusionStats().moved_points
      << ", \"voxels\": " << m.fusionStats().voxels
      << ", \"kept_voxels\": " << m.fusionStats().kept_voxels
      << ", \"kept_points\": " << m.fusionStats().kept_points
      << ", \"keyframe_stride\": " << m.mapCloudsStride() << "},\n"
      << "  \"loop_gap_egomotion_m\": " << io::jsonNumber(loopGap(m.egomotionPoses())) << ",\n"
      << "  \"loop_gap_slam_m\": " << io::jsonNumber(loopGap(m.slamPoses())) << ",\n"
      << "  \"seconds\": " << io::jsonNumber(info.seconds) << ",\n"
      << "  \"seconds_after_last_frame\": " << io::jsonNumber(info.seconds_after_last_frame)
      << ",\n"
      << "  \"wall_ms_per_frame\": "
      << io::jsonNumber(
             m.runFrameCount() > 0 ? 1e3 * info.seconds / static_cast<double>(m.runFrameCount())
                                   : 0.0);
    writeGroundTruthMeasuresJson(j, info);
    j << "\n}\n";
    io::AtomicTextFile f(file);
    f.stream() << j.str();
    f.commit();
}

MapDrawingContent mapDrawingContent(
    const slam::EntropySlam& m,
    const emslam::io::TumTrajectory& egomotion,
    const emslam::io::TumTrajectory& slam,
    const emslam::io::TumTrajectory& ground_truth_in_map)
{
    MapDrawingContent c;
    c.cloud = &m.mapCloud();
    c.egomotion = &egomotion;
    c.slam = &slam;
    c.ground_truth = ground_truth_in_map.empty() ? nullptr : &ground_truth_in_map;
    c.entropy_map = &m.entropyMap();
    c.max_height = m.parameters().mapper.export_max_height;
    return c;
}

namespace
{
/** The trajectories the drawings of `m` show (ground truth in the map frame). */
struct DrawnTrajectories
{
    emslam::io::TumTrajectory egomotion, slam, ground_truth;
    /** The accepted loop edges, their ends at the final poses. */
    std::vector<std::pair<mrpt::math::TPoint3D, mrpt::math::TPoint3D>> loops;

    DrawnTrajectories(const slam::EntropySlam& m, const emslam::io::TumTrajectory& gt)
        : egomotion(tumTrajectoryOf(m.egomotionPoses())),
          slam(tumTrajectoryOf(m.slamPoses())),
          ground_truth(groundTruthInMapFrame(gt, egomotion))
    {
        const auto& poses = m.slamPoses();
        for (const auto& e : m.loopCloser().loopEdges())
        {
            if (e.frame_from < poses.size() && e.frame_to < poses.size())
            {
                loops.emplace_back(
                    poses[e.frame_from].T_world_frame.asTPose().translation(),
                    poses[e.frame_to].T_world_frame.asTPose().translation());
            }
        }
    }
    MapDrawingContent content(const slam::EntropySlam& m) const
    {
        MapDrawingContent c = mapDrawingContent(m, egomotion, slam, ground_truth);
        c.loops = &loops;
        return c;
    }
};
}  // namespace

void writeScene(
    const slam::EntropySlam& m,
    const emslam::io::TumTrajectory& ground_truth,
    const std::string& file)
{
    const DrawnTrajectories t(m, ground_truth);
    writeMapScene(t.content(m), file);
}

void writeTopViewPng(
    const slam::EntropySlam& m,
    const emslam::io::TumTrajectory& ground_truth,
    const std::string& file)
{
    const DrawnTrajectories t(m, ground_truth);
    writeTopView(t.content(m), file);
}

void writeOccupancyGrid(
    const slam::EntropySlam& m, const std::string& gridmap_file, const std::string& png_file)
{
    if (m.parameters().occupancy_grid.cell_size <= 0)
    {
        return;
    }
    slam::OccupancyGridBuilder builder(m.parameters().occupancy_grid);
    const mrpt::maps::COccupancyGridMap2D grid = builder.build(m.mapCloud(), m.keyframePoses());
    io::writeFileAtomically(
        gridmap_file,
        [&](const std::string& partial)
        {
            io::GzOutputStream f(partial, 1, gridmap_file);
            mrpt::serialization::archiveFrom(f) << grid;
            f.close();
            return true;
        });
    mrpt::img::CImage picture;
    grid.getAsImage(picture, true);  // +Y (left) up
    io::writeFileAtomically(
        png_file,
        [&](const std::string& partial)
        {
            io::writeImageFile(partial, picture.asCvMatRef(), png_file);
            return true;
        });
}

void writeOctoMap(const slam::EntropySlam& m, const std::string& file)
{
    if (m.parameters().octomap.resolution <= 0)
    {
        return;
    }
    slam::OctoMapBuilder builder(m.parameters().octomap);
    const auto tree = builder.build(m.fusedKeyframeScans(), m.keyframePoses());
    io::writeFileAtomically(
        file, [&](const std::string& partial) { return tree->writeBinary(partial); });
}

void writeEntropyMap(const slam::EntropySlam& m, const std::string& file)
{
    io::writeFileAtomically(
        file,
        [&](const std::string& partial)
        {
            io::OutputFile f(partial, file);
            auto a = mrpt::serialization::archiveFrom(f);
            a << m.entropyMap();
            f.close();
            return true;
        });
}

void writeEntropyMapView(const slam::EntropySlam& m, const std::string& file)
{
    writeEntropyMapScene(m.entropyMap(), 50000, file);
}

MapperReportData makeReportData(
    const slam::EntropySlam& m,
    const MapperRunInfo& info,
    const emslam::io::TumTrajectory& ground_truth)
{
    MapperReportData d;
    d.title = info.rawlog;
    d.egomotion = tumTrajectoryOf(m.egomotionPoses());
    d.slam = tumTrajectoryOf(m.slamPoses());
    d.online = tumTrajectoryOf(m.onlinePoses());
    d.ground_truth = ground_truth;
    d.frames = m.frames();
    d.rectifications = m.rectifications();
    const StageMeans ms = stageMeans(m.frames());
    const RectificationTotals rt = rectificationTotals(m.rectifications());
    auto& s = d.summary;
    s.emplace_back("rawlog", info.rawlog);
    s.emplace_back("configuration", info.config);
    s.emplace_back("energy", emslam::maps::toString(m.parameters().map.energy));
    s.emplace_back(
        "frames / accepted",
        std::to_string(m.frameCount()) + " / " + std::to_string(m.acceptedCount()));
    s.emplace_back("egomotion failures", std::to_string(m.egomotionFailures()));
    const auto unreliable = m.unreliableReasons();
    std::string why;
    for (const auto& r : unreliable)
    {
        why += (why.empty() ? "" : "; ") + r;
    }
    s.emplace_back("unreliable", unreliable.empty() ? std::string("no reason known") : why);
    s.emplace_back(
        "ms per frame: stereo / egomotion / rectification / total",
        fixed(ms.stereo, 1) + " / " + fixed(ms.egomotion, 1) + " / " + fixed(ms.rectification, 1) +
            " / " + fixed(ms.total, 1));
    s.emplace_back(
        "rectifications: calls / attempts / successes", std::to_string(m.rectifications().size()) +
                                                            " / " + std::to_string(rt.attempts) +
                                                            " / " + std::to_string(rt.successes));
    s.emplace_back(
        "rectification ms per call: median / max",
        fixed(rt.median_ms, 1) + " / " + fixed(rt.max_ms, 1));
    s.emplace_back("final energy", fixed(m.finalEnergy(), 4));
    const std::string gap = startToEndName(ground_truth);
    s.emplace_back(gap + " egomotion [m]", fixed(loopGap(m.egomotionPoses()), 3));
    s.emplace_back(gap + " SLAM [m]", fixed(loopGap(m.slamPoses()), 3));
    if (!ground_truth.empty())
    {
        s.emplace_back(
            "ground truth: path length / start-to-end distance [m]",
            fixed(eval::pathLength(ground_truth), 3) + " / " + fixed(loopGap(ground_truth), 3));
    }
    if (info.egomotion_vs_gt && info.slam_vs_gt)
    {
        s.emplace_back(
            "ATE egomotion / SLAM [m]", fixed(info.egomotion_vs_gt->ate_rmse_m, 3) + " / " +
                                            fixed(info.slam_vs_gt->ate_rmse_m, 3));
        s.emplace_back(
            "drift egomotion / SLAM [%]", fixed(info.egomotion_vs_gt->rel.t_rel_percent, 2) +
                                              " / " + fixed(info.slam_vs_gt->rel.t_rel_percent, 2));
    }
    d.egomotion_vs_gt = info.egomotion_vs_gt;
    d.slam_vs_gt = info.slam_vs_gt;
    if (!info.input_ended_early.empty())
    {
        s.emplace_back("input ended early", info.input_ended_early);
    }
    if (!info.degenerate.empty())
    {
        s.emplace_back("degenerate result", info.degenerate);
    }
    if (info.skipped_observations > 0)
    {
        std::string first;
        for (const auto& r : info.skipped_reasons)
        {
            first += (first.empty() ? "" : "; ") + r;
        }
        s.emplace_back("frames skipped", info.skipped_text + " (first: " + first + ")");
    }
    if (info.skipped_unusable > 0)
    {
        s.emplace_back("unusable observations skipped", std::to_string(info.skipped_unusable));
    }
    if (!info.camera_change_warning.empty())
    {
        s.emplace_back("camera change", info.camera_change_warning);
    }
    if (!info.stopped_by_error.empty())
    {
        s.emplace_back(
            "stopped by an error",
            info.stopped_by_error + ": outputs cover the frames processed until then");
    }
    if (info.interrupted)
    {
        s.emplace_back("interrupted", "yes: outputs cover the frames processed until then");
    }
    s.emplace_back("wall time [s]", fixed(info.seconds, 1));
    return d;
}

}  // namespace emslam::apps
