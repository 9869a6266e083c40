// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/ActionCovariance.h>
#include <emslam/slam/ConfigRenames.h>
#include <emslam/slam/EntropySlam.h>
#include <emslam/slam/ScanFusion.h>
#include <emslam/util/ConfigVisitor.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <future>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace emslam::slam
{
namespace
{
constexpr const char* MAPPER_SECTION = "EntropySlam";
constexpr const char* STEREO_SECTION = "StereoMatcher";
constexpr const char* EGOMOTION_SECTION = "EgomotionEstimator";
constexpr const char* MAP_SECTION = "EntropyVoxelMap";
constexpr const char* SAMPLING_SECTION = "SpaceSampler";
constexpr const char* RECTIFIER_SECTION = "Rectifier";
constexpr const char* LOOP_CLOSER_SECTION = "LoopCloser";
/** Keyframes whose dense cloud may still be computing when a frame is
 * processed (the others join the map before it): the next keyframe's task
 * may then start beside it, on the same StereoMatcher, which serialises its
 * OpenCV calls (their shared buffers made the map depend on timing). */
constexpr std::size_t DENSE_KEYFRAMES_IN_FLIGHT = 1;
constexpr const char* VERTICAL_SECTION = "VerticalFromPlanes";
constexpr const char* OCCUPANCY_GRID_SECTION = "OccupancyGridBuilder";
constexpr const char* OCTOMAP_SECTION = "OctoMapBuilder";
/** A failed egomotion step is predicted by the previous one, and may be off
 * by that whole motion or at least by these. */
constexpr double FAILED_STEP_MIN_SIGMA_XYZ = 0.1;      // [m]
constexpr double FAILED_STEP_MIN_SIGMA_ROT_DEG = 3.0;  // [deg]

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/** Runs `load`; an error that does not name its section yet gets it in front. */
void loadSection(const std::string& section, const std::function<void()>& load)
{
    try
    {
        load();
    }
    catch (const std::exception& e)
    {
        const std::string msg = emslam::util::shortExceptionMessage(e);
        if (msg.find("[" + section + "]") != std::string::npos)
        {
            throw std::invalid_argument(msg);
        }
        throw std::invalid_argument("[" + section + "] " + msg);
    }
}

/** The frame's points the entropy map takes: `[EntropyVoxelMap]` min_range,
 * max_range and decimation apply, as for observations inserted through MRPT. */
emslam::maps::WeightedPointCloud toWeightedCloud(
    const emslam::stereo::StereoFrame& f, const emslam::CEntropyVoxelMap::TInsertionOptions& o)
{
    const double max_r2 =
        o.max_range > 0 ? o.max_range * o.max_range : std::numeric_limits<double>::infinity();
    const double min_r2 = o.min_range * o.min_range;
    const auto step = static_cast<std::size_t>(o.decimation);
    emslam::maps::WeightedPointCloud c;
    c.points.reserve(f.size() / step + 1);
    for (std::size_t i = 0; i < f.size(); i += step)
    {
        const auto& p = f.points[i];
        const double r2 = static_cast<double>(p.x) * p.x + static_cast<double>(p.y) * p.y +
                          static_cast<double>(p.z) * p.z;
        if (std::isfinite(r2) && r2 <= max_r2 && r2 >= min_r2)
        {
            c.points.push_back(p);
        }
    }
    c.weights.assign(c.points.size(), 1.0f);
    return c;
}
}  // namespace

namespace
{
/** Every key of the section, once for load and save. */
void visit(EntropySlam::TOptions& p, emslam::util::ConfigVisitor& v)
{
    v.field("egomotion_only", p.egomotion_only, "egomotion only: the map is never rectified");
    v.field("map_cell_size", p.map_cell_size, "[m] map.ply cell per frame (<= 0: every point)");
    v.field(
        "export_max_height", p.export_max_height,
        "[m] above the first camera: map.3Dscene / map_top.png cut (inf: none)");
    v.field(
        "depth_sigma_px", p.depth_sigma_px,
        "[px] disparity noise: sigma_z = z^2 sigma_d / (f b) of a stereo point");
    v.field("rgbd_depth_sigma", p.rgbd_depth_sigma, "[1/m] sigma_z = k z^2 of an RGB-D point");
    v.field(
        "fused_voxel_size", p.fused_voxel_size, "[m] cell of the fused map (1/sigma^2 weights)");
    v.field("max_point_sigma", p.max_point_sigma, "[m] fused points above this sigma are dropped");
    v.field(
        "max_observation_sigma", p.max_observation_sigma,
        "[m] points above this sigma are not fused at all");
    v.field(
        "fuse_along_rays", p.fuse_along_rays,
        "points join the strongest cell along their ray within 2 sigma");
    v.field(
        "max_map_clouds_mb", p.max_map_clouds_mb,
        "[MB] keyframe clouds kept for the map; past it every 2nd, 4th.. keyframe (0: no limit)");
}
}  // namespace

void EntropySlam::TOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    validate();
}

void EntropySlam::TOptions::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

std::size_t EntropySlam::TOptions::mapCloudsBytes() const
{
    return static_cast<std::size_t>(max_map_clouds_mb * 1024.0 * 1024.0);
}

FusedPointCloud::TOptions EntropySlam::TOptions::fusionOptions() const
{
    FusedPointCloud::TOptions o;
    o.voxel_size = fused_voxel_size;
    o.max_sigma = max_point_sigma;
    o.max_observation_sigma = max_observation_sigma;
    o.along_rays = fuse_along_rays;
    return o;
}

void EntropySlam::TOptions::validate() const
{
    // Cell indices are coordinate / cell size in an int: not below 1 mm.
    if (!std::isfinite(map_cell_size) ||
        (map_cell_size > 0 && (map_cell_size < 0.001 || map_cell_size > 1000)))
    {
        throw std::invalid_argument(
            "[EntropySlam] map_cell_size = " + std::to_string(map_cell_size) +
            ": must be <= 0 (every point) or in [0.001, 1000] m");
    }
    const auto positive = [](double v, const char* key, const std::string& range)
    {
        if (!(v > 0))
        {
            throw std::invalid_argument(
                std::string("[EntropySlam] ") + key + " = " + std::to_string(v) + ": must be " +
                range);
        }
    };
    positive(depth_sigma_px, "depth_sigma_px", "> 0 px");
    positive(rgbd_depth_sigma, "rgbd_depth_sigma", "> 0 per m");
    if (!(fused_voxel_size >= 0.001 && fused_voxel_size <= 1000))
    {
        throw std::invalid_argument(
            "[EntropySlam] fused_voxel_size = " + std::to_string(fused_voxel_size) +
            ": must be in [0.001, 1000] m");
    }
    positive(max_point_sigma, "max_point_sigma", "> 0 m (inf: no gate)");
    positive(max_observation_sigma, "max_observation_sigma", "> 0 m (inf: every point)");
    if (!(max_map_clouds_mb >= 0 && max_map_clouds_mb <= 1e6))
    {
        throw std::invalid_argument(
            "[EntropySlam] max_map_clouds_mb = " + std::to_string(max_map_clouds_mb) +
            ": must be in [0, 1e6] MB (0: no limit)");
    }
    if (std::isnan(export_max_height) ||
        export_max_height == -std::numeric_limits<double>::infinity())
    {
        throw std::invalid_argument(
            "[EntropySlam] export_max_height: must be a number of metres or inf (no cut)");
    }
}

void EntropySlam::TParameters::loadFromConfigFile(const mrpt::config::CConfigFileBase& given)
{
    // A config written before the sections took their components' names.
    std::ostringstream renamed;
    const auto c = emslam::util::withCurrentNames(given, configRenames(), renamed);
    loadSection(STEREO_SECTION, [&] { stereo.loadFromConfigFile(c, STEREO_SECTION); });
    loadSection(EGOMOTION_SECTION, [&] { egomotion.loadFromConfigFile(c, EGOMOTION_SECTION); });
    loadSection(MAP_SECTION, [&] { map.loadFromConfigFile(c, MAP_SECTION); });
    loadSection(MAP_SECTION, [&] { insertion.loadFromConfigFile(c, MAP_SECTION); });
    loadSection(SAMPLING_SECTION, [&] { sampling.loadFromConfigFile(c, SAMPLING_SECTION); });
    loadSection(RECTIFIER_SECTION, [&] { rectifier.loadFromConfigFile(c, RECTIFIER_SECTION); });
    loadSection(MAPPER_SECTION, [&] { mapper.loadFromConfigFile(c, MAPPER_SECTION); });
    loadSection(
        LOOP_CLOSER_SECTION, [&] { loop_closer.loadFromConfigFile(c, LOOP_CLOSER_SECTION); });
    loadSection(
        VERTICAL_SECTION,
        [&]
        {
            loop_closer.vertical.loadFromConfigFile(c, VERTICAL_SECTION);
            loop_closer.vertical.validate();
        });
    loadSection(
        OCCUPANCY_GRID_SECTION,
        [&] { occupancy_grid.loadFromConfigFile(c, OCCUPANCY_GRID_SECTION); });
    loadSection(OCTOMAP_SECTION, [&] { octomap.loadFromConfigFile(c, OCTOMAP_SECTION); });
}

void EntropySlam::TParameters::saveToConfigFile(mrpt::config::CConfigFileBase& c) const
{
    stereo.saveToConfigFile(c, STEREO_SECTION);
    egomotion.saveToConfigFile(c, EGOMOTION_SECTION);
    map.saveToConfigFile(c, MAP_SECTION);
    insertion.saveToConfigFile(c, MAP_SECTION);
    sampling.saveToConfigFile(c, SAMPLING_SECTION);
    rectifier.saveToConfigFile(c, RECTIFIER_SECTION);
    mapper.saveToConfigFile(c, MAPPER_SECTION);
    loop_closer.saveToConfigFile(c, LOOP_CLOSER_SECTION);
    loop_closer.vertical.saveToConfigFile(c, VERTICAL_SECTION);
    occupancy_grid.saveToConfigFile(c, OCCUPANCY_GRID_SECTION);
    octomap.saveToConfigFile(c, OCTOMAP_SECTION);
}

EntropySlam::EntropySlam(const TParameters& p)
    : m_p(p),
      m_odometry(p.stereo, p.egomotion),
      m_sampler(p.sampling),
      m_loops(p.loop_closer),
      m_loop_estimator(p.egomotion),
      m_clouds(p.mapper.max_observation_sigma, p.mapper.mapCloudsBytes())
{
    m_cov_keyframe_cur.setZero();
    if (m_p.mapper.egomotion_only)
    {
        m_p.rectifier.mode = emslam::rectify::RectificationMode::Serial;
        m_p.rectifier.rectify_every = 0;
    }
    m_runner = emslam::rectify::createRectificationRunner(m_p.rectifier, m_p.map, m_p.insertion);
    if (m_p.loop_closer.enabled && !m_p.mapper.egomotion_only)
    {
        m_loop_worker = std::make_unique<BackgroundWorker>(
            [this] { m_loops.update(m_loop_estimator, m_stop_check); });
    }
}

EntropySlam::~EntropySlam() = default;

bool EntropySlam::process(const mrpt::obs::CObservation& obs)
{
    if (m_finished)
    {
        throw std::logic_error("EntropySlam::process after finish()");
    }
    const auto t0 = Clock::now();
    StereoOdometry::Step step;
    if (!runOdometry(obs, step))
    {
        return false;
    }
    const emslam::stereo::StereoFrame& f = step.frame;
    FrameRecord r;
    r.index = m_records.size();
    r.timestamp = mrpt::Clock::toDouble(f.timestamp);
    r.ms_stereo = step.ms_stereo;
    r.points = f.size();
    m_image_width = f.intensity.cols;
    m_image_height = f.intensity.rows;
    m_last_image = f.intensity;

    const mrpt::poses::CPose3D& action = step.action;  // identity: the first frame
    const emslam::rectify::ActionCovariance action_cov = recordStep(step, r);
    m_egomotion.push_back({r.timestamp, r.index, m_T_session_run + m_odometry.pose()});
    // Sparse front-end: the keyframes' dense clouds are computed on the
    // other core while the next frame's stereo and egomotion run, and join
    // the map in order (DENSE_KEYFRAMES_IN_FLIGHT may stay pending).
    m_added_clouds.clear();
    completePendingKeyframe(&r, DENSE_KEYFRAMES_IN_FLIGHT);
    if (m_relocalizer && !relocalize(r))
    {
        // Not located yet: placed from the frame that will be, later.
        m_links.push_back({r.index, mrpt::poses::CPose3D()});
        r.ms_total = msSince(t0);
        m_records.push_back(r);
        m_online.push_back(m_egomotion.back());
        return true;
    }

    const emslam::rectify::ActionCovariance cov_since_keyframe = emslam::rectify::composeCovariance(
        m_T_keyframe_cur, m_cov_keyframe_cur, action, action_cov);
    const mrpt::poses::CPose3D motion_since_keyframe = m_T_keyframe_cur + action;
    r.accepted = m_sampler.feed(action);
    if (r.accepted)
    {
        m_last_keyframe = r.index;
        m_T_keyframe_cur = mrpt::poses::CPose3D();
        m_cov_keyframe_cur.setZero();
    }
    else
    {
        m_T_keyframe_cur = m_T_keyframe_cur + action;
        m_cov_keyframe_cur = cov_since_keyframe;
    }
    m_links.push_back({m_last_keyframe, m_T_keyframe_cur});
    if (r.accepted)
    {
        addKeyframe(f, cov_since_keyframe, motion_since_keyframe, r);
    }
    r.energy = m_energy;
    r.ms_total = msSince(t0);
    m_records.push_back(r);
    m_online.push_back({r.timestamp, r.index, onlinePose(r.index)});
    return true;
}

bool EntropySlam::runOdometry(const mrpt::obs::CObservation& obs, StereoOdometry::Step& step)
{
    try
    {
        return m_odometry.process(obs, step);
    }
    catch (const std::bad_alloc&)
    {
        throw;  // not the observation's fault
    }
    catch (const std::exception& e)
    {
        // The front-end changes no mapper state: the caller may skip the frame.
        throw UnusableObservation(emslam::util::shortExceptionMessage(e));
    }
}

emslam::rectify::ActionCovariance EntropySlam::recordStep(
    const StereoOdometry::Step& step, FrameRecord& r)
{
    const auto& ego = step.egomotion;
    r.ms_egomotion = ego.ms_total;
    emslam::rectify::ActionCovariance action_cov = m_p.rectifier.odometryPrior().stepCovariance();
    if (step.first)
    {
        return action_cov;
    }
    r.initial_matches = ego.initial_matches;
    r.final_matches = ego.final_matches;
    r.egomotion_ok = ego.ok;
    if (step.predicted)
    {
        m_predicted_since_keyframe = true;
        // Constant velocity, with a covariance wide enough for the
        // rectifier to move the step wherever the map says.
        action_cov = emslam::rectify::predictionCovariance(
            step.action, FAILED_STEP_MIN_SIGMA_XYZ, mrpt::DEG2RAD(FAILED_STEP_MIN_SIGMA_ROT_DEG));
    }
    else if (ego.has_covariance)
    {
        action_cov = ego.covariance;
    }
    for (int k = 0; k < 6; ++k)
    {
        r.step_sigma[static_cast<std::size_t>(k)] = std::sqrt(std::max(0.0, action_cov(k, k)));
    }
    return action_cov;
}

void EntropySlam::addKeyframe(
    const emslam::stereo::StereoFrame& f,
    const emslam::rectify::ActionCovariance& cov_since_keyframe,
    const mrpt::poses::CPose3D& motion_since_keyframe,
    FrameRecord& r)
{
    // What registering this keyframe again needs, kept only for loop closing.
    // The run's first keyframe in a session follows the session's last.
    const auto junction = std::exchange(m_junction, std::nullopt);
    m_loops.addKeyframe(
        r.index, loopClosing() ? m_odometry.estimator().lastDescription() : nullptr,
        junction ? junction->second : cov_since_keyframe,
        junction ? junction->first : motion_since_keyframe,
        !junction && m_predicted_since_keyframe);
    m_predicted_since_keyframe = false;
    if (loopClosing())
    {
        m_loop_worker->notify();
        const std::size_t lag = m_loops.keyframeCount() - m_loops.processedCount();
        const double max_ms = m_p.loop_closer.max_lag_ms;
        if (lag > static_cast<std::size_t>(m_p.loop_closer.max_lag) ||
            (max_ms > 0 && m_loops.backlogMs() > max_ms))
        {
            m_loop_worker->drain();
        }
    }
    PendingKeyframe k;
    k.index = r.index;
    k.timestamp = r.timestamp;
    k.covariance = cov_since_keyframe;
    // The first accepted frame is the world origin; later ones are placed
    // by the motion since the previous accepted frame.
    k.action = m_sampler.accepted() == 1 ? mrpt::poses::CPose3D() : m_sampler.actionSinceAccepted();
    if (auto task = m_odometry.frontEnd().mapFrameTask(f))
    {
        k.cloud = std::async(
            std::launch::async,
            [this, task = std::move(task)]
            {
                DenseKeyframe d;
                d.frame = task();
                d.clouds = mapClouds(d.frame);
                return d;
            });
        m_pending.push_back(std::move(k));
    }
    else
    {
        const auto t_rect = Clock::now();
        addAccepted(f, mapClouds(f), k);
        r.ms_rectification = msSince(t_rect);
    }
}

mrpt::poses::CPose3D EntropySlam::onlinePose(std::size_t index)
{
    std::optional<emslam::rectify::TimedPose> anchor;
    if (loopClosing())
    {
        // (A keyframe of the session is on another egomotion chain.)
        if (const auto k = m_loops.lastPose(); k && ofThisRun(k->frame_index))
        {
            anchor = emslam::rectify::TimedPose{0.0, k->frame_index, k->pose};
        }
    }
    else
    {
        // The rectified poses change only when a rectification ends.
        const std::size_t done = m_runner->progress().rectifications;
        if (done != m_anchor_rectifications)
        {
            m_anchor_rectifications = done;
            const auto poses = m_runner->framePoses();
            if (!poses.empty())
            {
                m_rectified_anchor = poses.back();
            }
        }
        anchor = m_rectified_anchor;
    }
    const mrpt::poses::CPose3D& ego = m_egomotion[index].T_world_frame;
    if (!anchor)
    {
        return ego;
    }
    return anchor->T_world_frame + (ego - m_egomotion[anchor->frame_index].T_world_frame);
}

void EntropySlam::completePendingKeyframe(FrameRecord* record, std::size_t keep)
{
    while (!m_pending.empty())
    {
        const bool ready =
            m_pending.front().cloud.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
        if (m_pending.size() <= keep && !ready)
        {
            return;
        }
        // Taken out first: if the task threw, get() rethrows once and no
        // consumed future is left behind for finish().
        PendingKeyframe k = std::move(m_pending.front());
        m_pending.pop_front();
        const auto t_wait = Clock::now();
        DenseKeyframe cloud = k.cloud.get();
        const double ms_wait = msSince(t_wait);
        const auto t_rect = Clock::now();
        addAccepted(cloud.frame, std::move(cloud.clouds), k);
        if (record != nullptr)
        {
            record->ms_stereo += ms_wait;  // the dense cloud was late
            record->ms_rectification += msSince(t_rect);
        }
    }
}

EntropySlam::MapClouds EntropySlam::mapClouds(const emslam::stereo::StereoFrame& f) const
{
    // Reads only parameters fixed at construction: safe on the map task's thread.
    const DepthNoiseModel noise(f.camera, m_p.mapper.depth_sigma_px, m_p.mapper.rgbd_depth_sigma);
    return {toWeightedCloud(f, m_p.insertion), downsampleFrame(f, m_p.mapper.map_cell_size, noise)};
}

void EntropySlam::addAccepted(
    const emslam::stereo::StereoFrame& f, MapClouds clouds, const PendingKeyframe& k)
{
    const mrpt::poses::CPose3D& action = k.action;
    const std::size_t index = k.index;
    const double t = k.timestamp;
    const emslam::rectify::ActionCovariance& covariance = k.covariance;
    m_runner->addFrame(action, std::move(clouds.weighted), t, index, covariance);
    if (loopClosing())
    {
        // The keyframe is the last or, with the sparse front-end, the one
        // before the last egomotion pose.
        const auto it = std::find_if(
            m_egomotion.rbegin(), m_egomotion.rend(),
            [index](const emslam::rectify::TimedPose& p) { return p.frame_index == index; });
        if (it != m_egomotion.rend())
        {
            m_loops.observeVertical(index, f, it->T_world_frame);
        }
    }
    m_clouds.append(index, clouds.downsampled);
    m_added_clouds.push_back({index, std::move(clouds.downsampled)});
    const auto progress = m_runner->progress();
    if (progress.rectifications > 0)
    {
        m_energy = progress.energy;
        m_has_energy = true;
    }
    if (loopClosing() && progress.rectifications != m_rectifications_sent)
    {
        // A rectification ended: the online graph takes its poses.
        m_rectifications_sent = progress.rectifications;
        std::vector<LoopCloser::KeyframePose> poses;
        for (const auto& p : m_runner->framePoses())
        {
            poses.push_back({p.frame_index, p.T_world_frame});
        }
        m_loops.setRectifiedPoses(std::move(poses));
        m_loop_worker->notify();
    }
}

void EntropySlam::finish()
{
    if (m_finished)
    {
        return;
    }
    m_finished = true;
    m_added_clouds.clear();
    completePendingKeyframe(nullptr);
    // The loop closer catches up on its thread meanwhile; its polish takes
    // the final rectified poses.
    if (loopClosing())
    {
        m_loops.prepareToClose();
    }
    m_runner->finish();
    if (m_loop_worker)
    {
        m_loop_worker->drain();
        m_loop_worker->stop();
    }
    m_rectifications = m_runner->statistics();
    if (m_session && !m_relocalization && frameCount() > m_session_frames)
    {
        throw std::runtime_error(
            "none of the run's " + std::to_string(frameCount() - m_session_frames) +
            " frames was found in the session's map (no saved keyframe that looks like one "
            "registered it with a second one agreeing and clearly more inliers than any "
            "look-alike place): is it the same place, seen with the same [EgomotionEstimator]?");
    }
    if (m_runner->trajectory().empty())
    {
        return;
    }
    m_energy = m_runner->trajectory().energy();
    m_has_energy = true;
    m_entropy = m_runner->trajectory().entropy();
    m_keyframes.clear();
    auto poses = m_session ? withSessionKeyframes(m_runner->framePoses()) : m_runner->framePoses();
    if (loopClosing())
    {
        if (poses.size() != m_loops.keyframeCount())
        {
            throw std::logic_error(
                "EntropySlam::finish: " + std::to_string(poses.size()) + " keyframe poses for " +
                std::to_string(m_loops.keyframeCount()) + " keyframes of the loop closer");
        }
        std::vector<mrpt::poses::CPose3D> keyframe_poses;
        keyframe_poses.reserve(poses.size());
        for (const auto& fp : poses)
        {
            keyframe_poses.push_back(fp.T_world_frame);
        }
        keyframe_poses = m_loops.close(keyframe_poses, m_loop_estimator, m_stop_check);
        for (std::size_t k = 0; k < poses.size(); ++k)
        {
            poses[k].T_world_frame = keyframe_poses[k];
        }
    }
    if (m_session && m_session_use == SessionUse::Localize)
    {
        // The session's keyframes were the map the run was tracked in.
        poses.erase(
            std::remove_if(
                poses.begin(), poses.end(),
                [this](const emslam::rectify::TimedPose& p) { return !ofThisRun(p.frame_index); }),
            poses.end());
    }
    m_keyframe_slam = poses;
    std::map<std::size_t, mrpt::poses::CPose3D> T_world_keyframe;
    for (const auto& fp : poses)
    {
        m_keyframes.push_back(fp.frame_index);
        T_world_keyframe[fp.frame_index] = fp.T_world_frame;
    }
    m_map_clouds_stride = m_clouds.stride();
    m_keyframe_scans = m_clouds.takeScans();
    if (m_session && m_session_use == SessionUse::Continue)
    {
        m_keyframe_scans.insert(
            m_keyframe_scans.begin(), m_session->scans.begin(), m_session->scans.end());
    }
    {
        FusedPointCloud fused = fuseScans(m_keyframe_scans, poses, m_p.mapper.fusionOptions());
        m_fused_scans = scansOnFusedSurfaces(m_keyframe_scans, poses, fused);
        m_fusion_stats = fused.stats();
        m_map_cloud = fused.cloud();
    }
    m_clouds = KeyframeClouds(m_p.mapper.max_observation_sigma, m_p.mapper.mapCloudsBytes());
    m_slam.clear();
    for (std::size_t i = 0; i < m_records.size(); i++)
    {
        const auto& link = m_links[i];
        const auto it = T_world_keyframe.find(link.keyframe);
        if (it == T_world_keyframe.end())
        {
            throw std::logic_error(
                "EntropySlam::finish: keyframe " + std::to_string(link.keyframe) + " has no pose");
        }
        m_slam.push_back(
            {m_records[i].timestamp, m_records[i].index, it->second + link.T_keyframe_frame});
    }
}

std::vector<emslam::rectify::TimedPose> EntropySlam::currentSlamPoses() const
{
    if (!loopClosing() || m_finished)
    {
        return m_finished && !m_keyframe_slam.empty() ? m_keyframe_slam : m_runner->framePoses();
    }
    std::vector<emslam::rectify::TimedPose> poses;
    for (const auto& k : m_loops.currentPoses())
    {
        if (k.frame_index < m_records.size())  // (Localize: not the session's)
        {
            poses.push_back({m_records[k.frame_index].timestamp, k.frame_index, k.pose});
        }
    }
    return poses;
}

const emslam::CEntropyVoxelMap& EntropySlam::entropyMap() const
{
    if (!m_finished)
    {
        throw std::logic_error("EntropySlam::entropyMap before finish()");
    }
    return m_runner->trajectory().map();
}

const emslam::rectify::Trajectory& EntropySlam::trajectory() const
{
    if (!m_finished)
    {
        throw std::logic_error("EntropySlam::trajectory before finish()");
    }
    return m_runner->trajectory();
}

std::size_t EntropySlam::trajectoryElements() const
{
    return m_finished ? m_runner->trajectory().size() : 0;
}

std::size_t EntropySlam::compressions() const
{
    return m_finished ? m_runner->trajectory().compressionCount() : 0;
}

std::vector<std::string> EntropySlam::unreliableReasons() const
{
    std::vector<std::string> reasons;
    const std::size_t steps = runFrameCount() > 0 ? runFrameCount() - 1 : 0;
    const std::size_t failed = egomotionFailures();
    if (50 * failed > steps)
    {
        reasons.push_back(
            "egomotion: " + std::to_string(failed) + " of " + std::to_string(steps) +
            " steps failed (more than 2 %), predicted at constant velocity");
    }
    if (m_p.loop_closer.enabled)
    {
        const std::string loops = m_loops.unreliable();
        if (!loops.empty())
        {
            reasons.push_back("loop closing: " + loops);
        }
    }
    return reasons;
}

}  // namespace emslam::slam
