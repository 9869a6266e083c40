// SPDX-License-Identifier: BSD-3-Clause
#include "ConfigCount.h"

#include <emslam/hwdrivers/CStereoImageFolderCamera.h>
#include <emslam/hwdrivers/SensorStatus.h>
#include <emslam/stereo/EurocSequence.h>
#include <emslam/stereo/ExceptionMessage.h>
#include <emslam/stereo/KittiSequence.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/Clock.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <stdexcept>

IMPLEMENTS_GENERIC_SENSOR(CStereoImageFolderCamera, emslam::hwdrivers)

namespace emslam::hwdrivers
{
void CStereoImageFolderCamera::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    format = c.read_string(s, "format", format);
    folder = c.read_string(s, "folder", folder);
    first_frame = readCount(c, s, "first_frame", first_frame);
    max_frames = readCount(c, s, "max_frames", max_frames);
    loop = c.read_bool(s, "loop", loop);
    timestamps = c.read_string(s, "timestamps", timestamps);
    time_offset = c.read_double(s, "time_offset", time_offset);
    validate();
}

void CStereoImageFolderCamera::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    c.write(s, "format", format);
    c.write(s, "folder", folder);
    c.write(s, "first_frame", static_cast<std::uint64_t>(first_frame));
    c.write(s, "max_frames", static_cast<std::uint64_t>(max_frames));
    c.write(s, "loop", loop);
    c.write(s, "timestamps", timestamps);
    // With a decimal point even when whole: a number key, not an integer one.
    c.write(s, "time_offset", mrpt::format("%#.17g", time_offset));
}

void CStereoImageFolderCamera::TParameters::validate() const
{
    if (format != "kitti" && format != "euroc")
    {
        throw std::invalid_argument(
            "CStereoImageFolderCamera: 'format' must be 'kitti' or 'euroc', not '" + format + "'");
    }
    if (folder.empty())
    {
        throw std::invalid_argument("CStereoImageFolderCamera: 'folder' is mandatory");
    }
    if (timestamps != "dataset" && timestamps != "now")
    {
        throw std::invalid_argument(
            "CStereoImageFolderCamera: 'timestamps' must be 'dataset' or 'now', not '" +
            timestamps + "'");
    }
    // A UNIX time: finite, and within +-1e11 s (about 3,000 years) so that
    // adding dataset times keeps microsecond resolution.
    if (!(std::abs(time_offset) <= 1e11))
    {
        throw std::invalid_argument(mrpt::format(
            "CStereoImageFolderCamera: 'time_offset' = %g: must be a UNIX time within +-1e11 s",
            time_offset));
    }
}

void CStereoImageFolderCamera::loadConfig_sensorSpecific(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    TParameters p;
    p.loadFromConfigFile(cfg, section);
    const std::string where = "CStereoImageFolderCamera, section " + section + ": ";
    std::error_code ec;
    if (!std::filesystem::is_directory(p.folder, ec))
    {
        throw std::invalid_argument(
            where + "folder '" + p.folder +
            "' does not exist (relative paths are taken from the working folder '" +
            std::filesystem::current_path().string() + "')");
    }
    double t_first = 0, t_last = 0;
    try
    {
        if (p.format == "kitti")
        {
            auto seq = std::make_shared<emslam::stereo::KittiSequence>();
            seq->sensor_label = m_sensorLabel;
            seq->time_offset = p.time_offset;
            seq->open(p.folder);
            m_size = seq->size();
            if (m_size > 0)
            {
                t_first = seq->timestamp(0);
                t_last = seq->timestamp(m_size - 1);
            }
            m_load = [seq](std::size_t i) { return seq->frame(i).obs; };
        }
        else
        {
            auto seq = std::make_shared<emslam::stereo::EurocSequence>();
            seq->sensor_label = m_sensorLabel;
            seq->open(p.folder);
            m_size = seq->size();
            if (m_size > 0)
            {
                t_first = seq->timestamp(0);
                t_last = seq->timestamp(m_size - 1);
            }
            m_load = [seq](std::size_t i) { return seq->frame(i).obs; };
        }
    }
    catch (const std::exception& e)
    {
        throw std::invalid_argument(where + emslam::stereo::shortExceptionMessage(e));
    }
    if (p.first_frame >= m_size)
    {
        throw std::invalid_argument(
            where + "first_frame " + std::to_string(p.first_frame) + " is past the folder's " +
            std::to_string(m_size) + " frames");
    }
    m_end = m_size;
    if (p.max_frames > 0)
    {
        m_end = std::min(m_end, p.first_frame + p.max_frames);
    }
    if (m_process_rate <= 0)
    {
        // The dataset's mean rate; 10 Hz for a one-frame folder.
        m_process_rate = (m_size > 1 && t_last > t_first)
                             ? static_cast<double>(m_size - 1) / (t_last - t_first)
                             : 10.0;
    }
    m_params = p;
    m_next = p.first_frame;
    m_delivered = 0;
}

void CStereoImageFolderCamera::doProcess()
{
    if (!m_load)
    {
        throw std::logic_error("CStereoImageFolderCamera: doProcess() before loadConfig()");
    }
    if (m_next >= m_end)
    {
        if (!m_params.loop)
        {
            throw EndOfStream(
                "CStereoImageFolderCamera '" + m_sensorLabel + "': end of '" + m_params.folder +
                "' after " + std::to_string(m_delivered) + " frames");
        }
        m_next = m_params.first_frame;
    }
    m_state = ssWorking;
    auto obs = m_load(m_next++);
    if (m_params.timestamps == "now")
    {
        obs->timestamp = mrpt::Clock::now();
    }
    ++m_delivered;
    appendObservation(obs);
}

}  // namespace emslam::hwdrivers
