// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/CalibrationFiles.h>
#include <emslam/io/DataFile.h>
#include <emslam/io/EurocSensorYaml.h>
#include <emslam/io/IniFile.h>
#include <emslam/io/TextParsing.h>
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/format.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace emslam::io
{
namespace
{
[[noreturn]] void fail(const std::string& what, const std::string& problem)
{
    throw std::runtime_error(what + ": " + problem);
}

void requireFile(const std::string& file, const std::string& what)
{
    if (std::error_code ec; !std::filesystem::is_regular_file(file, ec))
    {
        fail(what, "file not found");
    }
}

/** Ten significant digits, as the stereo library's calibration messages. */
std::string fmt(double v)
{
    return mrpt::format("%.10g", v);
}

// ---------------------------------------------------------------------------
// KITTI
// ---------------------------------------------------------------------------
/** One `Pn:` line: 3x4 row-major projection matrix and where it came from. */
struct KittiProjection
{
    std::array<double, 12> p{};
    std::size_t line_no{0};
};

std::array<double, 12> parseKittiMatrix(
    std::string_view rest, const std::string& what, const std::string& key, std::size_t line_no)
{
    std::array<double, 12> p{};
    std::size_t n = 0;
    const std::string where = "line " + std::to_string(line_no) + " (" + key + ")";
    std::size_t pos = 0;
    while (true)
    {
        pos = rest.find_first_not_of(" \t", pos);
        if (pos == std::string_view::npos)
        {
            break;
        }
        const auto end = std::min(rest.find_first_of(" \t", pos), rest.size());
        const std::string_view tok = rest.substr(pos, end - pos);
        pos = end;
        double v = 0;
        if (!parseDouble(tok, v))
        {
            fail(what, where + ": " + quotedExcerpt(tok) + " is not a number");
        }
        if (!std::isfinite(v))
        {
            fail(what, where + ": non-finite value " + quotedExcerpt(tok));
        }
        if (n == p.size())
        {
            fail(what, where + ": more than 12 numbers");
        }
        p[n++] = v;
    }
    if (n != p.size())
    {
        fail(what, where + ": " + std::to_string(n) + " numbers, expected 12 (3x4 row-major)");
    }
    // A rectified KITTI projection is K [I | t]: its last row must be (0 0 1 *).
    if (p[8] != 0.0 || p[9] != 0.0 || std::abs(p[10] - 1.0) > 1e-9)
    {
        fail(what, where + ": not a rectified projection K[I|t] (third row must be 0 0 1 t)");
    }
    return p;
}

mrpt::img::TCamera cameraFromProjection(
    const std::array<double, 12>& p, unsigned int w, unsigned int h)
{
    mrpt::img::TCamera c;
    c.ncols = w;
    c.nrows = h;
    c.setIntrinsicParamsFromValues(p[0], p[5], p[2], p[6]);
    c.distortion = mrpt::img::DistortionModel::none;
    c.dist.fill(0.0);
    return c;
}

// ---------------------------------------------------------------------------
// EuRoC (ASL sensor.yaml)
// ---------------------------------------------------------------------------
/** T_BS (4x4, row-major) as a rigid pose. The yaml numbers are rounded, so the
 * rotation is re-orthonormalised (SVD) after checking it is close to one. */
mrpt::poses::CPose3D readYamlPose(const EurocSensorYaml& yaml, const std::string& what)
{
    if (!yaml.has("T_BS"))
    {
        fail(what, "missing key 'T_BS'");
    }
    if (!yaml.isMap("T_BS"))
    {
        fail(
            what, "line " + std::to_string(yaml.lineOf("T_BS")) +
                      ": key 'T_BS' must be a map with 'rows', 'cols' and 'data'");
    }
    for (const char* dim : {"T_BS.rows", "T_BS.cols"})
    {
        if (yaml.has(dim) && yaml.number(dim) != 4.0)
        {
            fail(
                what, "line " + std::to_string(yaml.lineOf(dim)) + ": key '" + dim + "' must be 4");
        }
    }
    const std::vector<double> m = yaml.numbers("T_BS.data", {16});
    const std::string where = "line " + std::to_string(yaml.lineOf("T_BS.data")) + ": ";
    if (m[12] != 0.0 || m[13] != 0.0 || m[14] != 0.0 || m[15] != 1.0)
    {
        fail(what, where + "key 'T_BS.data': last row must be 0 0 0 1");
    }
    Eigen::Matrix3d r;
    r << m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10];
    if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4 ||
        r.determinant() <= 0.0)
    {
        fail(what, where + "key 'T_BS.data': the 3x3 block is not a rotation matrix");
    }
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d r_ortho = svd.matrixU() * svd.matrixV().transpose();

    mrpt::math::CMatrixDouble44 h = mrpt::math::CMatrixDouble44::Identity();
    for (int i = 0; i < 3; i++)
    {
        for (int j = 0; j < 3; j++)
        {
            h(i, j) = r_ortho(i, j);
        }
        h(i, 3) = m[4 * static_cast<std::size_t>(i) + 3];
    }
    return mrpt::poses::CPose3D(h);
}

/** The scalar `key` if present, as text. */
std::optional<std::string> optionalText(const EurocSensorYaml& yaml, const std::string& key)
{
    if (!yaml.has(key))
    {
        return std::nullopt;
    }
    return yaml.text(key);
}

/** Reads one EuRoC camera; also returns its pose in the body frame (T_body_cam). */
mrpt::img::TCamera readEurocCamera(const std::string& file, mrpt::poses::CPose3D& T_body_cam)
{
    const std::string what = "EuRoC sensor.yaml '" + file + "'";
    requireFile(file, what);
    // Our own strict reader: OpenCV 4.6's YAML parser hangs or overflows its
    // stack on some malformed files.
    const EurocSensorYaml yaml = EurocSensorYaml::load(file);

    if (const auto type = optionalText(yaml, "sensor_type"); type && *type != "camera")
    {
        fail(
            what, "line " + std::to_string(yaml.lineOf("sensor_type")) + ": sensor_type is " +
                      quotedExcerpt(*type) + ", expected 'camera'");
    }
    if (const auto model = optionalText(yaml, "camera_model"); model && *model != "pinhole")
    {
        fail(
            what, "line " + std::to_string(yaml.lineOf("camera_model")) +
                      ": unsupported camera_model " + quotedExcerpt(*model) + " (only 'pinhole')");
    }

    const auto res = yaml.numbers("resolution", {2});
    for (const double v : res)
    {
        if (v < 1.0 || v != std::floor(v) || v > 1e6)
        {
            fail(
                what, "line " + std::to_string(yaml.lineOf("resolution")) +
                          ": key 'resolution' must hold two positive integers [width, height]");
        }
    }
    const auto k = yaml.numbers("intrinsics", {4});

    const std::string model = yaml.text("distortion_model");
    if (model != "radial-tangential" && model != "radtan" && model != "plumb_bob")
    {
        fail(
            what, "line " + std::to_string(yaml.lineOf("distortion_model")) +
                      ": unsupported distortion_model " + quotedExcerpt(model) +
                      " (only radial-tangential)");
    }
    const auto d = yaml.numbers("distortion_coefficients", {4, 5});

    mrpt::img::TCamera cam;
    cam.ncols = static_cast<uint32_t>(res[0]);
    cam.nrows = static_cast<uint32_t>(res[1]);
    cam.setIntrinsicParamsFromValues(k[0], k[1], k[2], k[3]);
    cam.setDistortionPlumbBob(d[0], d[1], d[2], d[3], d.size() > 4 ? d[4] : 0.0);

    T_body_cam = readYamlPose(yaml, what);
    return cam;
}

}  // namespace

// ---------------------------------------------------------------------------
mrpt::img::TStereoCamera loadKittiCalibration(
    const std::string& calib_txt, unsigned int image_width, unsigned int image_height)
{
    const std::string what = "KITTI calib.txt '" + calib_txt + "'";
    requireFile(calib_txt, what);
    if (image_width == 0 || image_height == 0)
    {
        fail(
            what, "image size must be given (got " + std::to_string(image_width) + "x" +
                      std::to_string(image_height) + ")");
    }
    auto in = openTextFile(calib_txt, "KITTI calib.txt");

    std::optional<KittiProjection> p0, p1;
    std::string line;
    std::size_t line_no = 0;
    while (readBoundedLine(in, line, calib_txt, line_no + 1))
    {
        line_no++;
        const std::string_view l = trimmed(line);  // also drops a CR of CRLF files
        const auto colon = l.find(':');
        if (colon == std::string_view::npos)
        {
            continue;
        }
        const std::string key(trimmed(l.substr(0, colon)));
        if (key != "P0" && key != "P1")
        {
            continue;  // P2, P3, Tr, ... are not needed
        }
        auto& slot = key == "P0" ? p0 : p1;
        if (slot)
        {
            fail(
                what, "line " + std::to_string(line_no) + ": duplicate " + key +
                          " (first at line " + std::to_string(slot->line_no) + ")");
        }
        slot = KittiProjection{parseKittiMatrix(l.substr(colon + 1), what, key, line_no), line_no};
    }
    if (!p0)
    {
        fail(what, "missing 'P0:' line (left camera projection)");
    }
    if (!p1)
    {
        fail(what, "missing 'P1:' line (right camera projection)");
    }

    mrpt::img::TStereoCamera cam;
    cam.leftCamera = cameraFromProjection(p0->p, image_width, image_height);
    cam.rightCamera = cameraFromProjection(p1->p, image_width, image_height);
    for (const auto* pc : {&*p0, &*p1})
    {
        if (pc->p[0] <= 0.0)
        {
            fail(
                what, "line " + std::to_string(pc->line_no) + ": non-positive focal length " +
                          fmt(pc->p[0]));
        }
    }
    // P = K [I | t] with t = (-x_cam * fx, 0, 0): positions along the rectified x
    // axis are -P[0,3]/fx. P0[0,3] is 0 in KITTI, so this is -P1[0,3]/fx there.
    const double x_left = -p0->p[3] / p0->p[0];
    const double x_right = -p1->p[3] / p1->p[0];
    const double baseline = x_right - x_left;
    if (!(baseline > 0.0))
    {
        fail(
            what, "line " + std::to_string(p1->line_no) +
                      ": non-positive baseline -P1[0,3]/fx = " + fmt(baseline) + " m");
    }
    cam.rightCameraPose = mrpt::math::TPose3DQuat(baseline, 0, 0, 1, 0, 0, 0);
    stereo::validateStereoCamera(cam, what);
    return cam;
}

mrpt::img::TStereoCamera loadEurocCalibration(
    const std::string& cam0_sensor_yaml, const std::string& cam1_sensor_yaml)
{
    mrpt::poses::CPose3D T_body_left, T_body_right;
    mrpt::img::TStereoCamera cam;
    cam.leftCamera = readEurocCamera(cam0_sensor_yaml, T_body_left);
    cam.rightCamera = readEurocCamera(cam1_sensor_yaml, T_body_right);

    // a - b is MRPT's inverse composition b^-1 * a: T_left_right = inv(T_body_left) * T_body_right.
    const mrpt::poses::CPose3D T_left_right = T_body_right - T_body_left;
    cam.rightCameraPose = mrpt::poses::CPose3DQuat(T_left_right).asTPose();

    stereo::validateStereoCamera(
        cam, "EuRoC calibration '" + cam0_sensor_yaml + "' + '" + cam1_sensor_yaml + "'");
    return cam;
}

mrpt::img::TStereoCamera loadStereoCameraFromIniFile(
    const std::string& ini_file, const std::string& section)
{
    const std::string what = "stereo calibration INI '" + ini_file + "'";
    requireFile(ini_file, what);
    const mrpt::config::CConfigFileMemory cfg(readIniFile(ini_file, "stereo calibration INI"));
    try
    {
        return emslam::stereo::loadStereoCameraFromConfig(cfg, section);
    }
    catch (const std::exception& e)
    {
        fail(what, e.what());
    }
}

}  // namespace emslam::io
