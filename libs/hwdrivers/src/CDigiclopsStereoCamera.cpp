// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/hwdrivers/CDigiclopsStereoCamera.h>
#include <emslam/stereo/RangeScanConversion.h>
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/util/ConfigVisitor.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>
#include <mrpt/math/CQuaternion.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <tuple>

IMPLEMENTS_GENERIC_SENSOR(CDigiclopsStereoCamera, emslam::hwdrivers)

namespace emslam::hwdrivers
{
namespace
{
constexpr double DEG2RAD = M_PI / 180.0;

std::uint64_t parseGuid(const std::string& s)
{
    try
    {
        std::size_t pos = 0;
        const auto v = std::stoull(s, &pos, 16);
        if (s.find_first_not_of(" \t", pos) == std::string::npos)
        {
            return v;
        }
    }
    catch (const std::exception&)
    {
    }
    throw std::invalid_argument(
        "CDigiclopsStereoCamera: 'camera_guid' must be a hexadecimal number, got '" + s + "'");
}

mrpt::poses::CPose3D readPoseQuaternion(
    const mrpt::config::CConfigFileBase& c, const std::string& section)
{
    if (!c.sectionExists(section))
    {
        throw std::invalid_argument("calibration section [" + section + "] is missing");
    }
    std::vector<double> v;
    c.read_vector(section, "pose_quaternion", std::vector<double>(), v, true);
    if (v.size() != 7)
    {
        throw std::invalid_argument(
            "[" + section + "] pose_quaternion must be [x y z qr qx qy qz] (7 numbers), got " +
            std::to_string(v.size()));
    }
    mrpt::math::CQuaternionDouble q(v[3], v[4], v[5], v[6]);
    q.normalize();
    return mrpt::poses::CPose3D(mrpt::poses::CPose3DQuat(v[0], v[1], v[2], q));
}

void writePoseQuaternion(
    mrpt::config::CConfigFileBase& c, const std::string& section, const mrpt::poses::CPose3D& p)
{
    const mrpt::poses::CPose3DQuat q(p);
    c.write(
        section, "pose_quaternion",
        mrpt::format(
            "[%.17g %.17g %.17g %.17g %.17g %.17g %.17g]", q.x(), q.y(), q.z(), q.quat().r(),
            q.quat().x(), q.quat().y(), q.quat().z()));
}

cv::Mat cameraMatrix(const mrpt::img::TCamera& c)
{
    return (cv::Mat_<double>(3, 3) << c.fx(), 0, c.cx(), 0, c.fy(), c.cy(), 0, 0, 1);
}
}  // namespace

PackedFrameFormat CDigiclopsStereoCamera::TParameters::frameFormat() const
{
    PackedFrameFormat f;
    f.layout = packedLayoutFromString(pixel_layout);
    f.width = stereo_camera.leftCamera.ncols;
    f.height = stereo_camera.leftCamera.nrows;
    f.planar_channels = static_cast<unsigned int>(std::max(planar_channels, 0));
    return f;
}

namespace
{
/** Every key of the sensor's own, once for load and save. */
void visit(CDigiclopsStereoCamera::TParameters& p, emslam::util::ConfigVisitor& v)
{
    // "0x..." so that the key reads as hexadecimal text, not as an int key.
    v.text(
        "camera_guid", p.camera_guid,
        [](std::uint64_t g) { return mrpt::format("0x%llx", static_cast<unsigned long long>(g)); },
        parseGuid);
    v.field("camera_index", p.camera_index);
    v.field("video_mode", p.video_mode);
    v.field("framerate", p.framerate);
    v.field("iso_speed", p.iso_speed);
    v.field("shutter", p.shutter);
    v.field("gain", p.gain);
    v.field("exposure", p.exposure);
    v.field("dma_buffers", p.dma_buffers);
    v.field("pixel_layout", p.pixel_layout);
    v.field("planar_channels", p.planar_channels);
    v.field("channel_left", p.channel_left);
    v.field("channel_right", p.channel_right);
    v.field("channel_third", p.channel_third);
    v.field("calibration_section", p.calibration_section);
    v.field("rectify", p.rectify);
    v.field("rectify_alpha", p.rectify_alpha);
    v.field("pose_x", p.pose_x);
    v.field("pose_y", p.pose_y);
    v.field("pose_z", p.pose_z);
    v.field("pose_yaw_deg", p.pose_yaw_deg);
    v.field("pose_pitch_deg", p.pose_pitch_deg);
    v.field("pose_roll_deg", p.pose_roll_deg);
    v.field("compute_range_scan", p.compute_range_scan);
    v.field("stereo_section", p.stereo_section);
}
}  // namespace

void CDigiclopsStereoCamera::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);

    const std::string& cs = calibration_section;
    try
    {
        stereo_camera = emslam::stereo::loadStereoCameraFromConfig(c, cs);
    }
    catch (const std::exception& e)
    {
        throw std::invalid_argument(
            "CDigiclopsStereoCamera, section " + s + ": calibration_section = '" + cs +
            "': " + emslam::util::shortExceptionMessage(e));
    }
    PackedLayout layout{};
    try
    {
        layout = packedLayoutFromString(pixel_layout);
    }
    catch (const std::exception& e)
    {
        throw std::invalid_argument(
            "CDigiclopsStereoCamera, section " + s + ": pixel_layout: " + e.what());
    }
    const bool three = layout == PackedLayout::PIXEL_INTERLEAVED_24 ||
                       (layout == PackedLayout::PLANAR_8 && planar_channels == 3);
    if (three)
    {
        if (!c.sectionExists(cs + "_THIRD"))
        {
            throw std::invalid_argument(
                "CDigiclopsStereoCamera [" + s +
                "]: a 3-image layout needs the third camera's "
                "calibration section [" +
                cs + "_THIRD]");
        }
        try
        {
            third_camera.loadFromConfigFile(cs + "_THIRD", c);
            T_left_third = readPoseQuaternion(c, cs + "_LEFT2THIRD_POSE");
        }
        catch (const std::exception& e)
        {
            throw std::invalid_argument(
                "CDigiclopsStereoCamera, section " + s + ": calibration_section = '" + cs +
                "' (third camera: resolution, fx, fy, cx, cy, dist, distortion_model; " + cs +
                "_LEFT2THIRD_POSE: pose_quaternion): " + emslam::util::shortExceptionMessage(e));
        }
    }
    // An old config names the former section, which emslam's apps read as
    // [StereoMatcher] (slam::configRenames()); the stock grabber keeps [Stereo].
    if (stereo_section == "Stereo" && !c.sectionExists("Stereo") &&
        c.sectionExists("StereoMatcher"))
    {
        stereo_section = "StereoMatcher";
    }
    // Also checked when unused, so a bad value cannot wait for compute_range_scan.
    if (compute_range_scan || c.sectionExists(stereo_section))
    {
        stereo.loadFromConfigFile(c, stereo_section);
    }
    validate();
}

void CDigiclopsStereoCamera::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
    stereo_camera.saveToConfigFile(calibration_section, c);
    if (frameFormat().channels() == 3)
    {
        third_camera.saveToConfigFile(calibration_section + "_THIRD", c);
        writePoseQuaternion(c, calibration_section + "_LEFT2THIRD_POSE", T_left_third);
    }
    if (compute_range_scan)
    {
        stereo.saveToConfigFile(c, stereo_section);
    }
}

void CDigiclopsStereoCamera::TParameters::validate() const
{
    auto bad = [](const std::string& key, const std::string& why)
    { throw std::invalid_argument("CDigiclopsStereoCamera: '" + key + "' " + why); };
    const PackedLayout layout = packedLayoutFromString(pixel_layout);  // throws on unknown
    if (camera_index < 0)
    {
        bad("camera_index", "must be >= 0");
    }
    if (!(framerate > 0 && framerate <= 1000))
    {
        bad("framerate", "= " + std::to_string(framerate) + " must be in (0, 1000] fps");
    }
    if (iso_speed != 100 && iso_speed != 200 && iso_speed != 400 && iso_speed != 800)
    {
        bad("iso_speed", "must be 100, 200, 400 or 800, not " + std::to_string(iso_speed));
    }
    if (dma_buffers < 1)
    {
        bad("dma_buffers", "must be >= 1");
    }
    if (layout == PackedLayout::PLANAR_8 && planar_channels != 2 && planar_channels != 3)
    {
        bad("planar_channels", "must be 2 or 3");
    }
    const int n = static_cast<int>(frameFormat().channels());
    auto checkChannel = [&](const char* key, int ch)
    {
        if (ch < 0 || ch >= n)
        {
            bad(key, "is " + std::to_string(ch) + ", but a " + pixel_layout +
                         " frame has channels 0.." + std::to_string(n - 1));
        }
    };
    checkChannel("channel_left", channel_left);
    checkChannel("channel_right", channel_right);
    if (channel_left == channel_right)
    {
        bad("channel_right", "must differ from channel_left");
    }
    if (n == 3)
    {
        checkChannel("channel_third", channel_third);
        if (channel_third == channel_left || channel_third == channel_right)
        {
            bad("channel_third", "must differ from channel_left and channel_right");
        }
    }
    for (const auto& [key, v, limit] :
         {std::tuple{"pose_x", pose_x, 1e4}, std::tuple{"pose_y", pose_y, 1e4},
          std::tuple{"pose_z", pose_z, 1e4}, std::tuple{"pose_yaw_deg", pose_yaw_deg, 360.0},
          std::tuple{"pose_pitch_deg", pose_pitch_deg, 360.0},
          std::tuple{"pose_roll_deg", pose_roll_deg, 360.0}})
    {
        if (!(std::abs(v) <= limit))
        {
            bad(key, "= " + std::to_string(v) + " must be in [-" + mrpt::format("%g", limit) +
                         ", " + mrpt::format("%g", limit) + "]");
        }
    }
    if (!(rectify_alpha >= 0 && rectify_alpha <= 1))
    {
        bad("rectify_alpha", "= " + std::to_string(rectify_alpha) + " must be in [0, 1]");
    }
    emslam::stereo::validateStereoCamera(stereo_camera, "CDigiclopsStereoCamera calibration");
    if (stereo_camera.rightCamera.ncols != stereo_camera.leftCamera.ncols ||
        stereo_camera.rightCamera.nrows != stereo_camera.leftCamera.nrows)
    {
        bad(calibration_section, "left and right cameras must have the same resolution");
    }
    if (n == 3 && (third_camera.ncols != stereo_camera.leftCamera.ncols ||
                   third_camera.nrows != stereo_camera.leftCamera.nrows ||
                   !(third_camera.fx() > 0 && third_camera.fx() <= 1e6) ||
                   !(third_camera.fy() > 0 && third_camera.fy() <= 1e6) ||
                   !(std::abs(third_camera.cx()) <= 1e6) || !(std::abs(third_camera.cy()) <= 1e6)))
    {
        bad(calibration_section + "_THIRD",
            "must have the left camera's resolution, focal lengths in (0, 1e6] px and a "
            "principal point in [-1e6, 1e6] px (resolution, fx, fy, cx, cy)");
    }
}

void CDigiclopsStereoCamera::loadConfig_sensorSpecific(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    TParameters p;
    p.loadFromConfigFile(cfg, section);
    setParameters(p);
}

void CDigiclopsStereoCamera::setParameters(const TParameters& p)
{
    p.validate();
    m_params = p;
    m_third_map_x.release();
    m_third_map_y.release();
    m_front_end.reset();
    if (m_params.compute_range_scan)
    {
        m_front_end = std::make_unique<emslam::stereo::StereoFrontEnd>(m_params.stereo);
    }
}

std::vector<mrpt::serialization::CSerializable::Ptr> CDigiclopsStereoCamera::convertFrame(
    const std::uint8_t* data, std::size_t size, mrpt::Clock::time_point t)
{
    const TParameters& p = m_params;
    const PackedFrameFormat fmt = p.frameFormat();
    std::vector<cv::Mat> imgs = deinterleave(data, size, fmt);

    cv::Mat left = imgs[static_cast<std::size_t>(p.channel_left)];
    cv::Mat right = imgs[static_cast<std::size_t>(p.channel_right)];
    mrpt::img::TStereoCamera calib = p.stereo_camera;
    if (p.rectify)
    {
        m_rectifier.setCalibration(p.stereo_camera, p.rectify_alpha);
        if (!m_rectifier.isIdentity())
        {
            cv::Mat rl, rr;
            m_rectifier.rectify(left, right, rl, rr);
            left = rl;
            right = rr;
        }
        calib = m_rectifier.rectifiedCamera();
    }
    const mrpt::poses::CPose3D T_robot_left(
        p.pose_x, p.pose_y, p.pose_z, p.pose_yaw_deg * DEG2RAD, p.pose_pitch_deg * DEG2RAD,
        p.pose_roll_deg * DEG2RAD);

    std::vector<mrpt::serialization::CSerializable::Ptr> out;
    auto stereo_obs = mrpt::obs::CObservationStereoImages::Create();
    stereo_obs->timestamp = t;
    stereo_obs->sensorLabel = m_sensorLabel;
    stereo_obs->imageLeft = mrpt::img::CImage(left, mrpt::img::SHALLOW_COPY);
    stereo_obs->imageRight = mrpt::img::CImage(right, mrpt::img::SHALLOW_COPY);
    stereo_obs->hasImageRight = true;
    stereo_obs->setStereoCameraParams(calib);
    stereo_obs->cameraPose = mrpt::poses::CPose3DQuat(T_robot_left);
    out.push_back(stereo_obs);

    if (fmt.channels() == 3)
    {
        cv::Mat third = imgs[static_cast<std::size_t>(p.channel_third)];
        mrpt::img::TCamera cam = p.third_camera;
        if (p.rectify && cam.distortion != mrpt::img::DistortionModel::none)
        {
            if (m_third_map_x.empty())
            {
                std::vector<double> d(cam.dist.begin(), cam.dist.begin() + 5);
                const cv::Mat K = cameraMatrix(cam);
                cv::initUndistortRectifyMap(
                    K, d, cv::Mat(), K, third.size(), CV_32FC1, m_third_map_x, m_third_map_y);
            }
            cv::Mat undist;
            cv::remap(third, undist, m_third_map_x, m_third_map_y, cv::INTER_LINEAR);
            third = undist;
            cam.distortion = mrpt::img::DistortionModel::none;
            cam.dist.fill(0);
        }
        auto img_obs = mrpt::obs::CObservationImage::Create();
        img_obs->timestamp = t;
        img_obs->sensorLabel = m_sensorLabel + "_THIRD";
        img_obs->image = mrpt::img::CImage(third, mrpt::img::SHALLOW_COPY);
        img_obs->cameraParams = cam;
        img_obs->cameraPose = T_robot_left + p.T_left_third;
        out.push_back(img_obs);
    }
    if (m_front_end)
    {
        const auto frame = m_front_end->process(*stereo_obs);
        auto scan = emslam::stereo::toRangeScan(frame);
        scan->timestamp = t;
        scan->sensorLabel = m_sensorLabel + "_3D";
        // MRPT's range-scan frame (+X forward, +Y left, +Z up) in the optical left frame.
        const mrpt::poses::CPose3D T_sensor_optical(0, 0, 0, -M_PI / 2, 0, -M_PI / 2);
        scan->setSensorPose(T_robot_left + (-T_sensor_optical));
        out.push_back(scan);
    }
    return out;
}

void CDigiclopsStereoCamera::initialize()
{
    m_state = ssInitializing;
    try
    {
        openDevice();
    }
    catch (...)
    {
        m_state = ssError;
        throw;
    }
    m_state = ssWorking;
}

void CDigiclopsStereoCamera::doProcess()
{
    if (!m_dev)
    {
        throw std::logic_error(
            "CDigiclopsStereoCamera '" + m_sensorLabel + "': doProcess() before initialize()");
    }
    grabFrame();
}

}  // namespace emslam::hwdrivers
