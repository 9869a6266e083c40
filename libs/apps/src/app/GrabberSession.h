// SPDX-License-Identifier: BSD-3-Clause
// Private to emslam_apps (not installed): emslam-grabber's writing of the
// sensors' observations in time order, and its status line.
#pragma once

#include "GrabberSensors.h"

#include <emslam/apps/LiveViewer.h>
#include <emslam/hwdrivers/SensorStatus.h>
#include <emslam/io/RawlogOutput.h>

#include <mrpt/core/format.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/serialization/CSerializable.h>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace emslam::apps::grabber
{
/** Observations of a running sensor are held back at most this long to sort
 * them with the other sensors' [s]. */
constexpr double MAX_REORDER_DELAY = 2.0;

/** The grabbing session of one run(): sensors, pending observations, output.
 * It stops writing stereo frames after `max_frames` of them, if given. */
class Session
{
public:
    Session(
        std::vector<std::unique_ptr<Slot>>& slots,
        io::RawlogOutput& out,
        std::optional<std::size_t> max_frames)
        : m_slots(slots), m_out(out), m_max_frames(max_frames)
    {
    }

    /** Moves every queued observation into the pending set; returns the
     * state of each sensor sampled before its queue was emptied. */
    std::vector<int> collect()
    {
        std::vector<int> states;
        for (std::size_t i = 0; i < m_slots.size(); ++i)
        {
            Slot& s = *m_slots[i];
            states.push_back(s.state.load());
            for (auto& [ts, obj] : s.sensor->getObservations())
            {
                m_pending.emplace(ts, std::make_pair(i, obj));
                if (!s.has_last || ts > s.last_ts)
                {
                    s.last_ts = ts;
                    s.has_last = true;
                }
            }
        }
        return states;
    }

    /** Writes the pending observations that no running sensor can precede
     * any more (all of them if `all`). Throws if writing fails. */
    void write(const std::vector<int>& states, bool all)
    {
        bool bounded = false;
        mrpt::Clock::time_point watermark{};
        if (!all)
        {
            for (std::size_t i = 0; i < m_slots.size(); ++i)
            {
                if (states[i] == RUNNING && m_slots[i]->has_last)
                {
                    watermark =
                        bounded ? std::min(watermark, m_slots[i]->last_ts) : m_slots[i]->last_ts;
                    bounded = true;
                }
            }
            if (bounded && !m_pending.empty())
            {
                // A stalled sensor must not hold the others back for ever.
                const auto newest = m_pending.rbegin()->first;
                const auto cap = newest - std::chrono::duration_cast<mrpt::Clock::duration>(
                                              std::chrono::duration<double>(MAX_REORDER_DELAY));
                watermark = std::max(watermark, cap);
            }
        }
        while (!m_pending.empty() && (!bounded || m_pending.begin()->first <= watermark))
        {
            auto node = m_pending.extract(m_pending.begin());
            writeOne(node.key(), node.mapped().first, *node.mapped().second);
        }
    }

    bool frameLimitReached() const { return m_limit_reached; }
    /** CObservationStereoImages written so far. */
    std::size_t framesWritten() const { return m_frames_written; }
    /** Observations of any kind written so far. */
    std::size_t objectsWritten() const { return m_objects_written; }
    void setViewer(LiveViewer* viewer) { m_viewer = viewer; }

private:
    void writeOne(
        mrpt::Clock::time_point ts, std::size_t slot, mrpt::serialization::CSerializable& obj)
    {
        const bool is_stereo = dynamic_cast<mrpt::obs::CObservationStereoImages*>(&obj) != nullptr;
        if (m_limit_reached && (is_stereo || ts > m_cutoff))
        {
            return;  // after the last requested frame
        }
        m_out.archive() << obj;
        ++m_objects_written;
        ++m_slots[slot]->written;
        if (is_stereo)
        {
            ++m_frames_written;
            if (m_viewer && m_viewer->wantsSnapshot())
            {
                LiveViewSnapshot snap;
                snap.image = dynamic_cast<mrpt::obs::CObservationStereoImages&>(obj).imageLeft;
                snap.status = "stereo frames written: " + std::to_string(m_frames_written);
                m_viewer->push(std::move(snap));
            }
            if (m_max_frames && m_frames_written >= *m_max_frames)
            {
                m_limit_reached = true;
                m_cutoff = ts;
            }
        }
    }

    std::vector<std::unique_ptr<Slot>>& m_slots;
    io::RawlogOutput& m_out;
    std::optional<std::size_t> m_max_frames;
    std::size_t m_frames_written{0};
    std::size_t m_objects_written{0};
    std::multimap<
        mrpt::Clock::time_point,
        std::pair<std::size_t, mrpt::serialization::CSerializable::Ptr>>
        m_pending;
    bool m_limit_reached{false};
    mrpt::Clock::time_point m_cutoff{};
    LiveViewer* m_viewer{nullptr};
};

/** The status line: observations and rate per sensor, dropped frames, size. */
class StatusLine
{
public:
    explicit StatusLine(bool enabled) : m_enabled(enabled), m_tty(::isatty(::fileno(stderr)) != 0)
    {
    }

    void update(
        const std::vector<std::unique_ptr<Slot>>& slots,
        double elapsed,
        const std::string& partial_file,
        bool force = false)
    {
        if (!m_enabled)
        {
            return;
        }
        const double every = m_tty ? 0.5 : 10.0;
        if (!force && elapsed < m_next)
        {
            return;
        }
        m_next = elapsed + every;
        std::string line = mrpt::format("%s: %6.1f s", PROGRAM, elapsed);
        std::size_t dropped = 0;
        for (const auto& s : slots)
        {
            line += mrpt::format(
                " | %s %zu (%.1f fps)%s", s->label.c_str(), s->written,
                elapsed > 0 ? static_cast<double>(s->written) / elapsed : 0.0,
                s->state.load() == RUNNING ? ""
                                           : (s->state.load() == ENDED ? " ended" : " FAILED"));
            if (const auto* st =
                    dynamic_cast<const emslam::hwdrivers::SensorStatus*>(s->sensor.get()))
            {
                dropped += st->droppedFrames();
            }
        }
        std::error_code ec;
        const auto bytes = std::filesystem::file_size(partial_file, ec);
        line += mrpt::format(" | dropped %zu | %s", dropped, megabytes(ec ? 0 : bytes).c_str());
        if (m_tty)
        {
            std::fprintf(stderr, "\r%s\x1b[K", line.c_str());
            m_open = true;
        }
        else
        {
            std::fprintf(stderr, "%s\n", line.c_str());
        }
        std::fflush(stderr);
    }

    void finish()
    {
        if (m_open)
        {
            std::fprintf(stderr, "\n");
            m_open = false;
        }
    }

private:
    bool m_enabled;
    bool m_tty;
    bool m_open{false};
    double m_next{0.0};
};

}  // namespace emslam::apps::grabber
