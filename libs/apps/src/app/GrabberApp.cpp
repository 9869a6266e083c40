// SPDX-License-Identifier: BSD-3-Clause
#include "GrabberSession.h"

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
#include <emslam/io/InputOutputClash.h>
#include <emslam/io/RawlogOutput.h>
#include <emslam/stereo/StereoMatcher.h>
#include <emslam/util/ExceptionMessage.h>

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
using namespace grabber;

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

GrabberApp::GrabberApp() : App(PROGRAM) {}

bool GrabberApp::parseArguments(int argc, const char** argv)
{
    TCLAP::CmdLine cmd(
        "Records stereo cameras (CDigiclopsStereoCamera, CSimulatedStereoCamera, "
        "CStereoImageFolderCamera, CVideoStereoCamera) and stock MRPT sensors of a rawlog-grabber "
        "INI file into one "
        "gz-compressed rawlog, every observation in timestamp order. Stops on SIGINT/SIGTERM, "
        "after --max-frames stereo frames or --seconds, or when every sensor has stopped. Example: "
        "'" +
            std::string(PROGRAM) + " config/grabber/simulated.ini -o sim.rawlog --max-frames 30'.",
        ' ', std::string("emslam-grabber (") + mrpt::system::MRPT_getVersion() + ")");
    // A multi-arg: an optional UnlabeledValueArg sets a process-wide TCLAP flag
    // that makes every later command line with an unlabeled argument fail.
    TCLAP::UnlabeledMultiArg<std::string> arg_cfg(
        "config", "Sensor INI file (rawlog-grabber format).", false, "CONFIG.ini", cmd);
    TCLAP::ValueArg<std::string> arg_out(
        "o", "output", "Output rawlog (default: <[global] rawlog_prefix>.rawlog).", false, "",
        "OUT.rawlog", cmd);
    TCLAP::ValueArg<long long> arg_frames(
        "", "max-frames",
        "Stop after N stereo frames (CObservationStereoImages) were written (default 0: no "
        "limit).",
        false, 0, "N", cmd);
    TCLAP::ValueArg<double> arg_seconds(
        "", "seconds", "Stop after S seconds.", false, 0.0, "S", cmd);
    TCLAP::SwitchArg arg_list(
        "", "list-devices",
        "List the IEEE-1394 / USB cameras (libdc1394), USB devices (libusb) and V4L2 video "
        "devices, then exit.",
        cmd, false);
    TCLAP::SwitchArg arg_quiet("q", "quiet", "No status line or summary.", cmd, false);
    TCLAP::SwitchArg arg_viewer(
        "", "viewer", "Show the left images live in a window (no display: a warning).", cmd, false);
    if (!parseCommandLine(cmd, argc, argv, {{"--frames", "--max-frames", 0, "N"}}))
    {
        return false;
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
        return true;
    }
    if (arg_cfg.getValue().size() > 1)
    {
        usageError("expected one CONFIG.ini, got " + std::to_string(arg_cfg.getValue().size()));
    }
    if (config_file.empty())
    {
        usageError("a CONFIG.ini file is required (or --list-devices)");
    }
    if (countOption(arg_frames.getValue(), "--max-frames", 0, PROGRAM) > 0)
    {
        if (arg_seconds.isSet())
        {
            usageError("give --max-frames or --seconds, not both");
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
    return true;
}

namespace
{
using Slots = std::vector<std::unique_ptr<Slot>>;

double secondsSince(Clock::time_point t0)
{
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

/** Stops the sensor threads and waits for them. */
void joinAll(Slots& slots, std::atomic<bool>& stop_threads)
{
    stop_threads.store(true);
    for (auto& s : slots)
    {
        if (s->thread.joinable())
        {
            s->thread.join();
        }
    }
}

/** Tells once about each sensor that stopped (a failure even when quiet). */
void reportEnds(Slots& slots, StatusLine& status, bool quiet)
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
}

/** The results of each sensor; returns how many failed. */
std::size_t sensorResults(const Slots& slots, std::vector<GrabberApp::SensorResult>& sensors)
{
    std::size_t failed = 0;
    for (const auto& s : slots)
    {
        GrabberApp::SensorResult r;
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
    return failed;
}

/** Runs the sensor threads and writes their observations in time order
 * until a stop condition (app.stop_reason); returns the write error, if
 * writing failed. Shows the stereo frames in `live`, if any. */
std::string grabUntilStop(
    GrabberApp& app,
    Slots& slots,
    io::RawlogOutput& out,
    LiveViewer* live,
    Clock::time_point t_start)
{
    const std::string partial = out.partialFile();
    std::atomic<bool> stop_threads{false};
    for (auto& s : slots)
    {
        Slot& slot = *s;
        slot.thread = std::thread([&slot, &stop_threads] { sensorThread(slot, stop_threads); });
    }
    Session session(slots, out, app.max_frames);
    if (live != nullptr)
    {
        session.setViewer(live);
    }
    StatusLine status(!app.quiet);
    std::string write_error;
    try
    {
        while (true)
        {
            const auto states = session.collect();
            session.write(states, false);
            reportEnds(slots, status, app.quiet);
            if (session.frameLimitReached())
            {
                app.stop_reason = std::to_string(*app.max_frames) + " stereo frames written";
                break;
            }
            if (StopSignal::requested())
            {
                app.stop_reason = "interrupted by a signal";
                break;
            }
            if (app.max_seconds && secondsSince(t_start) >= *app.max_seconds)
            {
                app.stop_reason = mrpt::format("%g s elapsed", *app.max_seconds);
                break;
            }
            if (std::all_of(states.begin(), states.end(), [](int st) { return st != RUNNING; }))
            {
                app.stop_reason = "every sensor stopped";
                break;
            }
            status.update(slots, secondsSince(t_start), partial);
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        joinAll(slots, stop_threads);
        const auto states = session.collect();
        session.write(states, true);
        reportEnds(slots, status, app.quiet);
    }
    catch (const std::exception& e)
    {
        write_error = errorText(e);
        app.stop_reason = "writing failed";
        joinAll(slots, stop_threads);
    }
    app.frames_written = session.framesWritten();
    app.objects_written = session.objectsWritten();
    status.update(slots, secondsSince(t_start), partial, true);
    status.finish();
    return write_error;
}
/** The INI's values checked ([global] and emslam's sensor sections);
 * returns its gz level. Errors name the file. */
int checkedGzLevel(const mrpt::config::CConfigFileBase& cfg, const std::string& config_file)
{
    try
    {
        requireWellFormedValues(cfg);
        return gzLevel(cfg);
    }
    catch (const std::invalid_argument& e)
    {
        throw std::invalid_argument("'" + config_file + "': " + e.what());
    }
}

/** What is grabbed into what, until when. */
void announce(const GrabberApp& app, std::size_t sensors, const std::string& out_file)
{
    std::cerr << PROGRAM << ": grabbing " << sensors << " sensor(s) into '" << out_file << "'";
    if (app.max_frames)
    {
        std::cerr << " until " << *app.max_frames << " stereo frames";
    }
    if (app.max_seconds)
    {
        std::cerr << " for " << *app.max_seconds << " s";
    }
    std::cerr << " (Ctrl+C stops)\n";
}
/** Commits the rawlog; if the last compressed block does not fit (a full
 * disk), keeps the rest and sets the first write error. */
void commitOutput(io::RawlogOutput& out, std::string& write_error, std::string& stop_reason)
{
    try
    {
        out.commit();
    }
    catch (const std::exception& e)
    {
        if (write_error.empty())
        {
            write_error = errorText(e);
            stop_reason = "writing failed";
        }
        out.keepWhatWasWritten();
    }
}
}  // namespace

void GrabberApp::execute()
{
    const auto t_start = Clock::now();
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
    const int gz_level = checkedGzLevel(cfg, config_file);
    const std::string out_file = output_file.empty() ? prefix + ".rawlog" : output_file;

    io::requireOutputsAreNotInputs(
        {{"output rawlog", out_file}}, {{"the config file", config_file}});
    // Create, configure and initialize every sensor before anything is written.
    auto slots = createSensors(cfg, config_file);
    initializeSensors(slots);

    io::RawlogOutput::checkOutputFolders(out_file, {});
    io::RawlogOutput out(out_file, gz_level);
    if (!quiet)
    {
        announce(*this, slots.size(), out_file);
    }
    StopSignal::clear();
    const StopSignalGuard signals;
    std::unique_ptr<LiveViewer> live;
    if (viewer)
    {
        live = std::make_unique<LiveViewer>(LiveViewer::Options{PROGRAM});
    }
    std::string write_error = grabUntilStop(*this, slots, out, live.get(), t_start);
    commitOutput(out, write_error, stop_reason);

    std::error_code ec;
    output_bytes = fs::file_size(out_file, ec);
    elapsed_seconds = secondsSince(t_start);
    const std::size_t failed = sensorResults(slots, sensors);
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
