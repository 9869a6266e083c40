// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/stereo/StereoRectifier.h>

#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <string>

namespace emslam::stereo
{
namespace
{
constexpr double REL_TOL = 1e-6;

bool nearlyEqual(double a, double b)
{
    const double scale = std::max({std::abs(a), std::abs(b), 1.0});
    return std::abs(a - b) <= REL_TOL * scale;
}

bool hasDistortion(const mrpt::img::TCamera& c)
{
    if (c.distortion == mrpt::img::DistortionModel::none)
    {
        return false;
    }
    // Coefficients act on normalised coordinates: an absolute tolerance is the
    // meaningful one (1e-6 moves an image corner by far less than a pixel).
    return std::any_of(
        c.dist.begin(), c.dist.end(), [](double k) { return std::abs(k) > REL_TOL; });
}

cv::Mat cameraMatrix(const mrpt::img::TCamera& c)
{
    cv::Mat k = cv::Mat::eye(3, 3, CV_64F);
    k.at<double>(0, 0) = c.fx();
    k.at<double>(1, 1) = c.fy();
    k.at<double>(0, 2) = c.cx();
    k.at<double>(1, 2) = c.cy();
    return k;
}

/** MRPT's plumb_bob dist[] is OpenCV's order (k1 k2 p1 p2 k3 k4 k5 k6). */
cv::Mat distortionVector(const mrpt::img::TCamera& c)
{
    switch (c.distortion)
    {
        case mrpt::img::DistortionModel::none:
            return cv::Mat::zeros(1, 5, CV_64F);
        case mrpt::img::DistortionModel::plumb_bob:
        {
            const bool rational = c.k4() != 0.0 || c.k5() != 0.0 || c.k6() != 0.0;
            cv::Mat d(1, rational ? 8 : 5, CV_64F);
            for (int i = 0; i < d.cols; i++)
            {
                d.at<double>(0, i) = c.dist[static_cast<std::size_t>(i)];
            }
            return d;
        }
        default:
            throw std::runtime_error(
                "StereoRectifier: unsupported distortion model (only none and plumb_bob)");
    }
}

bool samePose(const mrpt::math::TPose3DQuat& a, const mrpt::math::TPose3DQuat& b)
{
    return a.x == b.x && a.y == b.y && a.z == b.z && a.qr == b.qr && a.qx == b.qx && a.qy == b.qy &&
           a.qz == b.qz;
}

mrpt::img::TCamera pinholeFromProjection(const cv::Mat& p, const mrpt::img::TCamera& raw)
{
    mrpt::img::TCamera c = raw;  // keeps size and name
    c.setIntrinsicParamsFromValues(
        p.at<double>(0, 0), p.at<double>(1, 1), p.at<double>(0, 2), p.at<double>(1, 2));
    c.distortion = mrpt::img::DistortionModel::none;
    c.dist.fill(0.0);
    return c;
}

void checkImage(const cv::Mat& im, const mrpt::img::TCamera& c, const char* side)
{
    if (im.empty() || im.cols != static_cast<int>(c.ncols) || im.rows != static_cast<int>(c.nrows))
    {
        std::ostringstream s;
        s << "StereoRectifier::rectify: " << side << " image is " << im.cols << "x" << im.rows
          << ", the calibration expects " << c.ncols << "x" << c.nrows;
        throw std::runtime_error(s.str());
    }
}

/** remap() cannot run in place: go through a temporary when out aliases in. */
void remapInto(const cv::Mat& in, cv::Mat& out, const cv::Mat& map1, const cv::Mat& map2)
{
    if (out.data != nullptr && out.data == in.data)
    {
        cv::Mat tmp;
        cv::remap(in, tmp, map1, map2, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
        out = tmp;
        return;
    }
    cv::remap(in, out, map1, map2, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
}

}  // namespace

StereoRectifier::StereoRectifier(const mrpt::img::TStereoCamera& raw, double alpha)
{
    setCalibration(raw, alpha);
}

bool StereoRectifier::isAlreadyRectified(const mrpt::img::TStereoCamera& cam)
{
    const auto& l = cam.leftCamera;
    const auto& r = cam.rightCamera;
    if (hasDistortion(l) || hasDistortion(r) || l.ncols != r.ncols || l.nrows != r.nrows)
    {
        return false;
    }
    // cx may differ: rows stay aligned and the offset only shifts every
    // disparity by a constant (cropped pairs such as Middlebury's).
    if (!nearlyEqual(l.fx(), r.fx()) || !nearlyEqual(l.fy(), r.fy()) ||
        !nearlyEqual(l.cy(), r.cy()))
    {
        return false;
    }
    const auto& p = cam.rightCameraPose;
    if (!(p.x > 0.0) || std::abs(p.y) > REL_TOL * p.x || std::abs(p.z) > REL_TOL * p.x)
    {
        return false;
    }
    const double qn = std::sqrt(p.qr * p.qr + p.qx * p.qx + p.qy * p.qy + p.qz * p.qz);
    const double q_vec = std::sqrt(p.qx * p.qx + p.qy * p.qy + p.qz * p.qz);
    return qn > 0.0 && q_vec <= REL_TOL * qn;
}

void StereoRectifier::setCalibration(const mrpt::img::TStereoCamera& raw, double alpha)
{
    if (m_initialized && alpha == m_alpha && raw.leftCamera == m_raw.leftCamera &&
        raw.rightCamera == m_raw.rightCamera &&
        samePose(raw.rightCameraPose, m_raw.rightCameraPose))
    {
        return;  // the cached maps are still valid
    }
    validateStereoCamera(raw, "StereoRectifier input calibration");
    if (raw.leftCamera.ncols != raw.rightCamera.ncols ||
        raw.leftCamera.nrows != raw.rightCamera.nrows)
    {
        throw std::runtime_error(
            "StereoRectifier: left and right cameras have different image sizes");
    }

    // Everything is computed into locals and committed at the end, so a throw
    // leaves the previous state intact.
    mrpt::img::TStereoCamera rectified = raw;
    cv::Mat map_lx, map_ly, map_rx, map_ry;
    const bool identity = isAlreadyRectified(raw);
    if (identity)
    {
        // Tidy copy of the input: shared fx, fy, cy (the right cx is kept), pure +x translation.
        cv::Mat k_right = cameraMatrix(raw.leftCamera);
        k_right.at<double>(0, 2) = raw.rightCamera.cx();
        rectified.leftCamera = pinholeFromProjection(cameraMatrix(raw.leftCamera), raw.leftCamera);
        rectified.rightCamera = pinholeFromProjection(k_right, raw.rightCamera);
        rectified.rightCameraPose =
            mrpt::math::TPose3DQuat(raw.rightCameraPose.x, 0, 0, 1, 0, 0, 0);
    }
    else
    {
        // MRPT gives T_left_right (right camera pose in the left frame, so
        // X_l = R_lr X_r + t_lr). OpenCV wants X_r = R X_l + T: the inverse,
        // R = R_lr^T, T = -R_lr^T t_lr.
        const mrpt::poses::CPose3D T_left_right(mrpt::poses::CPose3DQuat(raw.rightCameraPose));
        const auto& R_lr = T_left_right.getRotationMatrix();
        const double t_lr[3] = {T_left_right.x(), T_left_right.y(), T_left_right.z()};
        cv::Mat R(3, 3, CV_64F), T(3, 1, CV_64F);
        for (int i = 0; i < 3; i++)
        {
            double t = 0;
            for (int j = 0; j < 3; j++)
            {
                R.at<double>(i, j) = R_lr(j, i);
                t -= R_lr(j, i) * t_lr[j];
            }
            T.at<double>(i, 0) = t;
        }

        const cv::Size size(
            static_cast<int>(raw.leftCamera.ncols), static_cast<int>(raw.leftCamera.nrows));
        const cv::Mat K1 = cameraMatrix(raw.leftCamera), D1 = distortionVector(raw.leftCamera);
        const cv::Mat K2 = cameraMatrix(raw.rightCamera), D2 = distortionVector(raw.rightCamera);
        cv::Mat R1, R2, P1, P2, Q;
        cv::stereoRectify(
            K1, D1, K2, D2, size, R, T, R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, alpha, size);

        // P2 = [f 0 cx -f*b; 0 f cy 0; 0 0 1 0] for a horizontal pair with the
        // right camera at +x; anything else is a calibration we cannot use.
        const double f = P2.at<double>(0, 0);
        const double baseline = -P2.at<double>(0, 3) / f;
        if (std::abs(P2.at<double>(1, 3)) > std::abs(P2.at<double>(0, 3)))
        {
            throw std::runtime_error(
                "StereoRectifier: vertical stereo pair (right camera displaced mostly along y) "
                "is not supported");
        }
        if (!(baseline > 0.0) || !std::isfinite(baseline))
        {
            std::ostringstream s;
            s << "StereoRectifier: rectified baseline " << baseline
              << " m is not positive: the right camera is not to the right of the left one "
                 "(check rightCameraPose, which must be the right camera's pose in the left "
                 "frame)";
            throw std::runtime_error(s.str());
        }

        cv::initUndistortRectifyMap(K1, D1, R1, P1, size, CV_16SC2, map_lx, map_ly);
        cv::initUndistortRectifyMap(K2, D2, R2, P2, size, CV_16SC2, map_rx, map_ry);

        rectified.leftCamera = pinholeFromProjection(P1, raw.leftCamera);
        rectified.rightCamera = pinholeFromProjection(P1, raw.rightCamera);
        rectified.rightCameraPose = mrpt::math::TPose3DQuat(baseline, 0, 0, 1, 0, 0, 0);
    }

    m_raw = raw;
    m_rectified = rectified;
    m_alpha = alpha;
    m_identity = identity;
    m_map_left_x = map_lx;
    m_map_left_y = map_ly;
    m_map_right_x = map_rx;
    m_map_right_y = map_ry;
    m_initialized = true;
}

void StereoRectifier::rectify(
    const cv::Mat& raw_left,
    const cv::Mat& raw_right,
    cv::Mat& rect_left,
    cv::Mat& rect_right) const
{
    if (!m_initialized)
    {
        throw std::runtime_error("StereoRectifier::rectify: no calibration set");
    }
    checkImage(raw_left, m_raw.leftCamera, "left");
    checkImage(raw_right, m_raw.rightCamera, "right");
    if (m_identity)
    {
        // Shallow: the outputs share the inputs' pixels (no copy needed).
        rect_left = raw_left;
        rect_right = raw_right;
        return;
    }
    remapInto(raw_left, rect_left, m_map_left_x, m_map_left_y);
    remapInto(raw_right, rect_right, m_map_right_x, m_map_right_y);
}

}  // namespace emslam::stereo
