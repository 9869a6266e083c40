// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>
#include <emslam/apps/ConfigLookup.h>
#include <emslam/apps/ConfigValidation.h>
#include <emslam/apps/OdometryApp.h>
#include <emslam/apps/StopSignal.h>
#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/io/FrameStreamGuard.h>
#include <emslam/io/InputOutputClash.h>
#include <emslam/io/RawlogInput.h>
#include <emslam/io/TrajectoryWriter.h>
#include <emslam/slam/StereoOdometry.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/img/CImage.h>
#include <mrpt/serialization/CArchive.h>

#include <chrono>
#include <cstdio>
#include <new>
#include <stdexcept>
#include <vector>

namespace emslam::apps
{
namespace
{
constexpr const char* STEREO_SECTION = "StereoMatcher";
constexpr const char* EGOMOTION_SECTION = "EgomotionEstimator";
constexpr const char* PROGRAM = "emslam-odometry";

/** Every section and key this app reads, with its default value. */
mrpt::config::CConfigFileMemory knownParameters()
{
    mrpt::config::CConfigFileMemory known;
    emslam::stereo::StereoMatcher::TParameters().saveToConfigFile(known, STEREO_SECTION);
    emslam::egomotion::EgomotionEstimator::TParameters().saveToConfigFile(known, EGOMOTION_SECTION);
    return known;
}

/** 'a', 'b' */
std::string quotedList(const std::vector<std::string>& files)
{
    std::string s;
    for (const auto& f : files)
    {
        s += (s.empty() ? "'" : ", '") + f + "'";
    }
    return s;
}
/** Sums of the per-frame times and match counts (steps: after the first frame). */
struct OdometrySums
{
    double stereo{0}, features{0}, descriptors{0}, matching{0}, lwo{0}, pose{0}, egomotion{0};
    double initial_matches{0}, final_matches{0};
    std::size_t steps{0};

    void add(const slam::StereoOdometry::Step& step)
    {
        const auto& r = step.egomotion;
        if (!step.first)
        {
            ++steps;
            initial_matches += static_cast<double>(r.initial_matches);
            final_matches += static_cast<double>(r.final_matches);
            matching += r.ms_matching;
            lwo += r.ms_lwo;
            pose += r.ms_pose;
        }
        stereo += step.ms_stereo;
        features += r.ms_features;
        descriptors += r.ms_descriptors;
        egomotion += r.ms_total;
    }
};

void printFrame(std::size_t index, const slam::StereoOdometry::Step& step)
{
    const auto& f = step.frame;
    const auto& r = step.egomotion;
    std::printf(
        "frame %zu: %zu points, %zu features, matches %zu -> %zu (LWO %d it), %s | ms: "
        "stereo %.1f features %.1f descr %.1f match %.1f lwo %.1f pose %.1f egomotion "
        "%.1f\n",
        index, f.size(), r.features_cur, r.initial_matches, r.final_matches, r.lwo_iterations,
        r.ok ? (r.guided ? "ok, guided" : "ok") : r.failure_reason.c_str(), step.ms_stereo,
        r.ms_features, r.ms_descriptors, r.ms_matching, r.ms_lwo, r.ms_pose, r.ms_total);
}

void warn(const std::string& warning)
{
    if (!warning.empty())
    {
        std::fflush(stdout);
        std::fprintf(stderr, "%s: warning: %s\n", PROGRAM, warning.c_str());
    }
}

/** Feeds the rawlog's observations to handle() until max_frames (0: all)
 * were taken or a signal came. Frames with a bad timestamp or another
 * camera, or that the front-end refuses, are skipped: the trajectory stays
 * strictly increasing in time. Returns the observations handle() did not
 * take (other classes). */
template <typename Handle>
std::size_t feedFrames(
    io::RawlogInput& in,
    io::FrameStreamGuard& guard,
    std::size_t max_frames,
    const std::size_t& frames_processed,
    const Handle& handle)
{
    std::vector<mrpt::obs::CObservation::Ptr> batch;
    std::size_t ignored = 0;
    while ((max_frames == 0 || frames_processed < max_frames) && !StopSignal::requested() &&
           in.next(batch))
    {
        const std::size_t record = in.recordsRead() - 1;
        for (const auto& o : batch)
        {
            if (max_frames != 0 && frames_processed >= max_frames)
            {
                break;
            }
            const auto decision = guard.check(*o, record);
            if (decision.verdict == io::FrameStreamGuard::Verdict::Skip)
            {
                warn(decision.warning);
                continue;
            }
            try
            {
                if (decision.verdict == io::FrameStreamGuard::Verdict::NotAFrame || !handle(*o))
                {
                    ++ignored;
                    continue;
                }
            }
            catch (const std::bad_alloc&)
            {
                throw;  // not the observation's fault
            }
            catch (const std::exception& e)
            {
                // StereoOdometry changed nothing: the frame is skipped.
                warn(guard.skipUnusable(record, emslam::util::shortExceptionMessage(e)));
                continue;
            }
            guard.accept();
        }
    }
    return ignored;
}
/** The means per frame (per step for what only steps have) into the app's results. */
void storeMeans(OdometryApp& app, const OdometrySums& sums)
{
    const double n = static_cast<double>(app.frames_processed);
    app.mean_ms_stereo = sums.stereo / n;
    app.mean_ms_features = sums.features / n;
    app.mean_ms_descriptors = sums.descriptors / n;
    app.mean_ms_egomotion = sums.egomotion / n;
    const double ns = sums.steps > 0 ? static_cast<double>(sums.steps) : 1.0;
    app.mean_ms_matching = sums.matching / ns;
    app.mean_ms_lwo = sums.lwo / ns;
    app.mean_ms_pose = sums.pose / ns;
    app.mean_initial_matches = sums.initial_matches / ns;
    app.mean_final_matches = sums.final_matches / ns;
}
void warnDegenerate(const std::string& degenerate)
{
    std::fflush(stdout);
    std::fprintf(
        stderr,
        "emslam-odometry: warning: degenerate result: %s; the trajectory is written but "
        "is not usable (check the images, the calibration and [StereoMatcher] / "
        "[EgomotionEstimator]); "
        "exit status %d\n",
        degenerate.c_str(), EXIT_DEGENERATE);
}
void printParameters(
    const emslam::stereo::StereoMatcher::TParameters& sp,
    const emslam::egomotion::EgomotionEstimator::TParameters& ep)
{
    std::printf(
        "[StereoMatcher] num_disparities=%d range=[%g, %g] m  [EgomotionEstimator] |W|=%d S_min=%g "
        "sigma_min=%g "
        "min_final_matches=%d\n",
        sp.num_disparities, sp.min_range, sp.max_range, ep.window_size, ep.similarity_min,
        ep.lwo_sigma_min, ep.min_final_matches);
}
}  // namespace

OdometryApp::OdometryApp() : App(PROGRAM) {}

bool OdometryApp::parseArguments(int argc, const char** argv)
{
    TCLAP::CmdLine cmd(
        "emslam-odometry: stereo visual odometry (GLM features, log-polar matching, LWO, Dpp "
        "pose) over a rawlog; writes the camera trajectory in TUM format. Exit status: 0 ok; 1 "
        "error; 3 degenerate result (more than half of the egomotion steps failed: the "
        "trajectory is written, with a warning).",
        ' ', "0.1");
    TCLAP::UnlabeledValueArg<std::string> rawlog(
        "rawlog", "Rawlog with CObservationStereoImages / CObservation3DRangeScan", true, "",
        "DATASET.rawlog", cmd);
    TCLAP::ValueArg<std::string> output(
        "o", "output",
        "Output trajectory: the TUM file (t tx ty tz qx qy qz qw), or with --trajectory-format "
        "kitti the KITTI poses file (its times beside it, NAME_times.txt)",
        true, "", "OUT.tum", cmd);
    TCLAP::ValueArg<std::string> trajectory_format(
        "", "trajectory-format",
        withDefault(
            "tum, kitti (3x4 poses + times) or both (TUM at FILE, KITTI beside it as "
            "FILE-stem_kitti.txt + FILE-stem_times.txt)",
            "tum"),
        false, "tum", "tum|kitti|both", cmd);
    TCLAP::ValueArg<std::string> config(
        "c", "config",
        withDefault(
            "INI file with [StereoMatcher] and [EgomotionEstimator] sections, or the name of a "
            "shipped one (kitti, "
            "euroc: share/emslam/config/odometry)",
            "the built-in defaults"),
        false, "", "CONFIG.ini", cmd);
    addSetOption(
        cmd, "Override a parameter: SECTION.key=value ([StereoMatcher], [EgomotionEstimator])");
    addMaxFramesOption(cmd, "Stop after N frames (0: all)");
    addQuietOption(cmd, "Print the summary only, not every frame");

    if (!parseCommandLine(cmd, argc, argv, {{"--rawlog", "", 0, "DATASET.rawlog"}}))
    {
        return false;
    }
    m_rawlog = rawlog.getValue();
    m_output = output.getValue();
    const std::string config_file = findConfigFile(config.getValue(), "odometry");
    try
    {
        m_trajectory_output = emslam::io::parseTrajectoryOutput(trajectory_format.getValue());
    }
    catch (const std::invalid_argument& e)
    {
        throw std::invalid_argument(std::string("--trajectory-format: ") + e.what());
    }
    std::vector<io::RolePath> outputs;
    for (const auto& f : io::trajectoryFiles(m_output, m_trajectory_output))
    {
        outputs.push_back({"output trajectory", f});
    }
    io::requireOutputsAreNotInputs(
        outputs, {{"the rawlog", m_rawlog}, {"the config file", config_file}});
    const auto known = knownParameters();
    loadParameters(config_file, &known);
    checkConfig(params);
    return true;
}

void OdometryApp::checkConfig(const mrpt::config::CConfigFileBase& params)
{
    requireValidConfig(params, knownParameters(), {}, true);
    emslam::stereo::StereoMatcher::TParameters().loadFromConfigFile(params, STEREO_SECTION);
    emslam::egomotion::EgomotionEstimator::TParameters().loadFromConfigFile(
        params, EGOMOTION_SECTION);
}

void OdometryApp::execute()
{
    // Parameters are read (and validated) before any input is touched.
    emslam::stereo::StereoMatcher::TParameters sp;
    sp.loadFromConfigFile(params, STEREO_SECTION);
    emslam::egomotion::EgomotionEstimator::TParameters ep;
    ep.loadFromConfigFile(params, EGOMOTION_SECTION);
    slam::StereoOdometry odometry(sp, ep);
    printParameters(sp, ep);

    io::RawlogInput in(m_rawlog);
    // SIGINT / SIGTERM / SIGHUP end the loop after the current frame; the
    // trajectory of the frames done is still written (exit 128 + signal).
    StopSignal::clear();
    const StopSignalGuard signals;

    trajectory = {};
    degenerate.clear();
    camera_change.clear();
    skipped_reasons.clear();
    frames_processed = failures = 0;
    OdometrySums sums;
    slam::StereoOdometry::Step step;
    const auto handle = [&](const mrpt::obs::CObservation& o)
    {
        if (!odometry.process(o, step))
        {
            return false;
        }
        sums.add(step);
        failures = odometry.failures();
        trajectory.add(mrpt::Clock::toDouble(step.frame.timestamp), odometry.pose());
        if (!quiet())
        {
            printFrame(frames_processed, step);
        }
        ++frames_processed;
        return true;
    };
    io::FrameStreamGuard guard;
    const std::size_t ignored = feedFrames(in, guard, maxFrames(), frames_processed, handle);
    in.warnIfEndedEarly(PROGRAM);
    skipped = guard.counts();
    skipped_reasons = guard.namedSkips();
    camera_change = guard.cameraChangeWarning();
    if (frames_processed == 0)
    {
        throw std::runtime_error(
            "no usable stereo or RGB-D observation in rawlog '" + m_rawlog + "'" +
            (skipped.total() > 0
                 ? " (" + guard.skippedText() + ", first: " + skipped_reasons.front() + ")"
                 : std::string()));
    }
    const auto written = emslam::io::saveTrajectory(trajectory, m_output, m_trajectory_output);
    if (StopSignal::requested())
    {
        std::fprintf(
            stderr, "%s: interrupted after %zu frames; %s hold them\n", PROGRAM, frames_processed,
            quotedList(written).c_str());
    }

    storeMeans(*this, sums);
    if (ignored > 0)
    {
        std::printf("ignored %zu observations of other classes\n", ignored);
    }
    if (skipped.total() > 0)
    {
        std::printf("%s\n", guard.skippedText().c_str());
    }
    printSummary(odometry, quotedList(written));
    degenerate = degenerateRunWarning(sums.steps, failures, std::nullopt);
    if (!degenerate.empty())
    {
        warnDegenerate(degenerate);
    }
}

void OdometryApp::printSummary(
    const slam::StereoOdometry& odometry, const std::string& written) const
{
    if (odometry.estimator().parameters().guided_matching)
    {
        std::printf(
            "guided matching: %zu steps guided, %zu fell back to the full search\n",
            odometry.guidedSteps(), odometry.guidedFallbacks());
    }
    const auto& T = odometry.pose();
    std::printf(
        "%zu frames, %zu failed steps; matches %.0f -> %.0f after LWO on average\n"
        "mean ms per frame: stereo %.1f, features %.1f, descriptors %.1f, matching %.1f, LWO "
        "%.1f, pose %.1f, egomotion total %.1f\n"
        "final pose: x %.3f y %.3f z %.3f m (%.3f m from the start); trajectory written to "
        "%s\n",
        frames_processed, failures, mean_initial_matches, mean_final_matches, mean_ms_stereo,
        mean_ms_features, mean_ms_descriptors, mean_ms_matching, mean_ms_lwo, mean_ms_pose,
        mean_ms_egomotion, T.x(), T.y(), T.z(), T.norm(), written.c_str());
    if (!camera_change.empty())
    {
        std::fflush(stdout);
        std::fprintf(stderr, "%s: warning: %s\n", PROGRAM, camera_change.c_str());
    }
}

}  // namespace emslam::apps
