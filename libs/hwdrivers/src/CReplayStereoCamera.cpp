// SPDX-License-Identifier: BSD-3-Clause
#include "ConfigCount.h"

#include <emslam/hwdrivers/CReplayStereoCamera.h>
#include <emslam/hwdrivers/SensorStatus.h>

#include <mrpt/core/Clock.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>

namespace emslam::hwdrivers
{
void TReplayRange::loadRangeKeys(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    first_frame = readCount(c, s, "first_frame", first_frame);
    max_frames = readCount(c, s, "max_frames", max_frames);
    loop = c.read_bool(s, "loop", loop);
}

void TReplayRange::saveRangeKeys(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    c.write(s, "first_frame", static_cast<std::uint64_t>(first_frame));
    c.write(s, "max_frames", static_cast<std::uint64_t>(max_frames));
    c.write(s, "loop", loop);
}

void CReplayStereoCamera::startReplay(
    const TReplayRange& range,
    std::size_t source_frames,
    bool stamp_now,
    double default_rate,
    const std::string& where)
{
    if (range.first_frame >= source_frames)
    {
        throw std::invalid_argument(
            where + "first_frame " + std::to_string(range.first_frame) + " is past the " +
            std::to_string(source_frames) + " frames of " + sourceName());
    }
    m_range = range;
    m_end = source_frames;
    if (range.max_frames > 0)
    {
        m_end = std::min(m_end, range.first_frame + range.max_frames);
    }
    if (m_process_rate <= 0)
    {
        m_process_rate = default_rate;
    }
    m_stamp_now = stamp_now;
    m_next = range.first_frame;
    m_delivered = 0;
    m_started = true;
}

void CReplayStereoCamera::doProcess()
{
    if (!m_started)
    {
        throw std::logic_error(
            std::string(GetRuntimeClass()->className) + ": doProcess() before loadConfig()");
    }
    if (m_next >= m_end)
    {
        if (!m_range.loop)
        {
            throw EndOfStream(
                std::string(GetRuntimeClass()->className) + " '" + m_sensorLabel + "': end of " +
                sourceName() + " after " + std::to_string(m_delivered) + " frames");
        }
        m_next = m_range.first_frame;
    }
    m_state = ssWorking;
    auto obs = replayFrame(m_next++);
    obs->sensorLabel = m_sensorLabel;
    if (m_stamp_now)
    {
        obs->timestamp = mrpt::Clock::now();
    }
    ++m_delivered;
    appendObservation(obs);
}

}  // namespace emslam::hwdrivers
