// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>
#include <emslam/apps/ConfigLookup.h>
#include <emslam/apps/ConfigValidation.h>
#include <emslam/apps/EnergyScanOutputs.h>
#include <emslam/apps/MapperApp.h>
#include <emslam/apps/MapperLiveFeed.h>
#include <emslam/apps/MapperReport.h>
#include <emslam/apps/PlyFile.h>
#include <emslam/apps/ProgressLine.h>
#include <emslam/apps/StopSignal.h>
#include <emslam/io/AtomicTextFile.h>
#include <emslam/io/DatasetFolder.h>
#include <emslam/io/DatasetReadAhead.h>
#include <emslam/io/FrameStreamGuard.h>
#include <emslam/io/InputFileChecks.h>
#include <emslam/io/InputOutputClash.h>
#include <emslam/io/OutputPathChecks.h>
#include <emslam/io/RawlogInput.h>
#include <emslam/io/RawlogReadAhead.h>
#include <emslam/io/TrajectoryInput.h>
#include <emslam/io/TrajectoryWriter.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/core/bits_math.h>
#include <mrpt/core/format.h>
#include <mrpt/poses/CPose3DQuat.h>
#include <mrpt/system/filesystem.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace emslam::apps
{
namespace
{
constexpr const char* PROGRAM = "emslam-mapper";

std::string joinPath(const std::string& dir, const std::string& name)
{
    return dir + "/" + name;
}

/** Every file the mapper may write into its output folder. */
const std::vector<std::string>& outputNames()
{
    static const std::vector<std::string> names = {
        "trajectory_egomotion.tum",
        "trajectory_slam.tum",
        "trajectory_online.tum",
        "trajectory_egomotion_kitti.txt",
        "trajectory_slam_kitti.txt",
        "trajectory_online_kitti.txt",
        "trajectory_egomotion_times.txt",
        "trajectory_slam_times.txt",
        "trajectory_online_times.txt",
        "keyframes.txt",
        "loop_closures.txt",
        "map.ply",
        "map.3Dscene",
        "map_top.png",
        "map_grid.gridmap",
        "map_grid.png",
        "map.bt",
        "entropy_map.bin",
        "entropy_map.3Dscene",
        "stats.csv",
        "summary.json",
        "effective.ini",
        "report.html",
        "energy_scan.csv"};
    return names;
}

/** The arguments (without the program name) with `-c NAME`, `--config NAME`
 * or `--config=NAME` taken out and NAME put first, where the positional
 * CONFIG stands; `moved` says whether one was. Throws when the option lacks
 * its value or is given twice. */
std::vector<std::string> configOptionFirst(const std::vector<std::string>& args, bool& moved)
{
    std::vector<std::string> out;
    std::vector<std::string> names;
    for (std::size_t i = 0; i < args.size(); ++i)
    {
        const std::string& a = args[i];
        if (a == "--")
        {
            out.insert(out.end(), args.begin() + static_cast<std::ptrdiff_t>(i), args.end());
            break;
        }
        const bool inline_value = a.rfind("--config=", 0) == 0;
        if (inline_value || a == "-c" || a == "--config")
        {
            const std::string name =
                inline_value ? a.substr(9) : (i + 1 < args.size() ? args[++i] : std::string());
            if (name.empty())
            {
                usageError(PROGRAM, a + " needs a value (a config name such as kitti, or a file)");
            }
            names.push_back(name);
        }
        else
        {
            out.push_back(a);
        }
    }
    if (names.size() > 1)
    {
        usageError(PROGRAM, "-c / --config given " + std::to_string(names.size()) + " times");
    }
    moved = !names.empty();
    if (moved)
    {
        out.insert(out.begin(), names.front());
    }
    return out;
}

/** The mapper's input read ahead: a dataset folder's frames, or a rawlog's
 * records (the rawlog outlives its reader). */
struct InputReader
{
    InputReader(
        const std::shared_ptr<io::DatasetSequence>& sequence, const std::string& rawlog_file)
    {
        if (sequence)
        {
            source = std::make_unique<io::DatasetReadAhead>(*sequence);
            return;
        }
        rawlog = std::make_unique<io::RawlogInput>(rawlog_file);
        source = std::make_unique<io::RawlogReadAhead>(*rawlog);
    }
    std::unique_ptr<io::RawlogInput> rawlog;
    std::unique_ptr<io::ObservationSource> source;
};

void writeEffectiveIni(const slam::EntropySlam::TParameters& p, const std::string& file)
{
    mrpt::config::CConfigFileMemory cfg;
    p.saveToConfigFile(cfg);
    io::AtomicTextFile f(file);
    f.stream() << "# emslam-mapper: every parameter this run used (load it with emslam-mapper to "
                  "repeat the run)\n"
               << cfg.getContent();
    f.commit();
}

/** The progress line's energy (none before the first rectification gives
 * one), and UNRELIABLE once the run is (EntropySlam::unreliableReasons()). */
std::string energyText(const slam::EntropySlam& m)
{
    // A run found unreliable says so as soon as it is known.
    const std::string unreliable = m.unreliableReasons().empty() ? "" : "UNRELIABLE";
    if (!m.hasEnergy())
    {
        return unreliable;
    }
    char buf[48];
    std::snprintf(buf, sizeof(buf), "energy %.4f", m.currentEnergy());
    return unreliable.empty() ? std::string(buf) : std::string(buf) + ", " + unreliable;
}

/** keyframes.txt: the frames space sampling accepted (rectified), one per line. */
void writeKeyframes(const slam::EntropySlam& m, const std::string& file)
{
    io::AtomicTextFile f(file);
    f.stream() << "# keyframes (accepted frames, rectified): frame_index timestamp; frame_index "
                  "is the line of trajectory_slam.tum from 0\n";
    const auto& frames = m.frames();
    for (const auto i : m.keyframes())
    {
        f.stream() << i << ' ' << emslam::io::formatTimestamp(frames[i].timestamp) << '\n';
    }
    f.commit();
}
/** loop_closures.txt: the loop edges [LoopCloser] accepted, one per line. */
void writeLoopClosures(const slam::EntropySlam& m, const std::string& file)
{
    io::AtomicTextFile f(file);
    f.stream() << "# loop closures: frame_from frame_to x y z qx qy qz qw matches; the pose of "
                  "frame_to in frame_from as the egomotion registered it [m], frame indices are "
                  "lines of trajectory_slam.tum from 0\n";
    for (const auto& e : m.loopCloser().loopEdges())
    {
        if (e.frame_from >= m.frames().size() || e.frame_to >= m.frames().size())
        {
            continue;  // --localize: an edge to the session's map, not a line of the trajectory
        }
        const mrpt::poses::CPose3DQuat q(e.measurement);
        f.stream() << e.frame_from << ' ' << e.frame_to << ' ' << q.x() << ' ' << q.y() << ' '
                   << q.z() << ' ' << q.quat().x() << ' ' << q.quat().y() << ' ' << q.quat().z()
                   << ' ' << q.quat().r() << ' ' << e.matches << '\n';
    }
    f.commit();
}
}  // namespace

MapperApp::MapperApp() : App(PROGRAM) {}

bool MapperApp::parseArguments(int argc, const char** argv)
{
    TCLAP::CmdLine cmd(
        "emslam-mapper: Entropy Minimization SLAM over a rawlog or a KITTI odometry, EuRoC MAV "
        "or TUM RGB-D folder (ground truth found in the folder is used as with --gt). Stereo "
        "(or RGB-D) observations go through the stereo front-end, egomotion (GLM features, "
        "log-polar "
        "matching, LWO, Dpp), space sampling and global rectification by entropy minimization; "
        "the trajectories, map, statistics and an HTML report are written to --out. Exit "
        "status: 0 ok; 1 error (an error that stops the mapping still writes the outputs of "
        "the frames before it); 3 degenerate result (more than half of the egomotion steps "
        "failed, or the map has no point: outputs written, with a warning); 130 / 143 "
        "interrupted by SIGINT / SIGTERM (outputs written).",
        ' ', "0.1");
    TCLAP::UnlabeledValueArg<std::string> config(
        "config_file",
        "INI file ([StereoMatcher] [EgomotionEstimator] [EntropyVoxelMap] [SpaceSampler] "
        "[Rectifier] [LoopCloser] "
        "[EntropySlam]), or the name of a shipped one (kitti, euroc, 6dof-structured, ...: see "
        "share/emslam/config/mapper); or give it as -c NAME",
        true, "", "CONFIG.ini", cmd);
    TCLAP::UnlabeledValueArg<std::string> rawlog(
        "rawlog",
        "Rawlog with CObservationStereoImages / CObservation3DRangeScan, or a KITTI odometry "
        "sequence, EuRoC MAV or TUM RGB-D folder",
        true, "", "DATASET.rawlog", cmd);
    // Taken out of the arguments before parsing (configOptionFirst()): listed
    // here for --help and the check of known options.
    TCLAP::ValueArg<std::string> config_option(
        "c", "config", "The config (a name or a file) instead of the first argument", false, "",
        "NAME", cmd);
    TCLAP::ValueArg<std::string> out(
        "o", "out", "Output folder (created if needed)", true, "", "DIR", cmd);
    TCLAP::SwitchArg egomotion_only(
        "", "egomotion-only",
        "No global rectification (same as --set EntropySlam.egomotion_only=true)", cmd);
    TCLAP::ValueArg<std::string> gt(
        "", "gt",
        "Ground truth for the report and summary.json: TUM, KITTI poses (+ times) or EuRoC CSV",
        false, "", "GT", cmd);
    TCLAP::ValueArg<std::string> gt_format(
        "", "gt-format",
        withDefault("Format of --gt: auto (from the content), tum, kitti or euroc", "auto"), false,
        "auto", "auto|tum|kitti|euroc", cmd);
    TCLAP::ValueArg<std::string> gt_times(
        "", "gt-times",
        "Times file of a KITTI --gt (default: found beside it, e.g. sequences/NN/times.txt for "
        "poses/NN.txt)",
        false, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> trajectory_format(
        "", "trajectory-format",
        withDefault(
            "Trajectory files: tum (trajectory_*.tum), kitti (trajectory_*_kitti.txt + "
            "trajectory_*_times.txt) or both",
            "tum"),
        false, "tum", "tum|kitti|both", cmd);
    addSetOption(cmd, "Override a parameter: SECTION.key=value");
    addMaxFramesOption(cmd, "Stop after N stereo / RGB-D frames (0: all)");
    TCLAP::SwitchArg energy_scan(
        "", "energy-scan",
        "With --gt: scan the entropy along each dimension of a few actions of the final "
        "trajectory around the ground truth (does the energy have its minimum at the truth?); "
        "writes energy_scan.csv and an energy_scan object in summary.json",
        cmd);
    addQuietOption(cmd, "No progress line");
    TCLAP::SwitchArg viewer(
        "", "viewer", "Show the run live in a window (map, trajectories, camera, image)", cmd);
    TCLAP::ValueArg<std::string> save_session(
        "", "save-session",
        "Write the session to FILE when the run ends (keyframes, their descriptions, the pose "
        "graph, the map clouds, the config), to continue it later or localize in it",
        false, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> load_session(
        "", "load-session",
        "Continue the session in FILE with this input: the run is located in the saved map by "
        "its look, loops close across both, and the results (and --save-session) hold both",
        false, "", "FILE", cmd);
    TCLAP::SwitchArg localize(
        "", "localize",
        "With --load-session: track the input in the saved map without changing it; the "
        "results hold this input's frames only, in the session's world",
        cmd);

    if (!parseConfigFirst(cmd, config, rawlog, argc, argv))
    {
        return false;
    }
    m_config = findConfigFile(config.getValue(), "mapper");
    m_rawlog = rawlog.getValue();
    m_out = out.getValue();
    m_gt = gt.getValue();
    m_energy_scan = energy_scan.getValue();
    if (m_energy_scan && m_gt.empty())
    {
        throw std::invalid_argument(
            "--energy-scan needs --gt: the scan is made around the ground truth");
    }
    try
    {
        m_gt_options.format = emslam::io::parseTrajectoryFormat(gt_format.getValue());
    }
    catch (const std::invalid_argument& e)
    {
        throw std::invalid_argument(std::string("--gt-format: ") + e.what());
    }
    m_gt_options.times_file = gt_times.getValue();
    try
    {
        m_trajectory_output = emslam::io::parseTrajectoryOutput(trajectory_format.getValue());
    }
    catch (const std::invalid_argument& e)
    {
        throw std::invalid_argument(std::string("--trajectory-format: ") + e.what());
    }
    m_egomotion_only = egomotion_only.getValue();
    m_viewer = viewer.getValue();
    m_load_session = load_session.getValue();
    m_save_session = save_session.getValue();
    m_localize = localize.getValue();
    if (m_localize && m_load_session.empty())
    {
        usageError("--localize needs --load-session FILE: the session to localize in");
    }
    if (m_localize && !m_save_session.empty())
    {
        usageError("--localize does not change the session: no --save-session with it");
    }
    loadParameters(m_config);

    // Everything a run needs is checked here, before any long work.
    checkConfig(params);
    checkInputsAndOutputs();
    return true;
}

bool MapperApp::parseConfigFirst(
    TCLAP::CmdLine& cmd,
    const TCLAP::Arg& config,
    const TCLAP::Arg& dataset,
    int argc,
    const char** argv)
{
    bool config_option_given = false;
    std::vector<std::string> args = configOptionFirst(
        std::vector<std::string>(argv + std::min(argc, 1), argv + std::max(argc, 0)),
        config_option_given);
    args.insert(args.begin(), PROGRAM);
    std::vector<const char*> c_args;
    for (const auto& a : args)
    {
        c_args.push_back(a.c_str());
    }
    try
    {
        return parseCommandLine(cmd, static_cast<int>(c_args.size()), c_args.data());
    }
    catch (const std::invalid_argument&)
    {
        if (config_option_given && config.isSet() && dataset.isSet())
        {
            usageError("give the config once: as -c NAME or as the first argument");
        }
        throw;
    }
}

void MapperApp::checkInputsAndOutputs()
{
    openInput();
    io::requireOutputFolder(m_out, "output folder");
    io::requireReplaceableFiles(m_out, outputNames());
    std::vector<io::RolePath> inputs{
        {"the config file", m_config},
        {"the rawlog", m_sequence ? std::string() : m_rawlog},
        {"the ground truth (--gt)", m_gt},
        {"the ground-truth times (--gt-times)", m_gt_options.times_file}};
    for (const auto& f : m_sequence ? m_sequence->inputFiles() : std::vector<std::string>())
    {
        inputs.push_back({"a file of the dataset", f});
    }
    inputs.push_back({"the session (--load-session)", m_load_session});
    auto outputs = io::filesOfOutputFolder(m_out, outputNames(), "output");
    if (!m_save_session.empty())
    {
        outputs.push_back({"the session (--save-session)", m_save_session});
    }
    io::requireOutputsAreNotInputs(outputs, inputs);
    m_session.reset();
    if (!m_load_session.empty())
    {
        // Read now: a bad session stops the run before the long work.
        io::requireInputFile(m_load_session, "session file");
        m_session = slam::CMapSession::load(m_load_session);
    }
    m_ground_truth = {};
    if (!m_gt.empty())
    {
        io::requireInputFile(m_gt, "ground-truth file");
        // Read now: a bad ground truth stops the run before the long work.
        m_ground_truth = io::loadTrajectoryInput(m_gt, "ground-truth", m_gt_options);
        io::requireTimes(m_ground_truth, m_gt, "ground truth", "--gt-times");
    }
    else if (m_sequence)
    {
        // The dataset's own ground truth, as emslam-import --gt-out writes it.
        m_ground_truth.trajectory = m_sequence->groundTruthTrajectory();
    }
}

void MapperApp::openInput()
{
    m_sequence.reset();
    if (!io::DatasetFolder::isFolder(m_rawlog))
    {
        io::requireInputFile(m_rawlog, "rawlog");
        m_input_name = "rawlog '" + m_rawlog + "'";
        return;
    }
    const auto folder = io::DatasetFolder::detect(m_rawlog);
    // Opened now: a bad folder stops the run before the long work.
    m_sequence = folder.open();
    m_input_name = folder.formatName() + " folder '" + folder.sequence_dir + "'";
    if (!quiet())
    {
        std::string gt = "no ground truth";
        if (!m_gt.empty())
        {
            gt = "ground truth from --gt";
        }
        else if (m_sequence->hasGroundTruth())
        {
            gt = "ground truth " + (folder.ground_truth_file.empty()
                                        ? std::string("from the folder")
                                        : "'" + folder.ground_truth_file + "'");
        }
        std::printf(
            "%s: %s, %zu frames, %s\n", PROGRAM, m_input_name.c_str(), m_sequence->size(),
            gt.c_str());
    }
}

void MapperApp::checkConfig(const mrpt::config::CConfigFileBase& params)
{
    mrpt::config::CConfigFileMemory known;
    slam::EntropySlam::TParameters().saveToConfigFile(known);
    requireValidConfig(params, known);
    slam::EntropySlam::TParameters p;
    p.loadFromConfigFile(params);
}

void MapperApp::execute()
{
    const auto t_start = std::chrono::steady_clock::now();
    m_degenerate.clear();
    slam::EntropySlam::TParameters p;
    p.loadFromConfigFile(params);
    p.mapper.egomotion_only = p.mapper.egomotion_only || m_egomotion_only;
    m_mapper = std::make_unique<slam::EntropySlam>(p);
    if (m_session)
    {
        m_mapper->continueSession(
            m_session, m_localize ? slam::EntropySlam::SessionUse::Localize
                                  : slam::EntropySlam::SessionUse::Continue);
    }
    // A signal during the loop closer's catching up or polish ends them.
    m_mapper->setStopCheck([] { return StopSignal::requested(); });
    m_info = {};
    m_info.rawlog = m_rawlog;
    m_info.config = m_config;
    m_info.session_loaded = m_load_session;
    m_info.session_saved = m_save_session;
    m_info.localized = m_localize;

    StopSignal::clear();
    const StopSignalGuard signals;
    // Frames with a bad timestamp or another camera never reach the mapper.
    io::FrameStreamGuard guard;
    mapInput(guard);
    if (m_info.interrupted)
    {
        std::fprintf(
            stderr, "%s: interrupted after %zu frames; writing the outputs\n", PROGRAM,
            m_mapper->runFrameCount());
    }
    if (m_mapper->runFrameCount() == 0)
    {
        failWithoutFrames(guard);
    }
    if (m_info.stopped_by_error.empty())
    {
        finishAndWrite(t_start);
        m_degenerate = m_info.degenerate;
        if (!m_degenerate.empty())
        {
            std::fflush(stdout);  // the summary first
            std::fprintf(
                stderr,
                "%s: warning: degenerate result: %s; the outputs are written but are not a "
                "usable map (check the images, the calibration and [StereoMatcher] / "
                "[EgomotionEstimator]); "
                "exit status %d\n",
                PROGRAM, m_degenerate.c_str(), EXIT_DEGENERATE);
        }
        return;
    }
    // An error stopped the run: write the frames mapped before it, as Ctrl-C does,
    // and still fail.
    const std::string what = "mapping stopped by an error at " + m_info.stopped_by_error;
    std::fprintf(
        stderr, "%s: %s; writing the outputs of the %zu frames before it\n", PROGRAM, what.c_str(),
        m_mapper->runFrameCount());
    try
    {
        finishAndWrite(t_start);
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error(
            what + " (and the outputs could not be written: " +
            emslam::util::shortExceptionMessage(e) + ")");
    }
    throw std::runtime_error(
        what + "; the outputs of the " + std::to_string(m_mapper->runFrameCount()) +
        " frames before it are in '" + m_out + "'");
}

void MapperApp::mapInput(io::FrameStreamGuard& guard)
{
    ProgressLine progress(PROGRAM, 1, !quiet());
    const auto live = m_viewer ? std::make_unique<MapperLiveFeed>(PROGRAM) : nullptr;
    std::vector<mrpt::obs::CObservation::Ptr> batch;
    bool done = false;
    // The next record (or frame) is read while this one is mapped.
    const InputReader input(m_sequence, m_rawlog);
    io::ObservationSource& reader = *input.source;
    while (!done && reader.next(batch))
    {
        for (const auto& o : batch)
        {
            if (StopSignal::requested() ||
                (maxFrames() != 0 && m_mapper->runFrameCount() >= maxFrames()))
            {
                done = true;
                break;
            }
            if (!mapObservation(*o, reader.recordsRead() - 1, guard, progress, done))
            {
                if (done)
                {
                    break;
                }
                continue;
            }
            if (live)
            {
                live->update(*m_mapper);
            }
            progress.updateFraction(
                m_mapper->runFrameCount(), reader.fractionRead(), energyText(*m_mapper));
        }
        done = done || StopSignal::requested();
    }
    progress.finish();
    recordSkips(guard);
    m_info.interrupted = StopSignal::requested();
    checkInputEnd(reader);
}

bool MapperApp::mapObservation(
    const mrpt::obs::CObservation& o,
    std::size_t record,
    io::FrameStreamGuard& guard,
    ProgressLine& progress,
    bool& stop)
{
    const auto decision = guard.check(o, record);
    if (decision.verdict == io::FrameStreamGuard::Verdict::Skip)
    {
        warnSkipped(decision.warning, progress);
        return false;
    }
    try
    {
        if (decision.verdict == io::FrameStreamGuard::Verdict::NotAFrame || !m_mapper->process(o))
        {
            ++m_info.ignored_observations;
            return false;
        }
    }
    catch (const slam::EntropySlam::UnusableObservation& e)
    {
        warnSkipped(guard.skipUnusable(record, e.what()), progress);
        return false;
    }
    catch (const std::exception& e)
    {
        // The mapper cannot go on, but what it has is still worth writing.
        m_info.stopped_by_error =
            "record " + std::to_string(record) + ": " + emslam::util::shortExceptionMessage(e);
        stop = true;
        return false;
    }
    guard.accept();
    return true;
}

void MapperApp::checkInputEnd(const io::ObservationSource& reader)
{
    if (!reader.endedEarly())
    {
        return;
    }
    m_info.input_ended_early = reader.endReason();
    if (reader.recordsRead() == 0)
    {
        throw std::runtime_error(
            m_sequence ? m_input_name + ": " + reader.endReason()
                       : "'" + m_rawlog + "' is not a readable rawlog: " + reader.endReason());
    }
    if (reader.corrupt() && m_info.stopped_by_error.empty())
    {
        // Not a cut file: some frames read may hold damaged pixels, so the
        // run fails after writing its outputs (exit 1), as after an error.
        m_info.stopped_by_error = reader.endReason();
    }
    else
    {
        std::fprintf(
            stderr,
            "%s: warning: rawlog '%s' ended early at %s; mapping the %zu frames before it\n",
            PROGRAM, m_rawlog.c_str(), reader.endReason().c_str(), m_mapper->runFrameCount());
    }
}

void MapperApp::failWithoutFrames(const io::FrameStreamGuard& guard) const
{
    if (!m_info.stopped_by_error.empty())
    {
        throw std::runtime_error(
            m_input_name + ", " + m_info.stopped_by_error + " (no output written)");
    }
    std::string skipped;
    if (m_info.skipped_observations > 0)
    {
        skipped = "; " + guard.skippedText() + ", first: " + m_info.skipped_reasons.front();
    }
    throw std::runtime_error(
        "no usable stereo or RGB-D observation in " + m_input_name + " (" +
        std::to_string(m_info.ignored_observations) + " observations of other classes" + skipped +
        ")");
}

void MapperApp::finishAndWrite(std::chrono::steady_clock::time_point t_start)
{
    const auto t_finish = std::chrono::steady_clock::now();
    m_mapper->finish();
    m_info.seconds_after_last_frame =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_finish).count();
    m_info.interrupted = m_info.interrupted || StopSignal::requested();
    m_info.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    const slam::EntropySlam& m = *m_mapper;
    m_info.degenerate =
        degenerateRunWarning(m.runFrameCount() - 1, m.egomotionFailures(), m.mapCloud().size());
    writeOutputs(m_ground_truth.trajectory);
}

void MapperApp::warnSkipped(const std::string& warning, ProgressLine& progress)
{
    if (!warning.empty())
    {
        progress.finish();  // a warning never lands in the middle of the progress line
        std::fprintf(stderr, "%s: warning: %s\n", PROGRAM, warning.c_str());
    }
}

void MapperApp::recordSkips(const io::FrameStreamGuard& guard)
{
    const auto& n = guard.counts();
    m_info.skipped_observations = n.total();
    m_info.skipped_bad_stamps = n.bad_stamps;
    m_info.skipped_camera_changes = n.camera_changes;
    m_info.skipped_unusable = n.unusable;
    m_info.skipped_reasons = guard.namedSkips();
    m_info.skipped_text = guard.skippedText();
    m_info.camera_change = guard.cameraChange();
    m_info.camera_change_warning = guard.cameraChangeWarning();
}

void MapperApp::writeOutputs(const emslam::io::TumTrajectory& ground_truth)
{
    // Made only now: a run that fails before leaves no empty folder behind.
    io::createOutputFolder(m_out);
    const slam::EntropySlam& m = *m_mapper;
    if (!ground_truth.empty())
    {
        eval::TrajectoryMetrics::Options opts;
        m_info.egomotion_vs_gt = eval::TrajectoryMetrics::compute(
            ground_truth, tumTrajectoryOf(m.egomotionPoses()), opts);
        m_info.slam_vs_gt =
            eval::TrajectoryMetrics::compute(ground_truth, tumTrajectoryOf(m.slamPoses()), opts);
        m_info.online_vs_gt =
            eval::TrajectoryMetrics::compute(ground_truth, tumTrajectoryOf(m.onlinePoses()), opts);
    }
    // A scan that cannot be made (a frame without ground truth) fails the run,
    // but only after every other output is written.
    std::string scan_error;
    if (m_energy_scan && !ground_truth.empty())
    {
        try
        {
            m_info.energy_scan = scanMapperEnergy(
                m,
                groundTruthFramePoses(m, ground_truth, eval::TrajectoryMetrics::Options().max_dt));
            writeEnergyScanCsv(m_info.energy_scan->scan, joinPath(m_out, "energy_scan.csv"));
        }
        catch (const std::exception& e)
        {
            scan_error = emslam::util::shortExceptionMessage(e);
        }
    }
    const auto ego = tumTrajectoryOf(m.egomotionPoses());
    const auto slam = tumTrajectoryOf(m.slamPoses());
    const auto online = tumTrajectoryOf(m.onlinePoses());
    for (const auto& [name, t] :
         {std::pair{"trajectory_egomotion", &ego}, std::pair{"trajectory_slam", &slam},
          std::pair{"trajectory_online", &online}})
    {
        const bool kitti_only = m_trajectory_output == emslam::io::TrajectoryOutput::Kitti;
        emslam::io::saveTrajectory(
            *t, joinPath(m_out, std::string(name) + (kitti_only ? "_kitti.txt" : ".tum")),
            m_trajectory_output);
    }
    writeKeyframes(m, joinPath(m_out, "keyframes.txt"));
    if (m.parameters().loop_closer.enabled)
    {
        writeLoopClosures(m, joinPath(m_out, "loop_closures.txt"));
    }
    // The small outputs first, so that a full disk still leaves the numbers
    // of the run: summary.json names no other output and nothing written
    // after it changes what it says, so it is written once, here.
    writeStatsCsv(m, joinPath(m_out, "stats.csv"));
    writeSummaryJson(m, m_info, joinPath(m_out, "summary.json"));
    writeEffectiveIni(m.parameters(), joinPath(m_out, "effective.ini"));
    savePly(m.mapCloud(), joinPath(m_out, "map.ply"));
    writeScene(m, ground_truth, joinPath(m_out, "map.3Dscene"));
    writeTopViewPng(m, ground_truth, joinPath(m_out, "map_top.png"));
    writeOccupancyGrid(m, joinPath(m_out, "map_grid.gridmap"), joinPath(m_out, "map_grid.png"));
    writeOctoMap(m, joinPath(m_out, "map.bt"));
    writeEntropyMap(m, joinPath(m_out, "entropy_map.bin"));
    writeEntropyMapView(m, joinPath(m_out, "entropy_map.3Dscene"));
    writeMapperReport(joinPath(m_out, "report.html"), makeReportData(m, m_info, ground_truth));
    saveSession();

    printSummary(ground_truth);
    std::printf(
        "outputs in '%s' (report: %s)\n", m_out.c_str(), joinPath(m_out, "report.html").c_str());
    if (!m_info.camera_change_warning.empty())
    {
        std::fflush(stdout);  // the summary first
        std::fprintf(stderr, "%s: warning: %s\n", PROGRAM, m_info.camera_change_warning.c_str());
    }
    if (!scan_error.empty())
    {
        throw std::runtime_error(scan_error + " (the other outputs are in '" + m_out + "')");
    }
}

void MapperApp::saveSession()
{
    if (m_save_session.empty())
    {
        return;
    }
    m_mapper->session()->save(m_save_session);
}

void MapperApp::printSummary(const emslam::io::TumTrajectory& ground_truth) const
{
    const slam::EntropySlam& m = *m_mapper;
    std::printf(
        "%s: %zu frames (%zu accepted, %zu egomotion failures", PROGRAM, m.frameCount(),
        m.acceptedCount(), m.egomotionFailures());
    if (m_info.ignored_observations > 0)
    {
        std::printf(", %zu other observations ignored", m_info.ignored_observations);
    }
    if (m_info.skipped_observations > 0)
    {
        std::printf(", %s", m_info.skipped_text.c_str());
    }
    std::printf(
        "), %zu rectifications, final energy %.4f, %.1f s\n", m.rectifications().size(),
        m.finalEnergy(), m_info.seconds);
    std::printf(
        "%s (first to last pose): egomotion %.3f m, SLAM %.3f m\n",
        startToEndName(ground_truth).c_str(), loopGap(m.egomotionPoses()), loopGap(m.slamPoses()));
    if (const auto& r = m.relocalization())
    {
        std::printf(
            "session: %s '%s', located at frame %zu of this input (%zu of %zu registrations "
            "agreed)%s\n",
            m_localize ? "localized in" : "continued", m_load_session.c_str(), r->frames_before,
            r->fix.agreeing, r->fix.tried, m_save_session.empty() ? "" : "; saved with this run");
    }
    if (!m_save_session.empty())
    {
        std::printf("session written to '%s'\n", m_save_session.c_str());
    }
    if (m.parameters().loop_closer.enabled && !m.parameters().mapper.egomotion_only)
    {
        const auto& lc = m.loopCloser().stats();
        std::printf(
            "loop closing (online): %zu loop edges of %zu registrations (%zu dropped as "
            "inconsistent), %zu local edges of %zu, %.1f s in the background, %.2f s polish; "
            "a loop is in the live estimate %.2f s (mean; max %.2f s) after its keyframe\n",
            lc.loop_edges, lc.registrations, lc.dropped_edges, lc.local_edges,
            lc.local_registrations, (lc.ms - lc.polish_ms) / 1000.0, lc.polish_ms / 1000.0,
            lc.latency_ms_mean / 1000.0, lc.latency_ms_max / 1000.0);
        if (lc.new_loops > 0)
        {
            std::printf(
                "new loops: %zu, in the live estimate %.2f s (mean; max %.2f s) and %.1f m of "
                "path (mean; max %.1f m) after the first keyframe that saw the place again\n",
                lc.new_loops, lc.new_loop_latency_ms_mean / 1000.0,
                lc.new_loop_latency_ms_max / 1000.0, lc.new_loop_wait_m_mean,
                lc.new_loop_wait_m_max);
        }
        if (m.parameters().loop_closer.vertical_prior)
        {
            // The bias is NaN until the keyframes' orientations observe it.
            const std::string bias =
                std::isnan(lc.vertical_bias_deg)
                    ? std::string("camera bias not observable yet")
                    : mrpt::format("camera bias %.2f deg", lc.vertical_bias_deg);
            std::printf(
                "levelling: %zu of %zu measured verticals agree (tilt spread %.2f deg, %s, "
                "%.1f keyframes per independent error)\n",
                lc.verticals_used, lc.verticals_measured, lc.vertical_drift_deg, bias.c_str(),
                lc.vertical_correlation_time);
        }
    }
    for (const auto& why : m.unreliableReasons())
    {
        std::fflush(stdout);
        std::fprintf(stderr, "%s: warning: the estimate is unreliable: %s\n", PROGRAM, why.c_str());
    }
    if (m_info.slam_vs_gt)
    {
        std::printf(
            "ATE against the ground truth: egomotion %.3f m, SLAM %.3f m, online %.3f m\n",
            m_info.egomotion_vs_gt->ate_rmse_m, m_info.slam_vs_gt->ate_rmse_m,
            m_info.online_vs_gt ? m_info.online_vs_gt->ate_rmse_m : 0.0);
    }
    if (m_info.energy_scan)
    {
        const auto& e = m_info.energy_scan->scan.summary;
        std::printf(
            "energy scan around the ground truth: minimum at the truth on %zu of %zu lines, median "
            "|argmin| %.3f m / %.2f deg, %.1f s; entropy at truth / egomotion / SLAM %.4f / "
            "%.4f / %.4f; odometry prior %.4f / %.4f / %.4f\n",
            e.lines_at_truth, e.lines, e.median_abs_argmin_translation_m,
            mrpt::RAD2DEG(e.median_abs_argmin_rotation_rad), e.seconds, e.energy_at_truth,
            m_info.energy_scan->entropy_egomotion, m_info.energy_scan->entropy_slam,
            m_info.energy_scan->prior_truth, m_info.energy_scan->prior_egomotion,
            m_info.energy_scan->prior_slam);
    }
}

}  // namespace emslam::apps
