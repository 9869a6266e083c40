// SPDX-License-Identifier: BSD-3-Clause
// Private to emslam_apps (not installed): the sensors of emslam-grabber, each
// on its own thread, and the checks of its configuration file.
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/Clock.h>
#include <mrpt/hwdrivers/CGenericSensor.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace emslam::apps::grabber
{
constexpr const char* PROGRAM = "emslam-grabber";

/** The human part of an exception's text (see GrabberSensors.cpp). */
std::string errorText(const std::exception& e);

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

/** The loop of a sensor's thread: doProcess() at its process_rate until
 * `stop`; the end of a replayed source (EndOfStream) sets ENDED, any other
 * exception FAILED with the error text. */
void sensorThread(Slot& s, const std::atomic<bool>& stop);

/** "12.3 MB". */
std::string megabytes(std::uintmax_t b);

/** Values that MRPT would misread in `[global]` and in the sections of
 * emslam's sensors (their parameter structs name the keys and kinds). */
void requireWellFormedValues(const mrpt::config::CConfigFileBase& cfg);

/** `[global] rawlog_GZ_compress_level`, checked. */
int gzLevel(const mrpt::config::CConfigFileBase& cfg);

/** One Slot per sensor section of `cfg` (created and configured, not yet
 * initialized). Throws naming the file, section and driver on errors. */
std::vector<std::unique_ptr<Slot>> createSensors(
    const mrpt::config::CConfigFileBase& cfg, const std::string& config_file);

/** initialize() of every sensor; throws naming the one that failed. */
void initializeSensors(std::vector<std::unique_ptr<Slot>>& slots);

}  // namespace emslam::apps::grabber
