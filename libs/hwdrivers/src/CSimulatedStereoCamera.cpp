// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/hwdrivers/CSimulatedStereoCamera.h>
#include <emslam/hwdrivers/SensorStatus.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/config/CConfigFileBase.h>

#include <filesystem>
#include <stdexcept>

IMPLEMENTS_GENERIC_SENSOR(CSimulatedStereoCamera, emslam::hwdrivers)

namespace emslam::hwdrivers
{
void CSimulatedStereoCamera::TParameters::visitSourceKeys(util::ConfigVisitor& v)
{
    v.field("world_file", world_file);
}

void CSimulatedStereoCamera::TParameters::validate() const
{
    if (world_file.empty())
    {
        throw std::invalid_argument("CSimulatedStereoCamera: 'world_file' is mandatory");
    }
    TReplayOptions::validate();
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
            "': " + emslam::util::shortExceptionMessage(e));
    }
    startReplay(
        p, sim->frameCount(), sim->params().fps,
        "CSimulatedStereoCamera, section " + section + ": ");
    m_params = p;
    m_sim = std::move(sim);
}

mrpt::obs::CObservation::Ptr CSimulatedStereoCamera::replayFrame(std::size_t i)
{
    return m_sim->renderFrame(i).obs;
}

}  // namespace emslam::hwdrivers
