// SPDX-License-Identifier: BSD-3-Clause
#include "ConfigCount.h"

#include <emslam/hwdrivers/CReplayStereoCamera.h>
#include <emslam/hwdrivers/SensorStatus.h>

#include <mrpt/core/Clock.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <utility>

namespace emslam::hwdrivers
{
TReplayOptions::TReplayOptions(std::string sensor, std::string source_clock)
    : timestamps(source_clock), m_sensor(std::move(sensor)), m_source_clock(std::move(source_clock))
{
}

void TReplayOptions::visitKeys(util::ConfigVisitor& v)
{
    visitSourceKeys(v);
    const auto count = [&v](const std::string& key, std::size_t& n)
    {
        v.text(
            key, n, [](std::size_t value) { return std::to_string(value); },
            [&](const std::string& text) { return parseCount(text, v.section(), key, n); });
    };
    count("first_frame", first_frame);
    count("max_frames", max_frames);
    v.field("loop", loop);
    v.field("timestamps", timestamps);
}

void TReplayOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    auto v = util::ConfigVisitor::loader(c, s);
    visitKeys(v);
    validate();
}

void TReplayOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    // A saver only reads the fields: the walk is shared with loading, so it
    // takes them non-const (a polymorphic struct cannot walk a copy).
    auto v = util::ConfigVisitor::saver(c, s);
    const_cast<TReplayOptions*>(this)->visitKeys(v);
}

void TReplayOptions::validate() const
{
    if (timestamps != m_source_clock && timestamps != "now")
    {
        throw std::invalid_argument(
            m_sensor + ": 'timestamps' must be '" + m_source_clock + "' or 'now', not '" +
            timestamps + "'");
    }
}

void CReplayStereoCamera::startReplay(
    const TReplayOptions& options,
    std::size_t source_frames,
    double default_rate,
    const std::string& where)
{
    if (options.first_frame >= source_frames)
    {
        throw std::invalid_argument(
            where + "first_frame " + std::to_string(options.first_frame) + " is past the " +
            std::to_string(source_frames) + " frames of " + sourceName());
    }
    m_first = options.first_frame;
    m_loop = options.loop;
    m_end = source_frames;
    if (options.max_frames > 0)
    {
        m_end = std::min(m_end, options.first_frame + options.max_frames);
    }
    if (m_process_rate <= 0)
    {
        m_process_rate = default_rate;
    }
    m_stamp_now = options.stampNow();
    m_next = options.first_frame;
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
        if (!m_loop)
        {
            throw EndOfStream(
                std::string(GetRuntimeClass()->className) + " '" + m_sensorLabel + "': end of " +
                sourceName() + " after " + std::to_string(m_delivered) + " frames");
        }
        m_next = m_first;
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
