// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/App.h>
#include <emslam/apps/DegenerateRun.h>
#include <emslam/apps/MapperOutputs.h>
#include <emslam/apps/ProgressLine.h>
#include <emslam/io/DatasetSequence.h>
#include <emslam/io/FrameStreamGuard.h>
#include <emslam/io/TrajectoryReader.h>
#include <emslam/io/TrajectoryWriter.h>
#include <emslam/slam/EntropySlam.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <chrono>
#include <memory>
#include <string>

namespace emslam::io
{
class ObservationSource;
}  // namespace emslam::io

namespace emslam::apps
{
/** `emslam-mapper`: the main job. Streams a rawlog, or a KITTI / EuRoC /
 * TUM RGB-D folder (io::DatasetFolder, read by io::DatasetReadAhead), through
 * emslam::slam::EntropySlam (stereo → egomotion → space sampling → global
 * rectification → compression, loop closing beside it) and writes, to the
 * output folder: `trajectory_egomotion.tum`, `trajectory_slam.tum`,
 * `trajectory_online.tum` (a pose for every frame; or / and the KITTI
 * `*_kitti.txt` + `*_times.txt`, `--trajectory-format`), `keyframes.txt`,
 * `loop_closures.txt`, `map.ply`, `map.3Dscene`, `map_top.png`,
 * `map_grid.gridmap`, `map_grid.png`, `entropy_map.bin`,
 * `entropy_map.3Dscene`, `stats.csv`, `summary.json`, `effective.ini` and
 * `report.html` (and `energy_scan.csv` with `--energy-scan`).
 *
 * \code
 * emslam-mapper CONFIG DATASET --out DIR [--egomotion-only]
 * emslam-mapper -c CONFIG DATASET --out DIR ...
 *   [--gt GT [--gt-format auto|tum|kitti|euroc] [--gt-times TIMES]]
 *   [--trajectory-format tum|kitti|both] [--set SECTION.key=value ...]
 *   [--max-frames N] [--energy-scan] [--quiet] [--viewer]
 * \endcode
 * - CONFIG is an INI file or the name of a shipped one (`kitti`,
 *   `kitti.ini`: findConfigFile()); DATASET a rawlog or a dataset folder,
 *   whose ground truth, when it has one, is used as `--gt` would be.
 * - `--energy-scan` (needs `--gt`): the entropy of the final trajectory's
 *   observations scanned around the ground truth along each dimension of a
 *   few actions (emslam::rectify::scanEnergy()): `energy_scan.csv` and an
 *   `energy_scan` object in summary.json.
 * - `--viewer` shows the run live (LiveViewer); without a display it warns
 *   and the run goes on.
 * - The configuration is checked before any work: an unknown section or key
 *   (with the closest valid name), or a bad value, stops the run.
 * - Ctrl-C (SIGINT) or SIGTERM stops after the current frame; every output
 *   is still written for the frames processed so far.
 * - A rawlog cut in the middle of a record (or with a corrupt record) is
 *   processed up to its last complete record, with a warning.
 * - A frame whose timestamp is invalid or not after the last mapped one's,
 *   whose camera differs from the first mapped frame's, or that the stereo
 *   front-end cannot use (images of different sizes, missing or invalid
 *   calibration, empty images) is skipped with a warning naming its record
 *   (io::FrameStreamGuard), and counted in summary.json
 *   (`skipped_observations` and per cause, `skipped_reasons`,
 *   `camera_change`). Any other error stops the
 *   run: the outputs of the frames mapped before it are still written, then
 *   run() throws.
 * - Inputs and outputs are checked in initialize(): the rawlog and config
 *   must be regular files, `--out` a writable folder (or creatable), and no
 *   output in it may be a folder, device, FIFO or symbolic link. The folder
 *   is created only when the outputs are written.
 * \ingroup emslam_apps_grp \sa emslam::slam::EntropySlam */
class MapperApp : public App
{
public:
    MapperApp();

    /** The configuration check initialize() runs on the INI file plus the
     * `--set` overrides, before any input is read: every section of the mapper ([StereoMatcher]
     * [EgomotionEstimator] [EntropyVoxelMap] [SpaceSampler] [Rectifier] [EntropySlam]) must hold
     * only known keys, values of their kind (see requireValidConfig()) and values in their ranges
     * (the parameter structs' validate()). Throws std::invalid_argument naming the section, key and
     * value. */
    static void checkConfig(const mrpt::config::CConfigFileBase& params);

    /** The mapper of the last run() (results stay readable). */
    const slam::EntropySlam& mapper() const { return *m_mapper; }
    /** What the last run() added to the mapper's results. */
    const MapperRunInfo& runInfo() const { return m_info; }

    /** Why the last run()'s result is degenerate (see degenerateRunWarning()),
     * or "" if it is usable. */
    const std::string& degenerateResult() const { return m_degenerate; }
    /** The process exit code of a run() that returned: 0, or
     * EXIT_DEGENERATE when degenerateResult() is not empty. */
    int exitCode() const { return m_degenerate.empty() ? 0 : EXIT_DEGENERATE; }

protected:
    bool parseArguments(int argc, const char** argv) override;
    /** Maps the rawlog and writes the outputs. Throws naming the file and the
     * cause on bad input (unreadable rawlog, no usable stereo / RGB-D
     * observation), or after writing the outputs when an error stopped the
     * mapping. */
    void execute() override;

private:
    /** Maps the input's frames until its end, a signal, --max-frames or an
     * error (m_info.stopped_by_error). */
    void mapInput(io::FrameStreamGuard& guard);
    /** One observation to the mapper; false if it did not take it (`stop`
     * set: an error ended the run). */
    bool mapObservation(
        const mrpt::obs::CObservation& o,
        std::size_t record,
        io::FrameStreamGuard& guard,
        ProgressLine& progress,
        bool& stop);
    /** An input that ended early: a warning, or an error to fail the run with. */
    void checkInputEnd(const io::ObservationSource& reader);
    /** Throws: no frame was mapped. */
    [[noreturn]] void failWithoutFrames(const io::FrameStreamGuard& guard) const;
    /** The mapper's finish() and every output. */
    void finishAndWrite(std::chrono::steady_clock::time_point t_start);
    void writeOutputs(const emslam::io::TumTrajectory& ground_truth);
    /** The run in a few lines on stdout (and unreliable-estimate warnings). */
    void printSummary(const emslam::io::TumTrajectory& ground_truth) const;
    /** Prints a skipped frame's warning (none once its cause was named often enough). */
    void warnSkipped(const std::string& warning, ProgressLine& progress);
    /** Copies what `guard` skipped into the run info. */
    void recordSkips(const io::FrameStreamGuard& guard);
    /** parseCommandLine() after `-c NAME` / `--config NAME` is moved to
     * where the positional `config` stands (configOptionFirst()). */
    bool parseConfigFirst(
        TCLAP::CmdLine& cmd,
        const TCLAP::Arg& config,
        const TCLAP::Arg& dataset,
        int argc,
        const char** argv);
    /** The input, outputs and ground truth, checked before any long work. */
    void checkInputsAndOutputs();
    /** Checks the input: a rawlog file, or a dataset folder (opened, into
     * m_sequence). */
    void openInput();

    std::string m_degenerate;
    bool m_viewer{false};
    bool m_egomotion_only{false};
    bool m_energy_scan{false};
    std::string m_config, m_rawlog, m_out, m_gt;
    /** The input as messages name it: "rawlog 'FILE'", "KITTI odometry folder 'DIR'". */
    std::string m_input_name;
    /** The dataset folder when the input is one (else a rawlog). */
    std::shared_ptr<io::DatasetSequence> m_sequence;
    emslam::io::TrajectoryReadOptions m_gt_options;
    emslam::io::LoadedTrajectory m_ground_truth;
    emslam::io::TrajectoryOutput m_trajectory_output{emslam::io::TrajectoryOutput::Tum};
    std::unique_ptr<slam::EntropySlam> m_mapper;
    MapperRunInfo m_info;
    /** --load-session (read before any long work), --localize, --save-session. */
    ///@{
    std::string m_load_session, m_save_session;
    bool m_localize{false};
    slam::CMapSession::Ptr m_session;
    ///@}
    /** Writes --save-session (after every other output). */
    void saveSession();
};

}  // namespace emslam::apps
