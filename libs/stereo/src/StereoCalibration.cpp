// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/poses/CPose3DQuat.h>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace emslam::stereo
{
namespace
{
[[noreturn]] void fail(const std::string& what, const std::string& problem)
{
    throw std::runtime_error(what + ": " + problem);
}

std::string fmt(double v)
{
    std::ostringstream s;
    s.precision(10);
    s << v;
    return s.str();
}
void validateCamera(const mrpt::img::TCamera& c, const std::string& what, const char* side)
{
    const std::string pre = std::string(side) + " camera: ";
    if (c.ncols == 0 || c.nrows == 0)
    {
        fail(
            what,
            pre + "zero image size " + std::to_string(c.ncols) + "x" + std::to_string(c.nrows));
    }
    // Generous physical ranges: a focal length of a million pixels, a
    // principal point a million pixels off the image.
    const auto intrinsics = pre + "fx = " + fmt(c.fx()) + ", fy = " + fmt(c.fy()) +
                            ", cx = " + fmt(c.cx()) + ", cy = " + fmt(c.cy());
    for (const double v : {c.fx(), c.fy(), c.cx(), c.cy()})
    {
        if (!std::isfinite(v))
        {
            fail(what, intrinsics + ": non-finite intrinsic parameter (NaN or inf)");
        }
    }
    if (!(c.fx() > 0.0 && c.fx() <= 1e6 && c.fy() > 0.0 && c.fy() <= 1e6))
    {
        fail(what, intrinsics + ": focal lengths fx, fy must be in (0, 1e6] px");
    }
    if (!(std::abs(c.cx()) <= 1e6 && std::abs(c.cy()) <= 1e6))
    {
        fail(what, intrinsics + ": principal point cx, cy must be within +-1e6 px");
    }
    for (const double v : c.dist)
    {
        if (!std::isfinite(v))
        {
            fail(what, pre + "non-finite distortion coefficient (dist)");
        }
    }
}

}  // namespace
mrpt::img::TStereoCamera loadStereoCameraFromConfig(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    const std::string what = "stereo calibration INI section prefix '" + section + "'";
    for (const char* suffix : {"_LEFT", "_RIGHT", "_LEFT2RIGHT_POSE"})
    {
        if (!cfg.sectionExists(section + suffix))
        {
            fail(what, "missing section [" + section + suffix + "]");
        }
    }
    mrpt::img::TStereoCamera cam;
    try
    {
        cam.loadFromConfigFile(section, cfg);
    }
    catch (const std::exception& e)
    {
        fail(
            what,
            "cannot be read (resolution, cx, cy, fx, fy, dist, distortion_model, "
            "pose_quaternion): " +
                emslam::util::shortExceptionMessage(e));
    }
    validateStereoCamera(cam, what);
    // saveToConfigFile() writes the quaternion with 6 decimals: make it unit again.
    auto& p = cam.rightCameraPose;
    const double qn = std::sqrt(p.qr * p.qr + p.qx * p.qx + p.qy * p.qy + p.qz * p.qz);
    p.qr /= qn;
    p.qx /= qn;
    p.qy /= qn;
    p.qz /= qn;
    return cam;
}

void validateStereoCamera(const mrpt::img::TStereoCamera& cam, const std::string& what)
{
    validateCamera(cam.leftCamera, what, "left");
    validateCamera(cam.rightCamera, what, "right");

    const auto& p = cam.rightCameraPose;
    for (const double v : {p.x, p.y, p.z, p.qr, p.qx, p.qy, p.qz})
    {
        if (!std::isfinite(v))
        {
            fail(what, "non-finite value (NaN or inf) in the right camera pose (pose_quaternion)");
        }
    }
    const double qn = std::sqrt(p.qr * p.qr + p.qx * p.qx + p.qy * p.qy + p.qz * p.qz);
    if (std::abs(qn - 1.0) > 1e-3)
    {
        fail(
            what,
            "right camera pose quaternion (pose_quaternion) is not unit (norm " + fmt(qn) + ")");
    }
    const double b = baselineOf(cam);
    if (!(b > 1e-9))
    {
        fail(what, "zero baseline (right camera at the left camera's position)");
    }
    // No stereo rig is a kilometre wide; depths f * b / d must stay finite.
    if (b > 1000)
    {
        fail(
            what,
            "baseline " + fmt(b) + " m (right camera pose, pose_quaternion) is not in (0, 1000] m");
    }
}

double baselineOf(const mrpt::img::TStereoCamera& cam)
{
    const auto& p = cam.rightCameraPose;
    return std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
}

}  // namespace emslam::stereo
