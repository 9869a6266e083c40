// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/App.h>
#include <emslam/io/FrameStreamGuard.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace emslam::stereo
{
struct StereoFrame;
class StereoFrontEnd;
}  // namespace emslam::stereo

namespace emslam::apps
{
/** `emslam-stereo`: runs the stereo front-end on one rectified or raw image
 * pair, or on every stereo / RGB-D observation of a rawlog, and prints what it
 * found (points, density, depth range, time per frame, and the bad-pixel rate
 * when a ground-truth disparity image is given).
 *
 * \code
 * emslam-stereo L.png R.png CALIB.ini [--calib-section CAMERA]
 * emslam-stereo IN.rawlog [--max-frames N]
 *   [--config STEREO.ini] [--set StereoMatcher.key=value ...]
 *   [--gt-disparity GT.png [--gt-disparity-scale S]]
 *   [--out-rawlog OUT.rawlog]   ; frames as CObservation3DRangeScan (stock viewers)
 *   [--ply OUT.ply]             ; the first frame's points, with intensity
 *   [--disparity-png OUT.png]   ; the first frame's disparity, false colour
 * \endcode
 * Parameters are read from the `[StereoMatcher]` section (StereoMatcher::TParameters).
 * A rawlog frame with a bad timestamp or another camera than the first one's,
 * or that the front-end cannot use, is skipped with a warning
 * (emslam::io::FrameStreamGuard, as in emslam-mapper).
 * \ingroup emslam_apps_grp */
class StereoApp : public App
{
public:
    StereoApp();

    /** The configuration check initialize() runs on the INI file plus the
     * `--set` overrides, before any input is read: [StereoMatcher] (other sections are ignored)
     * must hold only known keys, values of their kind (see requireValidConfig()) and values in
     * their ranges (the parameter structs' validate()). Throws std::invalid_argument naming the
     * section, key and value. */
    static void checkConfig(const mrpt::config::CConfigFileBase& params);

    // ---- Results of run() ----
    std::size_t frames_processed{0};  //!< frames run through the front-end
    std::size_t total_points{0};      //!< 3D points over every frame
    /** Mean fraction of pixels with a disparity. */
    double mean_density{0};
    double mean_ms_per_frame{0};  //!< mean front-end time per frame [ms]
    /** Fraction of pixels with a disparity that are > 1 px off the ground
     * truth (first frame), or -1 when no ground truth was given. */
    double bad_pixel_rate{-1};
    /** Fraction of ground-truth pixels that got a disparity, or -1. */
    double gt_coverage{-1};
    /** Rawlog frames skipped, per cause, and the first ones named ("record N: cause"). */
    emslam::io::FrameStreamGuard::Counts skipped;
    std::vector<std::string> skipped_reasons;  //!< the first skipped frames, "record N: cause"
    /** FrameStreamGuard::cameraChangeWarning(), or "". */
    std::string camera_change;

protected:
    bool parseArguments(int argc, const char** argv) override;
    /** Processes the input. Throws with a message naming the file on bad input. */
    void execute() override;

private:
    /** Takes each frame and the milliseconds the front-end took for it. */
    using FrameHandler = std::function<void(const emslam::stereo::StereoFrame&, double)>;
    /** --ply, --disparity and the comparison with --gt-disparity. */
    void writeFirstFrameOutputs(const emslam::stereo::StereoFrame& f);
    /** The one frame of --left/--right/--calib. */
    void processImagePair(emslam::stereo::StereoFrontEnd& front, const FrameHandler& handle) const;
    /** The frames of --rawlog, as the mapper would take them, until a signal. */
    void processRawlog(emslam::stereo::StereoFrontEnd& front, const FrameHandler& handle);

    std::string m_left, m_right, m_calib, m_calib_section{"CAMERA"};
    std::string m_rawlog, m_out_rawlog, m_ply, m_disparity_png, m_gt_disparity;
    double m_gt_scale{1.0};
};

}  // namespace emslam::apps
