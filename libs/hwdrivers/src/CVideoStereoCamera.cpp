// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/hwdrivers/CVideoStereoCamera.h>
#include <emslam/hwdrivers/SensorStatus.h>
#include <emslam/io/CalibrationFiles.h>
#include <emslam/io/OpenCvStereoCalibration.h>
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/util/ConfigVisitor.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <cmath>
#include <cstdlib>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <tuple>

IMPLEMENTS_GENERIC_SENSOR(CVideoStereoCamera, emslam::hwdrivers)

namespace emslam::hwdrivers
{
namespace
{
constexpr double DEG2RAD = M_PI / 180.0;
/** Polling rate of devices and pipelines without process_rate [Hz]: above
 * any camera's rate, since read() waits for the next frame. */
constexpr double LIVE_POLL_RATE = 100.0;

[[noreturn]] void bad(const std::string& key, const std::string& why)
{
    throw std::invalid_argument("CVideoStereoCamera: '" + key + "' " + why);
}

/** `cam` with `size` where it has none (an OpenCV file without a size). */
mrpt::img::TStereoCamera withSize(mrpt::img::TStereoCamera cam, cv::Size size)
{
    for (auto* c : {&cam.leftCamera, &cam.rightCamera})
    {
        if (c->ncols == 0 && c->nrows == 0)
        {
            c->ncols = static_cast<uint32_t>(size.width);
            c->nrows = static_cast<uint32_t>(size.height);
        }
    }
    return cam;
}

cv::Mat toGrey(const cv::Mat& m)
{
    if (m.channels() == 1)
    {
        return m;
    }
    cv::Mat g;
    cv::cvtColor(m, g, m.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
    return g;
}
/** A number key saved with all its digits and a decimal point: not an
 * integer key. */
void number(emslam::util::ConfigVisitor& v, const std::string& key, double& value)
{
    v.text(
        key, value, [](double x) { return mrpt::format("%#.17g", x); },
        [](const std::string& t) { return std::atof(t.c_str()); });
}

/** Every key of the sensor's own, once for load and save. */
void visit(CVideoStereoCamera::TParameters& p, emslam::util::ConfigVisitor& v)
{
    v.field("source", p.source);
    v.field("source_right", p.source_right);
    v.field("backend", p.backend);
    v.field("capture_width", p.capture_width);
    v.field("capture_height", p.capture_height);
    number(v, "capture_fps", p.capture_fps);
    v.field("fourcc", p.fourcc);
    v.field("timestamps", p.timestamps);
    number(v, "start_time", p.start_time);
    number(v, "video_fps", p.video_fps);
    v.field("grayscale", p.grayscale);
    v.field("calibration_file", p.calibration_file);
    v.field("calibration_extrinsics_file", p.calibration_extrinsics_file);
    v.field("calibration_section", p.calibration_section);
    number(v, "translation_scale", p.translation_scale);
    v.field("rectify", p.rectify);
    number(v, "rectify_alpha", p.rectify_alpha);
    number(v, "pose_x", p.pose_x);
    number(v, "pose_y", p.pose_y);
    number(v, "pose_z", p.pose_z);
    number(v, "pose_yaw_deg", p.pose_yaw_deg);
    number(v, "pose_pitch_deg", p.pose_pitch_deg);
    number(v, "pose_roll_deg", p.pose_roll_deg);
}
}  // namespace

void CVideoStereoCamera::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    loadCalibration(c, s);
    validate();
}

void CVideoStereoCamera::TParameters::loadCalibration(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    // The keys that choose the reader are checked before it runs.
    if (!(translation_scale > 0 && translation_scale <= 1e6))
    {
        bad("translation_scale", mrpt::format("= %g must be in (0, 1e6]", translation_scale));
    }
    const bool opencv = emslam::io::isOpenCvStorageFile(calibration_file);
    if (!calibration_extrinsics_file.empty() && !opencv)
    {
        bad("calibration_extrinsics_file",
            "is for OpenCV calibration files (.yml, .yaml, .xml, "
            ".json) only");
    }
    try
    {
        if (calibration_file.empty())
        {
            stereo_camera = emslam::stereo::loadStereoCameraFromConfig(c, calibration_section);
        }
        else if (opencv)
        {
            stereo_camera = emslam::io::loadOpenCvStereoCalibration(
                calibration_file, calibration_extrinsics_file, translation_scale);
        }
        else
        {
            stereo_camera =
                emslam::io::loadStereoCameraFromIniFile(calibration_file, calibration_section);
        }
    }
    catch (const std::exception& e)
    {
        const std::string key =
            calibration_file.empty()
                ? "calibration_section = '" + calibration_section + "'"
                : "calibration_file = '" + calibration_file + "'" +
                      (calibration_extrinsics_file.empty() ? std::string()
                                                           : ", calibration_extrinsics_file = '" +
                                                                 calibration_extrinsics_file + "'");
        throw std::invalid_argument(
            "CVideoStereoCamera, section " + s + ": " + key + ": " +
            emslam::util::shortExceptionMessage(e));
    }
}

void CVideoStereoCamera::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
    if (calibration_file.empty() && stereo_camera.leftCamera.ncols > 0)
    {
        stereo_camera.saveToConfigFile(calibration_section, c);
    }
}

void CVideoStereoCamera::TParameters::validate() const
{
    if (mrpt::system::trim(source).empty())
    {
        bad("source", "is mandatory (device index, /dev/videoN, video file or GStreamer pipeline)");
    }
    if (backend != "auto" && backend != "v4l2" && backend != "ffmpeg" && backend != "gstreamer" &&
        backend != "any")
    {
        bad("backend", "must be auto, v4l2, ffmpeg, gstreamer or any, not '" + backend + "'");
    }
    if (!fourcc.empty() && fourcc.size() != 4)
    {
        bad("fourcc", "= '" + fourcc + "' must be empty or four characters (MJPG, YUYV, ...)");
    }
    if (timestamps != "auto" && timestamps != "video" && timestamps != "now")
    {
        bad("timestamps", "must be auto, video or now, not '" + timestamps + "'");
    }
    validateNumbers();
    const std::string calib = calibration_file.empty() ? "calibration_section" : "calibration_file";
    const auto& L = stereo_camera.leftCamera;
    const auto& R = stereo_camera.rightCamera;
    if (L.ncols != R.ncols || L.nrows != R.nrows)
    {
        bad(calib, "left and right cameras must have the same resolution");
    }
    // Without a size (an OpenCV file) the rest is checked with a stand-in size.
    emslam::stereo::validateStereoCamera(
        withSize(stereo_camera, cv::Size(2, 2)), "CVideoStereoCamera: " + calib);
}

void CVideoStereoCamera::TParameters::validateNumbers() const
{
    for (const auto& [key, v] :
         {std::pair{"capture_width", capture_width}, std::pair{"capture_height", capture_height}})
    {
        if (v < 0 || v > 100000)
        {
            bad(key, "= " + std::to_string(v) + " must be in 0 .. 100000 px");
        }
    }
    for (const auto& [key, v] :
         {std::pair{"capture_fps", capture_fps}, std::pair{"video_fps", video_fps}})
    {
        if (!(v >= 0 && v <= 1000))
        {
            bad(key, mrpt::format("= %g must be in 0 .. 1000 Hz", v));
        }
    }
    // A UNIX time within +-1e11 s keeps microsecond resolution.
    if (!(std::abs(start_time) <= 1e11))
    {
        bad("start_time", mrpt::format("= %g must be a UNIX time within +-1e11 s", start_time));
    }
    if (!(translation_scale > 0 && translation_scale <= 1e6))
    {
        bad("translation_scale", mrpt::format("= %g must be in (0, 1e6]", translation_scale));
    }
    if (!(rectify_alpha >= 0 && rectify_alpha <= 1))
    {
        bad("rectify_alpha", mrpt::format("= %g must be in [0, 1]", rectify_alpha));
    }
    for (const auto& [key, v, limit] :
         {std::tuple{"pose_x", pose_x, 1e4}, std::tuple{"pose_y", pose_y, 1e4},
          std::tuple{"pose_z", pose_z, 1e4}, std::tuple{"pose_yaw_deg", pose_yaw_deg, 360.0},
          std::tuple{"pose_pitch_deg", pose_pitch_deg, 360.0},
          std::tuple{"pose_roll_deg", pose_roll_deg, 360.0}})
    {
        if (!(std::abs(v) <= limit))
        {
            bad(key, mrpt::format("= %g must be in [-%g, %g]", v, limit, limit));
        }
    }
}

CVideoStereoCamera::~CVideoStereoCamera() = default;

void CVideoStereoCamera::loadConfig_sensorSpecific(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    TParameters p;
    p.loadFromConfigFile(cfg, section);
    m_params = p;
    m_section = section;
    if (!std::isfinite(m_process_rate) || m_process_rate > 10000)
    {
        bad("process_rate",
            mrpt::format(
                "= %g must be at most 10000 Hz (absent or <= 0: the default)", m_process_rate));
    }
    // The real default (a file's rate) is known once it is open: initialize().
    m_rate_from_source = !(m_process_rate > 0);
    if (m_rate_from_source)
    {
        m_process_rate = LIVE_POLL_RATE;
    }
}

void CVideoStereoCamera::initialize()
{
    m_state = ssInitializing;
    try
    {
        openSources();
        m_read = 0;
        m_delivered = 0;
        if (!readFrame())
        {
            throw std::runtime_error(
                "source '" + m_params.source + "' delivered no frame (" +
                toString(m_source->kind()) + ")");
        }
        m_first_t = mrpt::Clock::now();
        m_have_first = true;
        prepareCalibration(m_left.size());
        if (m_rate_from_source && m_source->kind() == VideoSourceKind::FILE && m_stamp_fps > 0)
        {
            m_process_rate = m_stamp_fps;  // a file plays at its own rate
        }
    }
    catch (const std::exception& e)
    {
        m_state = ssError;
        m_source.reset();
        m_source_right.reset();
        throw std::runtime_error(
            "CVideoStereoCamera, section " + m_section + ": " +
            emslam::util::shortExceptionMessage(e));
    }
    m_state = ssWorking;
}

void CVideoStereoCamera::openSources()
{
    const TParameters& p = m_params;
    VideoCaptureRequest req;
    req.backend = p.backend;
    req.width = p.capture_width;
    req.height = p.capture_height;
    req.fps = p.capture_fps;
    req.fourcc = p.fourcc;
    m_source = std::make_unique<VideoSource>("source", p.source, req);
    if (!p.source_right.empty())
    {
        m_source_right = std::make_unique<VideoSource>("source_right", p.source_right, req);
    }
    m_video_stamps = p.timestamps == "video" ||
                     (p.timestamps == "auto" && m_source->kind() == VideoSourceKind::FILE);
    m_stamp_fps = p.video_fps > 0 ? p.video_fps : m_source->reportedFps();
    if (m_video_stamps && !(m_stamp_fps > 0))
    {
        throw std::invalid_argument(
            "'video_fps' = 0 and '" + p.source +
            "' declares no frame rate: set video_fps for its timestamps");
    }
}

void CVideoStereoCamera::prepareCalibration(cv::Size size)
{
    const TParameters& p = m_params;
    const mrpt::img::TStereoCamera raw = withSize(p.stereo_camera, size);
    const cv::Size calib(
        static_cast<int>(raw.leftCamera.ncols), static_cast<int>(raw.leftCamera.nrows));
    if (calib != size || m_right.size() != size)
    {
        throw std::runtime_error(mrpt::format(
            "the images are %dx%d (left) and %dx%d (right)%s, the calibration ('%s') is "
            "%dx%d: a frame of another size than the calibration's",
            size.width, size.height, m_right.cols, m_right.rows,
            p.source_right.empty() ? ", the halves of a side-by-side frame" : "",
            p.calibration_file.empty() ? p.calibration_section.c_str() : p.calibration_file.c_str(),
            calib.width, calib.height));
    }
    emslam::stereo::validateStereoCamera(raw, "CVideoStereoCamera calibration");
    m_output_camera = raw;
    if (p.rectify)
    {
        m_rectifier.setCalibration(raw, p.rectify_alpha);
        m_output_camera = m_rectifier.rectifiedCamera();
    }
}

bool CVideoStereoCamera::readFrame()
{
    cv::Mat frame, right;
    // Two devices: grab both first (close in time), then decode.
    if (!m_source->grab() || (m_source_right && !m_source_right->grab()))
    {
        return false;
    }
    if (!m_source->retrieve(frame) || frame.empty() ||
        (m_source_right && (!m_source_right->retrieve(right) || right.empty())))
    {
        return false;
    }
    if (m_params.grayscale)
    {
        frame = toGrey(frame);
        right = right.empty() ? right : toGrey(right);
    }
    if (m_source_right)
    {
        // Own copies: a backend may hand out its internal buffer.
        m_left = frame.clone();
        m_right = right.clone();
    }
    else
    {
        if (frame.cols % 2 != 0)
        {
            throw std::runtime_error(mrpt::format(
                "a side-by-side frame of odd width %d (left | right halves must be equal)",
                frame.cols));
        }
        const int w = frame.cols / 2;
        m_left = frame.colRange(0, w).clone();
        m_right = frame.colRange(w, frame.cols).clone();
    }
    ++m_read;
    return true;
}

std::string CVideoStereoCamera::endMessage() const
{
    return "CVideoStereoCamera '" + m_sensorLabel + "': " + toString(m_source->kind()) + " '" +
           m_params.source + "'" + (m_source_right ? " / '" + m_params.source_right + "'" : "");
}

void CVideoStereoCamera::doProcess()
{
    if (!m_source)
    {
        throw std::logic_error(
            "CVideoStereoCamera '" + m_sensorLabel + "': doProcess() before initialize()");
    }
    mrpt::Clock::time_point t_now = m_first_t;
    if (m_have_first)
    {
        m_have_first = false;  // read by initialize()
    }
    else
    {
        bool ok = false;
        try
        {
            ok = readFrame();
        }
        catch (const cv::Exception& e)
        {
            throw std::runtime_error(endMessage() + ": OpenCV: " + e.what());
        }
        t_now = mrpt::Clock::now();
        if (!ok)
        {
            const std::string after = " after " + std::to_string(m_delivered) + " frames";
            if (isLiveSource(m_source->kind()) ||
                (m_source_right && isLiveSource(m_source_right->kind())))
            {
                throw std::runtime_error(
                    endMessage() + ": the camera stopped delivering frames" + after +
                    " (unplugged?)");
            }
            throw EndOfStream(endMessage() + ": end of the stream" + after);
        }
    }
    const auto t = m_video_stamps
                       ? mrpt::Clock::fromDouble(
                             m_params.start_time + static_cast<double>(m_read - 1) / m_stamp_fps)
                       : t_now;
    appendObservation(convertFrame(t));
    ++m_delivered;
}

mrpt::obs::CObservationStereoImages::Ptr CVideoStereoCamera::convertFrame(mrpt::Clock::time_point t)
{
    const TParameters& p = m_params;
    cv::Mat left = m_left, right = m_right;
    if (left.size() != right.size() ||
        left.cols != static_cast<int>(m_output_camera.leftCamera.ncols) ||
        left.rows != static_cast<int>(m_output_camera.leftCamera.nrows))
    {
        throw std::runtime_error(mrpt::format(
            "%s: frame %zu has images of %dx%d and %dx%d, the calibration %ux%u",
            endMessage().c_str(), m_read - 1, left.cols, left.rows, right.cols, right.rows,
            m_output_camera.leftCamera.ncols, m_output_camera.leftCamera.nrows));
    }
    if (p.rectify && !m_rectifier.isIdentity())
    {
        cv::Mat rl, rr;
        m_rectifier.rectify(left, right, rl, rr);
        left = rl;
        right = rr;
    }
    const mrpt::poses::CPose3D T_robot_left(
        p.pose_x, p.pose_y, p.pose_z, p.pose_yaw_deg * DEG2RAD, p.pose_pitch_deg * DEG2RAD,
        p.pose_roll_deg * DEG2RAD);
    auto obs = mrpt::obs::CObservationStereoImages::Create();
    obs->timestamp = t;
    obs->sensorLabel = m_sensorLabel;
    obs->imageLeft = mrpt::img::CImage(left, mrpt::img::SHALLOW_COPY);
    obs->imageRight = mrpt::img::CImage(right, mrpt::img::SHALLOW_COPY);
    obs->hasImageRight = true;
    obs->hasImageDisparity = false;
    obs->setStereoCameraParams(m_output_camera);
    obs->cameraPose = mrpt::poses::CPose3DQuat(T_robot_left);
    return obs;
}

}  // namespace emslam::hwdrivers
