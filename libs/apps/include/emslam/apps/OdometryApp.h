// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/App.h>
#include <emslam/apps/DegenerateRun.h>
#include <emslam/io/FrameStreamGuard.h>
#include <emslam/io/TrajectoryWriter.h>
#include <emslam/io/TumTrajectory.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <cstddef>
#include <string>
#include <vector>

namespace emslam::slam
{
class StereoOdometry;
}  // namespace emslam::slam

namespace emslam::apps
{
/** `emslam-odometry`: stereo visual odometry alone (paper §2.1, no global
 * rectification). Every stereo / RGB-D observation of a rawlog goes through
 * the stereo front-end and EgomotionEstimator::process(); the steps are
 * composed into the pose of the left camera in the first frame's left
 * camera, written as a TUM trajectory, KITTI poses + times, or both
 * (`--trajectory-format`, emslam::io::saveTrajectory()). A failed step
 * keeps the previous pose and is counted. A frame with a bad timestamp or
 * another camera than the first one's, or that the front-end cannot use, is
 * skipped with a warning (emslam::io::FrameStreamGuard): the trajectory is
 * strictly increasing in time.
 *
 * \code
 * emslam-odometry IN.rawlog -o TRAJ.tum [--config X.ini]
 *   [--trajectory-format tum|kitti|both] [--set Section.key=value ...]
 *   [--max-frames N] [--quiet]
 * \endcode
 * Parameters: `[StereoMatcher]` (StereoMatcher::TParameters) and `[EgomotionEstimator]`
 * (EgomotionEstimator::TParameters); see config/odometry/kitti.ini.
 * \ingroup emslam_apps_grp \sa emslam::egomotion::EgomotionEstimator */
class OdometryApp : public App
{
public:
    OdometryApp();

    /** The configuration check initialize() runs on the INI file plus the
     * `--set` overrides, before any input is read: [StereoMatcher] and [EgomotionEstimator] (other
     * sections are ignored) must hold only known keys, values of their kind (see
     * requireValidConfig()) and values in their ranges (the parameter structs' validate()). Throws
     * std::invalid_argument naming the section, key and value. */
    static void checkConfig(const mrpt::config::CConfigFileBase& params);

    // ---- Results of run() ----
    std::size_t frames_processed{0};  //!< frames read and run through the egomotion
    /** Steps (frame pairs) whose egomotion failed (excludes the first frame). */
    std::size_t failures{0};
    /** Frames skipped, per cause, and the first ones named ("record N: cause"). */
    emslam::io::FrameStreamGuard::Counts skipped;
    std::vector<std::string> skipped_reasons;  //!< the first skipped frames, "record N: cause"
    /** FrameStreamGuard::cameraChangeWarning(), or "". */
    std::string camera_change;
    /** T_first_left of every processed frame, as written to the output. */
    emslam::io::TumTrajectory trajectory;
    /** Mean time per frame [ms]: stereo front-end, egomotion stages, total. */
    ///@{
    double mean_ms_stereo{0}, mean_ms_features{0}, mean_ms_descriptors{0}, mean_ms_matching{0},
        mean_ms_lwo{0}, mean_ms_pose{0}, mean_ms_egomotion{0};
    ///@}
    /** Mean matches per step before / after LWO. */
    ///@{
    double mean_initial_matches{0}, mean_final_matches{0};
    ///@}
    /** Why the trajectory is degenerate (more than half of the steps
     * failed, see degenerateRunWarning()), or "" if it is usable. */
    std::string degenerate;

    /** The process exit code of a run() that returned: 0, or
     * EXIT_DEGENERATE when `degenerate` is not empty. */
    int exitCode() const { return degenerate.empty() ? 0 : EXIT_DEGENERATE; }

protected:
    bool parseArguments(int argc, const char** argv) override;
    /** Runs the odometry and writes the trajectory. Throws with a message
     * naming the file on bad input or when no frame was found. */
    void execute() override;

private:
    /** The guided matching counts, the means and the final pose; `written`
     * names the trajectory files. */
    void printSummary(const slam::StereoOdometry& odometry, const std::string& written) const;

    std::string m_rawlog, m_output;
    emslam::io::TrajectoryOutput m_trajectory_output{emslam::io::TrajectoryOutput::Tum};
};

}  // namespace emslam::apps
