// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/hwdrivers/CStereoImageFolderCamera.h>
#include <emslam/hwdrivers/SensorStatus.h>
#include <emslam/io/EurocSequence.h>
#include <emslam/io/KittiSequence.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/config/CConfigFileBase.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <stdexcept>

IMPLEMENTS_GENERIC_SENSOR(CStereoImageFolderCamera, emslam::hwdrivers)

namespace emslam::hwdrivers
{
void CStereoImageFolderCamera::TParameters::visitSourceKeys(util::ConfigVisitor& v)
{
    v.field("format", format);
    v.field("folder", folder);
    // Written with a decimal point even when whole (a number key, not an
    // integer one); read as MRPT reads any double.
    v.text(
        "time_offset", time_offset, [](double t) { return mrpt::format("%#.17g", t); },
        [&v, this](const std::string&)
        { return v.input().read_double(v.section(), "time_offset", time_offset); });
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
    // A UNIX time: finite, and within +-1e11 s (about 3,000 years) so that
    // adding dataset times keeps microsecond resolution.
    if (!(std::abs(time_offset) <= 1e11))
    {
        throw std::invalid_argument(mrpt::format(
            "CStereoImageFolderCamera: 'time_offset' = %g: must be a UNIX time within +-1e11 s",
            time_offset));
    }
    TReplayOptions::validate();
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
    std::shared_ptr<emslam::io::DatasetSequence> sequence;
    try
    {
        if (p.format == "kitti")
        {
            auto kitti = std::make_shared<emslam::io::KittiSequence>();
            kitti->time_offset = p.time_offset;
            kitti->open(p.folder);
            sequence = kitti;
        }
        else
        {
            auto euroc = std::make_shared<emslam::io::EurocSequence>();
            euroc->open(p.folder);
            sequence = euroc;
        }
    }
    catch (const std::exception& e)
    {
        throw std::invalid_argument(where + emslam::util::shortExceptionMessage(e));
    }
    m_params = p;
    // The dataset's mean rate; 10 Hz for a one-frame folder.
    startReplay(p, sequence->size(), sequence->meanFrameRate(10.0), where);
    m_sequence = std::move(sequence);
}

mrpt::obs::CObservation::Ptr CStereoImageFolderCamera::replayFrame(std::size_t i)
{
    return m_sequence->readFrame(i).obs;
}

}  // namespace emslam::hwdrivers
