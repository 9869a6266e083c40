// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/IniFile.h>
#include <emslam/sim/StereoSimulator.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/Clock.h>
#include <mrpt/img/CImage.h>
#include <mrpt/poses/CPose3DQuat.h>
#include <mrpt/system/filesystem.h>

#include <cmath>
#include <stdexcept>

namespace emslam::sim
{
namespace
{
constexpr const char* SECTION = "Simulation";

[[noreturn]] void bad(const std::string& key, const std::string& msg)
{
    throw std::invalid_argument(std::string("[") + SECTION + "] " + key + ": " + msg);
}
}  // namespace

namespace
{
/** Every key of the section, once for load and save. */
void visit(StereoSimulator::TParameters& p, emslam::util::ConfigVisitor& v)
{
    v.field("fps", p.fps);
    v.field("start_time", p.start_time);
    v.field("sensor_label", p.sensor_label);
    v.field("exposure_amplitude", p.exposure_amplitude);
    v.field("exposure_period", p.exposure_period);
    v.field("max_step", p.max_step);
    v.field("max_step_deg", p.max_step_deg);
}
}  // namespace

void StereoSimulator::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    if (!(fps > 0 && fps <= 10000))
    {
        bad("fps", "must be in (0, 10000] (got " + std::to_string(fps) + ")");
    }
    // Timestamps are seconds since 1970 in a double: keep them exact to a microsecond.
    if (!(start_time >= 0 && start_time <= 1e10))
    {
        bad("start_time", "must be in [0, 1e10] s (got " + std::to_string(start_time) + ")");
    }
    if (!(exposure_amplitude >= 0 && exposure_amplitude < 0.9))
    {
        bad("exposure_amplitude", "must be in [0, 0.9)");
    }
    if (!(exposure_period > 0 && exposure_period <= 1e6))
    {
        bad("exposure_period", "must be in (0, 1e6] s");
    }
    if (!(max_step > 0 && max_step <= 1e3))
    {
        bad("max_step", "must be in (0, 1000] m");
    }
    if (!(max_step_deg > 0 && max_step_deg <= 180))
    {
        bad("max_step_deg", "must be in (0, 180] deg");
    }
    if (sensor_label.empty())
    {
        bad("sensor_label", "must not be empty");
    }
}

void StereoSimulator::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void StereoSimulator::loadFile(const std::string& ini_file)
{
    if (!mrpt::system::fileExists(ini_file))
    {
        throw std::invalid_argument("world file '" + ini_file + "' does not exist");
    }
    const mrpt::config::CConfigFileMemory cfg(emslam::io::readIniFile(ini_file, "world file"));
    try
    {
        load(cfg);
    }
    catch (const std::exception& e)
    {
        throw std::invalid_argument("'" + ini_file + "': " + e.what());
    }
}

void StereoSimulator::load(const mrpt::config::CConfigFileBase& cfg)
{
    TParameters p;
    p.loadFromConfigFile(cfg, SECTION);
    StereoRenderer::TParameters cam;
    cam.loadFromConfigFile(cfg, "Camera");
    Trajectory::TParameters tp;
    tp.loadFromConfigFile(cfg, "Trajectory");
    Trajectory traj;
    traj.setup(tp);
    World world;
    world.load(cfg, traj.waypointsXZ());

    const double step = tp.speed / p.fps;
    if (step > p.max_step)
    {
        bad("fps", "the camera moves " + std::to_string(step) +
                       " m between frames ([Trajectory] speed / " +
                       "fps), more than max_step = " + std::to_string(p.max_step) + " m");
    }
    const bool turns_on_spot = tp.type == "robot3dof" && tp.drive == "differential";
    if (turns_on_spot && tp.angular_speed_deg / p.fps > p.max_step_deg)
    {
        bad("fps", "the camera turns " + std::to_string(tp.angular_speed_deg / p.fps) +
                       " deg between frames, more than max_step_deg");
    }
    m_p = p;
    m_renderer.setParameters(cam);
    m_traj = traj;
    m_world = std::move(world);
    m_seed = cfg.read_int("World", "seed", 1);
    // A closed path ends with a frame at its very end (the camera waits there
    // for it), so the last frame is back at the first one's pose.
    const double frames = m_traj.duration() * p.fps;
    m_frames = static_cast<std::size_t>(
                   traj.params().closed ? std::ceil(frames - 1e-9) : std::floor(frames + 1e-9)) +
               1;
    m_T_scene_first = scenePose(0);
}

double StereoSimulator::frameTime(std::size_t i) const
{
    return m_p.start_time + static_cast<double>(i) / m_p.fps;
}

mrpt::poses::CPose3D StereoSimulator::scenePose(std::size_t i) const
{
    return m_traj.cameraPose(static_cast<double>(i) / m_p.fps, &m_world);
}

mrpt::poses::CPose3D StereoSimulator::groundTruth(std::size_t i) const
{
    if (i == 0)
    {
        return {};
    }
    return scenePose(i) - m_T_scene_first;
}

StereoSimulator::Frame StereoSimulator::renderFrame(std::size_t i, bool want_depth) const
{
    if (i >= m_frames)
    {
        throw std::out_of_range(
            "StereoSimulator::renderFrame: frame " + std::to_string(i) + " of " +
            std::to_string(m_frames));
    }
    const double t_rel = static_cast<double>(i) / m_p.fps;
    const double gain =
        1.0 + m_p.exposure_amplitude * std::sin(2 * M_PI * t_rel / m_p.exposure_period);
    const auto noise_seed = static_cast<std::uint64_t>(m_seed) * 1000003ULL + i;
    auto out = m_renderer.render(m_world, scenePose(i), t_rel, gain, noise_seed, want_depth);

    Frame f;
    f.t = frameTime(i);
    f.T_first_left = groundTruth(i);
    f.depth = out.depth;
    f.obs = mrpt::obs::CObservationStereoImages::Create();
    f.obs->timestamp = mrpt::Clock::fromDouble(f.t);
    f.obs->sensorLabel = m_p.sensor_label;
    f.obs->imageLeft = mrpt::img::CImage(out.left, mrpt::img::DEEP_COPY);
    f.obs->imageRight = mrpt::img::CImage(out.right, mrpt::img::DEEP_COPY);
    f.obs->hasImageRight = true;
    f.obs->hasImageDisparity = false;
    f.obs->setStereoCameraParams(m_renderer.stereoCamera());
    f.obs->cameraPose = mrpt::poses::CPose3DQuat();
    return f;
}

}  // namespace emslam::sim
