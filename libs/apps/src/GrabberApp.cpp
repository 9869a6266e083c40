// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>
#include <emslam/apps/ConfigValidation.h>
#include <emslam/apps/GrabberApp.h>
#include <emslam/apps/LiveViewer.h>
#include <emslam/apps/StopSignal.h>
#include <emslam/hwdrivers/CDigiclopsStereoCamera.h>
#include <emslam/hwdrivers/CSimulatedStereoCamera.h>
#include <emslam/hwdrivers/CStereoImageFolderCamera.h>
#include <emslam/hwdrivers/DeviceList.h>
#include <emslam/hwdrivers/SensorStatus.h>
#include <emslam/io/RawlogOutput.h>
#include <emslam/stereo/ExceptionMessage.h>
#include <emslam/stereo/StereoMatcher.h>

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/core/format.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/system/os.h>
#include <mrpt/system/string_utils.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace emslam::apps
{
namespace
{
constexpr const char* PROGRAM = "emslam-grabber";
/** Observations of a running sensor are held back at most this long to sort
 * them with the other sensors' [s]. */
constexpr double MAX_REORDER_DELAY = 2.0;

/** The human part of an exception's text. Beyond shortExceptionMessage(),
 * drops the banner and backtrace lines MRPT adds when it re-throws an
 * exception without a "Message:" line (CGenericSensor::loadConfig() does).
 * MRPT 2.5.8 puts the re-thrown text after "Location:" (with an empty
 * "Message:") and drops its last character; that text is kept. */
std::string errorText(const std::exception& e)
{
    const std::string s = emslam::stereo::shortExceptionMessage(e);
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

[[noreturn]] void usageError(const std::string& msg)
{
    throw std::invalid_argument(
        "bad command line: " + msg + "; try " + std::string(PROGRAM) + " --help");
}

enum SensorState : int
{
    RUNNING = 0,
    ENDED = 1,
    FAILED = 2
};

/** One sensor and its grabbing thread. */
struct Slot
{
    std::string section, driver, label;
    mrpt::hwdrivers::CGenericSensor::Ptr sensor;
    std::thread thread;
    std::atomic<int> state{RUNNING};
    std::string error;  // set by the thread before it stores FAILED
    bool reported{false};
    bool has_last{false};
    mrpt::Clock::time_point last_ts{};
    std::size_t written{0};
};

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

/** Values that MRPT would misread in `[global]` and in the sections of
 * emslam's sensors (their parameter structs name the keys and kinds). */
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
    }
    requireWellFormedConfigValues(cfg, known);
}

/** `[global] rawlog_GZ_compress_level`, checked. */
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

/** One Slot per sensor section of `cfg` (created and configured, not yet
 * initialized). Throws naming the file, section and driver on errors. */
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
                "CDigiclopsStereoCamera, CSimulatedStereoCamera, CStereoImageFolderCamera)");
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

/** Opens every sensor's device; throws naming the section on the first failure. */
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

/** The grabbing session of one run(): sensors, pending observations, output. */
class Session
{
public:
    Session(GrabberApp& app, std::vector<std::unique_ptr<Slot>>& slots, io::RawlogOutput& out)
        : m_app(app), m_slots(slots), m_out(out)
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
        ++m_app.objects_written;
        ++m_slots[slot]->written;
        if (is_stereo)
        {
            ++m_app.frames_written;
            if (m_viewer && m_viewer->wantsSnapshot())
            {
                LiveViewSnapshot snap;
                snap.image = dynamic_cast<mrpt::obs::CObservationStereoImages&>(obj).imageLeft;
                snap.status = "stereo frames written: " + std::to_string(m_app.frames_written);
                m_viewer->push(std::move(snap));
            }
            if (m_app.max_frames && m_app.frames_written >= *m_app.max_frames)
            {
                m_limit_reached = true;
                m_cutoff = ts;
            }
        }
    }

    GrabberApp& m_app;
    std::vector<std::unique_ptr<Slot>>& m_slots;
    io::RawlogOutput& m_out;
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
        const auto bytes = fs::file_size(partial_file, ec);
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

}  // namespace

void GrabberApp::requestStop()
{
    StopSignal::request();
}

void GrabberApp::checkConfig(const mrpt::config::CConfigFileBase& params)
{
    requireWellFormedValues(params);
    (void)gzLevel(params);
    (void)createSensors(params, "INI");
}

void GrabberApp::initialize(int argc, char** argv)
{
    initialize(argc, const_cast<const char**>(argv));
}

void GrabberApp::initialize(int argc, const char** argv)
{
    TCLAP::CmdLine cmd(
        "Records stereo cameras (CDigiclopsStereoCamera, CSimulatedStereoCamera, "
        "CStereoImageFolderCamera) and stock MRPT sensors of a rawlog-grabber INI file into one "
        "gz-compressed rawlog, every observation in timestamp order. Stops on SIGINT/SIGTERM, "
        "after --frames stereo frames or --seconds, or when every sensor has stopped. Example: "
        "'" +
            std::string(PROGRAM) + " config/grabber/simulated.ini -o sim.rawlog --frames 30'.",
        ' ', std::string("emslam-grabber (") + mrpt::system::MRPT_getVersion() + ")");
    // A multi-arg: an optional UnlabeledValueArg sets a process-wide TCLAP flag
    // that makes every later command line with an unlabeled argument fail.
    TCLAP::UnlabeledMultiArg<std::string> arg_cfg(
        "config", "Sensor INI file (rawlog-grabber format).", false, "CONFIG.ini", cmd);
    TCLAP::ValueArg<std::string> arg_out(
        "o", "output", "Output rawlog (default: <[global] rawlog_prefix>.rawlog).", false, "",
        "OUT.rawlog", cmd);
    TCLAP::ValueArg<long long> arg_frames(
        "", "frames", "Stop after N stereo frames (CObservationStereoImages) were written.", false,
        0, "N", cmd);
    TCLAP::ValueArg<double> arg_seconds(
        "", "seconds", "Stop after S seconds.", false, 0.0, "S", cmd);
    TCLAP::SwitchArg arg_list(
        "", "list-devices",
        "List the IEEE-1394 / USB cameras (libdc1394) and USB devices (libusb), then exit.", cmd,
        false);
    TCLAP::SwitchArg arg_quiet("q", "quiet", "No status line or summary.", cmd, false);
    TCLAP::SwitchArg arg_viewer(
        "", "viewer", "Show the left images live in a window (no display: a warning).", cmd, false);

    quit_requested = false;
    if (!parseCommandLine(cmd, PROGRAM, argc, argv))
    {
        quit_requested = true;
        return;
    }
    list_devices = arg_list.getValue();
    quiet = arg_quiet.getValue();
    viewer = arg_viewer.getValue();
    config_file = arg_cfg.getValue().empty() ? std::string() : arg_cfg.getValue().front();
    output_file = arg_out.getValue();
    max_frames.reset();
    max_seconds.reset();
    if (list_devices)
    {
        return;
    }
    if (arg_cfg.getValue().size() > 1)
    {
        usageError("expected one CONFIG.ini, got " + std::to_string(arg_cfg.getValue().size()));
    }
    if (config_file.empty())
    {
        usageError("a CONFIG.ini file is required (or --list-devices)");
    }
    if (arg_frames.isSet() && arg_seconds.isSet())
    {
        usageError("give --frames or --seconds, not both");
    }
    if (arg_frames.isSet())
    {
        if (arg_frames.getValue() < 1)
        {
            usageError("--frames must be >= 1");
        }
        max_frames = static_cast<std::size_t>(arg_frames.getValue());
    }
    if (arg_seconds.isSet())
    {
        if (!(arg_seconds.getValue() > 0))
        {
            usageError("--seconds must be > 0");
        }
        max_seconds = arg_seconds.getValue();
    }
    loadConfig(params, config_file, {});
}

void GrabberApp::run()
{
    if (quit_requested)
    {
        return;
    }
    const auto t_start = Clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t_start).count(); };
    if (list_devices)
    {
        device_listing = emslam::hwdrivers::listDevices().toText();
        if (!quiet)
        {
            std::cout << device_listing;
            std::cout.flush();
        }
        return;
    }
    frames_written = 0;
    objects_written = 0;
    sensors.clear();
    stop_reason.clear();
    output_bytes = 0;

    // Re-parse the text (a CConfigFileMemory written to reads back defaults otherwise).
    const mrpt::config::CConfigFileMemory cfg(params.getContent());
    const std::string prefix = cfg.read_string("global", "rawlog_prefix", "dataset");
    int gz_level = 1;
    try
    {
        requireWellFormedValues(cfg);
        gz_level = gzLevel(cfg);
    }
    catch (const std::invalid_argument& e)
    {
        throw std::invalid_argument("'" + config_file + "': " + e.what());
    }
    const std::string out_file = output_file.empty() ? prefix + ".rawlog" : output_file;

    // Create, configure and initialize every sensor before anything is written.
    auto slots = createSensors(cfg, config_file);
    initializeSensors(slots);

    io::RawlogOutput::checkOutputFolders(out_file, {});
    io::RawlogOutput out(out_file, gz_level);
    const std::string partial = out.partialFile();
    if (!quiet)
    {
        std::cerr << PROGRAM << ": grabbing " << slots.size() << " sensor(s) into '" << out_file
                  << "'";
        if (max_frames)
        {
            std::cerr << " until " << *max_frames << " stereo frames";
        }
        if (max_seconds)
        {
            std::cerr << " for " << *max_seconds << " s";
        }
        std::cerr << " (Ctrl+C stops)\n";
    }

    StopSignal::clear();
    const StopSignalGuard signals;
    std::atomic<bool> stop_threads{false};
    for (auto& s : slots)
    {
        Slot& slot = *s;
        slot.thread = std::thread([&slot, &stop_threads] { sensorThread(slot, stop_threads); });
    }
    auto joinAll = [&]
    {
        stop_threads.store(true);
        for (auto& s : slots)
        {
            if (s->thread.joinable())
            {
                s->thread.join();
            }
        }
    };

    Session session(*this, slots, out);
    std::unique_ptr<LiveViewer> live;
    if (viewer)
    {
        live = std::make_unique<LiveViewer>(LiveViewer::Options{PROGRAM});
        session.setViewer(live.get());
    }
    StatusLine status(!quiet);
    auto reportEnds = [&]
    {
        for (auto& s : slots)
        {
            const int st = s->state.load();
            if (st == RUNNING || s->reported)
            {
                continue;
            }
            s->reported = true;
            if (st == FAILED)
            {
                status.finish();
                std::cerr << PROGRAM << ": sensor [" << s->section << "] '" << s->label
                          << "' failed and was stopped (the others go on): " << s->error << "\n";
            }
            else if (!quiet)
            {
                status.finish();
                std::cerr << PROGRAM << ": sensor [" << s->section << "] '" << s->label
                          << "' reached the end of its stream\n";
            }
        }
    };

    std::string write_error;
    try
    {
        while (true)
        {
            const auto states = session.collect();
            session.write(states, false);
            reportEnds();
            if (session.frameLimitReached())
            {
                stop_reason = std::to_string(*max_frames) + " stereo frames written";
                break;
            }
            if (StopSignal::requested())
            {
                stop_reason = "interrupted by a signal";
                break;
            }
            if (max_seconds && elapsed() >= *max_seconds)
            {
                stop_reason = mrpt::format("%g s elapsed", *max_seconds);
                break;
            }
            if (std::all_of(states.begin(), states.end(), [](int st) { return st != RUNNING; }))
            {
                stop_reason = "every sensor stopped";
                break;
            }
            status.update(slots, elapsed(), partial);
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        joinAll();
        const auto states = session.collect();
        session.write(states, true);
        reportEnds();
    }
    catch (const std::exception& e)
    {
        write_error = errorText(e);
        stop_reason = "writing failed";
        joinAll();
    }
    status.update(slots, elapsed(), partial, true);
    status.finish();
    out.commit();

    std::error_code ec;
    output_bytes = fs::file_size(out_file, ec);
    elapsed_seconds = elapsed();
    std::size_t failed = 0;
    for (const auto& s : slots)
    {
        SensorResult r;
        r.section = s->section;
        r.driver = s->driver;
        r.written = s->written;
        if (const auto* st = dynamic_cast<const emslam::hwdrivers::SensorStatus*>(s->sensor.get()))
        {
            r.dropped = st->droppedFrames();
        }
        r.ended = s->state.load() == ENDED;
        r.failed = s->state.load() == FAILED;
        r.error = s->error;
        failed += r.failed ? 1 : 0;
        sensors.push_back(r);
    }
    if (!write_error.empty())
    {
        throw std::runtime_error(
            "writing '" + out_file + "' failed (disk full?): " + write_error +
            "; the rawlog keeps the " + std::to_string(objects_written) +
            " observations written before (readable up to its last complete record)");
    }
    if (!quiet)
    {
        std::cout << PROGRAM << ": " << stop_reason << "; wrote " << objects_written
                  << " observations (" << frames_written << " stereo frames, "
                  << megabytes(output_bytes) << ") to '" << out_file << "' in "
                  << mrpt::format("%.1f s", elapsed_seconds) << "\n";
        std::cout.flush();
    }
    if (failed == slots.size())
    {
        throw std::runtime_error(
            "every sensor failed (first: [" + slots.front()->section + "] " + slots.front()->error +
            "); '" + out_file + "' keeps the " + std::to_string(objects_written) +
            " observations recorded");
    }
}

}  // namespace emslam::apps
