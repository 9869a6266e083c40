// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/App.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace emslam::apps
{
/** The capture app behind `emslam-grabber`: runs every sensor of a
 * rawlog-grabber-style INI file (emslam's CDigiclopsStereoCamera,
 * CSimulatedStereoCamera, CStereoImageFolderCamera and any stock MRPT sensor,
 * e.g. an IMU) each in its own thread at its `process_rate`, and saves every
 * observation they deliver, in timestamp order, to one gz-compressed,
 * observations-only rawlog with a fixed name.
 *
 * \code
 * emslam-grabber CONFIG.ini [-o OUT.rawlog] [--frames N | --seconds S] [--quiet] [--viewer]
 * emslam-grabber --list-devices
 * \endcode
 *
 * Differences from the stock `rawlog-grabber` (same INI, same sensors):
 * - it never reads standard input (runs under CI, nohup, systemd);
 * - every observation is written, including the last ones of a sensor that
 *   ends or fails (the stock loop writes only half of its queue per period);
 * - the output name is fixed (`-o`, default `<rawlog_prefix>.rawlog`), written
 *   as `OUT.partial` and renamed when the run ends;
 * - a sensor that ends (EndOfStream) or throws is stopped and logged, the
 *   others go on; the run ends when all have stopped, after `--frames`
 *   stereo frames or `--seconds`, or on SIGINT / SIGTERM, and the rawlog is
 *   always closed properly (exit code 0). It fails (exit code 1, rawlog kept)
 *   only if every sensor failed or writing failed (e.g. a full disk: the
 *   rawlog keeps the records written before).
 *
 * INI: `[global]` keys `rawlog_prefix` (default "dataset") and
 * `rawlog_GZ_compress_level` (0..9, default 1), as the stock grabber; every
 * other section with a `driver` key is a sensor, unless it has
 * `rawlog-grabber-ignore = true`. Sections without `driver` (calibration,
 * [StereoMatcher]) are ignored.
 * \ingroup emslam_apps_grp \sa doc/apps/emslam-grabber.md */
class GrabberApp : public App
{
public:
    GrabberApp();

    /** Asks a running run() to stop, as SIGINT does (thread- and signal-safe). */
    static void requestStop();

    /** The check run() makes of the INI before opening any device: `[global]`
     * and the sections of emslam's sensors hold values of their keys' kind
     * (requireValidConfig()), and every sensor section loads (every
     * parameter in its range). Throws std::exception naming the section and
     * key. */
    static void checkConfig(const mrpt::config::CConfigFileBase& params);

    /** \name Settings (filled by initialize(); may be edited before run())
     * @{ */
    /** INI file name (for messages). */
    std::string config_file;
    /** Output rawlog; empty: `<rawlog_prefix>.rawlog`. */
    std::string output_file;
    /** Stop after this many `CObservationStereoImages` were written. */
    std::optional<std::size_t> max_frames;
    /** Stop after this much wall-clock time [s]. */
    std::optional<double> max_seconds;
    /** Only list the IEEE-1394 / USB devices. */
    bool list_devices{false};
    /** No status line or summary. */
    bool quiet{false};
    /** Show the left image of the stereo frames live (LiveViewer). */
    bool viewer{false};
    /** @} */

    /** Per-sensor results. */
    struct SensorResult
    {
        std::string section;     //!< INI section
        std::string driver;      //!< class name
        std::size_t written{0};  //!< observations written to the rawlog
        std::size_t dropped{0};  //!< frames the sensor reported as dropped
        bool ended{false};       //!< finished its stream (EndOfStream)
        bool failed{false};      //!< threw; see error
        std::string error;       //!< the failure, if any
    };

    /** \name Results
     * @{ */
    std::string device_listing;         //!< `--list-devices` output
    std::size_t frames_written{0};      //!< CObservationStereoImages written
    std::size_t objects_written{0};     //!< all observations written
    std::vector<SensorResult> sensors;  //!< one per sensor section, INI order
    std::string stop_reason;            //!< why grabbing ended
    std::uintmax_t output_bytes{0};     //!< size of the rawlog [bytes]
    double elapsed_seconds{0.0};        //!< wall-clock time of run() [s]
    /** @} */
protected:
    bool parseArguments(int argc, const char** argv) override;
    /** Lists devices (`--list-devices`) or grabs until a stop condition.
     * Throws on configuration or sensor-initialisation errors (no output is
     * left), and, after committing the rawlog, if every sensor failed or
     * writing failed. */
    void execute() override;
};

}  // namespace emslam::apps
