// SPDX-License-Identifier: BSD-3-Clause
#include "ConfigCount.h"

#include <emslam/hwdrivers/CSimulatedStereoCamera.h>
#include <emslam/hwdrivers/SensorStatus.h>
#include <emslam/stereo/ExceptionMessage.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/Clock.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

IMPLEMENTS_GENERIC_SENSOR(CSimulatedStereoCamera, emslam::hwdrivers)

namespace emslam::hwdrivers
{
void CSimulatedStereoCamera::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    world_file = c.read_string(s, "world_file", world_file);
    first_frame = readCount(c, s, "first_frame", first_frame);
    max_frames = readCount(c, s, "max_frames", max_frames);
    loop = c.read_bool(s, "loop", loop);
    timestamps = c.read_string(s, "timestamps", timestamps);
    validate();
}

void CSimulatedStereoCamera::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    c.write(s, "world_file", world_file);
    c.write(s, "first_frame", static_cast<std::uint64_t>(first_frame));
    c.write(s, "max_frames", static_cast<std::uint64_t>(max_frames));
    c.write(s, "loop", loop);
    c.write(s, "timestamps", timestamps);
}

void CSimulatedStereoCamera::TParameters::validate() const
{
    if (world_file.empty())
    {
        throw std::invalid_argument("CSimulatedStereoCamera: 'world_file' is mandatory");
    }
    if (timestamps != "now" && timestamps != "simulation")
    {
        throw std::invalid_argument(
            "CSimulatedStereoCamera: 'timestamps' must be 'now' or 'simulation', not '" +
            timestamps + "'");
    }
}

void CSimulatedStereoCamera::loadConfig_sensorSpecific(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    TParameters p;
    p.loadFromConfigFile(cfg, section);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p.world_file, ec))
    {
        throw std::invalid_argument(
            "CSimulatedStereoCamera, section " + section + ": world_file '" + p.world_file +
            "' does not exist (relative paths are taken from the working folder '" +
            std::filesystem::current_path().string() + "')");
    }
    auto sim = std::make_shared<emslam::sim::StereoSimulator>();
    try
    {
        sim->loadFile(p.world_file);
    }
    catch (const std::exception& e)
    {
        throw std::invalid_argument(
            "CSimulatedStereoCamera, section " + section + ": world_file '" + p.world_file +
            "': " + emslam::stereo::shortExceptionMessage(e));
    }
    if (p.first_frame >= sim->frameCount())
    {
        throw std::invalid_argument(
            "CSimulatedStereoCamera, section " + section + ": first_frame " +
            std::to_string(p.first_frame) + " is past the trajectory's " +
            std::to_string(sim->frameCount()) + " frames");
    }
    m_end = sim->frameCount();
    if (p.max_frames > 0)
    {
        m_end = std::min(m_end, p.first_frame + p.max_frames);
    }
    if (m_process_rate <= 0)
    {
        m_process_rate = sim->params().fps;
    }
    m_params = p;
    m_sim = std::move(sim);
    m_next = m_params.first_frame;
    m_delivered = 0;
}

void CSimulatedStereoCamera::doProcess()
{
    if (!m_sim)
    {
        throw std::logic_error("CSimulatedStereoCamera: doProcess() before loadConfig()");
    }
    if (m_next >= m_end)
    {
        if (!m_params.loop)
        {
            throw EndOfStream(
                "CSimulatedStereoCamera '" + m_sensorLabel + "': end of the trajectory after " +
                std::to_string(m_delivered) + " frames");
        }
        m_next = m_params.first_frame;
    }
    m_state = ssWorking;
    auto frame = m_sim->renderFrame(m_next++);
    frame.obs->sensorLabel = m_sensorLabel;
    if (m_params.timestamps == "now")
    {
        frame.obs->timestamp = mrpt::Clock::now();
    }
    ++m_delivered;
    appendObservation(frame.obs);
}

}  // namespace emslam::hwdrivers
