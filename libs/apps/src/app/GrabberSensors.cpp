// SPDX-License-Identifier: BSD-3-Clause
#include "GrabberSensors.h"

#include <emslam/apps/ConfigValidation.h>
#include <emslam/apps/StopSignal.h>
#include <emslam/hwdrivers/CDigiclopsStereoCamera.h>
#include <emslam/hwdrivers/CSimulatedStereoCamera.h>
#include <emslam/hwdrivers/CStereoImageFolderCamera.h>
#include <emslam/hwdrivers/CVideoStereoCamera.h>
#include <emslam/hwdrivers/SensorStatus.h>
#include <emslam/stereo/StereoMatcher.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/format.h>
#include <mrpt/system/string_utils.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <sstream>
#include <stdexcept>

namespace emslam::apps::grabber
{
using Clock = std::chrono::steady_clock;

std::string errorText(const std::exception& e)
{
    const std::string s = emslam::util::shortExceptionMessage(e);
    if (s.find("==== MRPT exception") == std::string::npos)
    {
        return s;
    }
    std::istringstream in(s);
    std::string out;
    for (std::string line; std::getline(in, line);)
    {
        const auto b = line.find_first_not_of(" \t");
        if (b == std::string::npos)
        {
            continue;
        }
        const bool frame = line[b] == '[' && b + 1 < line.size() &&
                           std::isdigit(static_cast<unsigned char>(line[b + 1]));  // "[3 ] ..."
        if (line.compare(b, 4, "====") == 0 || frame || line.compare(b, 10, "Call stack") == 0)
        {
            continue;
        }
        std::string text = line.substr(b);
        for (const char* label : {"Message:", "Location:"})
        {
            if (text.rfind(label, 0) == 0)
            {
                text = mrpt::system::trim(text.substr(std::string(label).size()));
            }
        }
        if (!text.empty())
        {
            out += (out.empty() ? "" : ": ") + text;
        }
    }
    return out.empty() ? s : out;
}

void sensorThread(Slot& s, const std::atomic<bool>& stop)
{
    const auto period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1.0 / s.sensor->getProcessRate()));
    auto next = Clock::now();
    while (!stop.load())
    {
        try
        {
            s.sensor->doProcess();
        }
        catch (const emslam::hwdrivers::EndOfStream&)
        {
            s.state.store(ENDED);
            return;
        }
        catch (const std::exception& e)
        {
            // A device call interrupted by the stop signal is not a failure.
            const bool stopping = stop.load() || StopSignal::requested();
            s.error = errorText(e);
            s.state.store(stopping ? ENDED : FAILED);
            return;
        }
        catch (...)
        {
            s.error = "unknown exception";
            s.state.store(FAILED);
            return;
        }
        next += period;
        if (next < Clock::now())
        {
            next = Clock::now();  // late: do not try to catch up in a burst
        }
        while (!stop.load() && Clock::now() < next)
        {
            std::this_thread::sleep_for(
                std::min<Clock::duration>(next - Clock::now(), std::chrono::milliseconds(20)));
        }
    }
}

std::string megabytes(std::uintmax_t b)
{
    return mrpt::format("%.1f MB", static_cast<double>(b) / 1e6);
}

void requireWellFormedValues(const mrpt::config::CConfigFileBase& cfg)
{
    mrpt::config::CConfigFileMemory known;
    known.write("global", "rawlog_GZ_compress_level", 1);
    std::vector<std::string> sections;
    cfg.getAllSections(sections);
    for (const auto& section : sections)
    {
        const std::string driver = cfg.read_string(section, "driver", "");
        if (cfg.keyExists(section, "rawlog-grabber-ignore"))
        {
            known.write(section, "rawlog-grabber-ignore", false);
        }
        if (!driver.empty())
        {
            known.write(section, "process_rate", 1.0);  // CGenericSensor's [Hz]
        }
        if (driver == "CDigiclopsStereoCamera")
        {
            emslam::hwdrivers::CDigiclopsStereoCamera::TParameters digiclops;
            digiclops.saveToConfigFile(known, section);
            const std::string stereo = cfg.read_string(section, "stereo_section", "");
            emslam::stereo::StereoMatcher::TParameters().saveToConfigFile(
                known, stereo.empty() ? digiclops.stereo_section : stereo);
        }
        else if (driver == "CSimulatedStereoCamera")
        {
            emslam::hwdrivers::CSimulatedStereoCamera::TParameters().saveToConfigFile(
                known, section);
        }
        else if (driver == "CStereoImageFolderCamera")
        {
            emslam::hwdrivers::CStereoImageFolderCamera::TParameters().saveToConfigFile(
                known, section);
        }
        else if (driver == "CVideoStereoCamera")
        {
            emslam::hwdrivers::CVideoStereoCamera::TParameters().saveToConfigFile(known, section);
        }
    }
    requireWellFormedConfigValues(cfg, known);
}

int gzLevel(const mrpt::config::CConfigFileBase& cfg)
{
    const int gz_level = cfg.read_int("global", "rawlog_GZ_compress_level", 1);
    if (gz_level < 0 || gz_level > 9)
    {
        throw std::invalid_argument(
            "[global] rawlog_GZ_compress_level = " + std::to_string(gz_level) +
            ": must be in 0..9");
    }
    return gz_level;
}

std::vector<std::unique_ptr<Slot>> createSensors(
    const mrpt::config::CConfigFileBase& cfg, const std::string& config_file)
{
    std::vector<std::unique_ptr<Slot>> slots;
    std::vector<std::string> sections;
    cfg.getAllSections(sections);
    for (const auto& section : sections)
    {
        const std::string driver = cfg.read_string(section, "driver", "");
        if (section == "global" || driver.empty() ||
            cfg.read_bool(section, "rawlog-grabber-ignore", false))
        {
            continue;
        }
        auto s = std::make_unique<Slot>();
        s->section = section;
        s->driver = driver;
        const std::string where = "sensor [" + section + "] (" + driver + "): ";
        s->sensor = mrpt::hwdrivers::CGenericSensor::createSensorPtr(driver);
        if (!s->sensor)
        {
            throw std::invalid_argument(
                "'" + config_file + "': " + where +
                "unknown driver (not a registered MRPT sensor class; emslam's are "
                "CDigiclopsStereoCamera, CSimulatedStereoCamera, CStereoImageFolderCamera, "
                "CVideoStereoCamera)");
        }
        try
        {
            s->sensor->loadConfig(cfg, section);
        }
        catch (const std::exception& e)
        {
            throw std::invalid_argument("'" + config_file + "': " + where + errorText(e));
        }
        if (!(s->sensor->getProcessRate() > 0))
        {
            throw std::invalid_argument(
                "'" + config_file + "': " + where + "process_rate must be > 0 [Hz]");
        }
        s->label = s->sensor->getSensorLabel();
        slots.push_back(std::move(s));
    }
    if (slots.empty())
    {
        throw std::invalid_argument(
            "'" + config_file + "' defines no sensor (no section with a 'driver' key)");
    }
    return slots;
}

void initializeSensors(std::vector<std::unique_ptr<Slot>>& slots)
{
    for (auto& s : slots)
    {
        try
        {
            s->sensor->initialize();
        }
        catch (const std::exception& e)
        {
            throw std::runtime_error(
                "sensor [" + s->section + "] (" + s->driver +
                "): initialize() failed: " + errorText(e));
        }
    }
}

}  // namespace emslam::apps::grabber
