// SPDX-License-Identifier: BSD-3-Clause
// A camera tilted in a corridor (floor, ceiling, one wall), its disparity
// rendered exactly plus noise: the up it measures against the true one.
#include "SyntheticStereo.h"

#include <emslam/stereo/VerticalFromPlanes.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/poses/CPose3D.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

using emslam::stereo::StereoFrame;
using emslam::stereo::VerticalFromPlanes;
using mrpt::math::TVector3D;

namespace
{
constexpr double F = 200, BASELINE = 0.1;

/** The disparity of a corridor (world y down: floor 1.6 m below the
 * camera, ceiling 1.2 m above, a wall 1.5 m to the right; `ramp`: the floor
 * rises by this slope [rad] ahead) seen by a camera turned by `pose`. */
StereoFrame corridor(const mrpt::poses::CPose3D& pose, double noise_px, double ramp = 0)
{
    StereoFrame f;
    f.camera = emslam::test::idealStereoCamera(320, 240, F, BASELINE);
    f.disparity = cv::Mat(240, 320, CV_32FC1, cv::Scalar(0));
    f.valid = cv::Mat(240, 320, CV_8UC1, cv::Scalar(0));
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, noise_px);
    const auto& R = pose.getRotationMatrix();
    const double cx = f.camera.leftCamera.cx(), cy = f.camera.leftCamera.cy();
    for (int v = 0; v < 240; ++v)
    {
        for (int u = 0; u < 320; ++u)
        {
            const double rc[3] = {(u - cx) / F, (v - cy) / F, 1.0};
            double rw[3];
            for (int a = 0; a < 3; ++a)
            {
                rw[a] = R(a, 0) * rc[0] + R(a, 1) * rc[1] + R(a, 2) * rc[2];
            }
            // Distance along the ray (z = 1 in the camera) to each plane.
            double t = 1e9;
            // Floor: y = 1.6 - tan(ramp) z.
            const double floor_den = rw[1] + std::tan(ramp) * rw[2];
            if (floor_den > 1e-9)
            {
                t = std::min(t, 1.6 / floor_den);
            }
            if (rw[1] < -1e-9)
            {
                t = std::min(t, -1.2 / rw[1]);
            }
            if (rw[0] > 1e-9)
            {
                t = std::min(t, 1.5 / rw[0]);
            }
            if (t > 30)
            {
                continue;
            }
            f.disparity.at<float>(v, u) = static_cast<float>(F * BASELINE / t + noise(rng));
            f.valid.at<uint8_t>(v, u) = 255;
        }
    }
    return f;
}

TVector3D trueUp(const mrpt::poses::CPose3D& pose)
{
    const auto& R = pose.getRotationMatrix();
    return {-R(1, 0), -R(1, 1), -R(1, 2)};  // Rᵀ (0, -1, 0)
}

double angleDeg(const TVector3D& a, const TVector3D& b)
{
    const double c = (a.x * b.x + a.y * b.y + a.z * b.z) / (a.norm() * b.norm());
    return mrpt::RAD2DEG(std::acos(std::min(1.0, c)));
}
}  // namespace

TEST(VerticalFromPlanes, aTiltedCameraFindsItsUpWithinItsOwnUncertainty)
{
    // Looking 10 degrees down, rolled by 3; predicted up 5 degrees off.
    const mrpt::poses::CPose3D pose(0, 0, 0, mrpt::DEG2RAD(3.0), 0, mrpt::DEG2RAD(-10.0));
    const StereoFrame f = corridor(pose, 0.05);
    const TVector3D truth = trueUp(pose);
    const mrpt::poses::CPose3D off(0, 0, 0, mrpt::DEG2RAD(3.0), 0, mrpt::DEG2RAD(-15.0));
    const VerticalFromPlanes vfp{VerticalFromPlanes::TParameters{}};
    const auto m = vfp.measure(f, trueUp(off));
    ASSERT_TRUE(m.has_value());
    const double err = angleDeg(m->up, truth);
    const double sigma_deg =
        mrpt::RAD2DEG(std::sqrt(m->covariance(0, 0) + m->covariance(1, 1) + m->covariance(2, 2)));
    std::printf(
        "tilted camera: %zu patches, error %.4f deg, sigma %.4f deg, dispersion %.2f\n", m->patches,
        err, sigma_deg, m->dispersion);
    EXPECT_GT(m->patches, 40u);  // floor and ceiling, not the wall
    EXPECT_LT(err, 0.1);
    EXPECT_LT(err, 3 * sigma_deg);
    // The covariance says nothing along the up itself.
    const double along = m->up.x * (m->covariance(0, 0) * m->up.x + m->covariance(0, 1) * m->up.y +
                                    m->covariance(0, 2) * m->up.z) +
                         m->up.y * (m->covariance(1, 0) * m->up.x + m->covariance(1, 1) * m->up.y +
                                    m->covariance(1, 2) * m->up.z) +
                         m->up.z * (m->covariance(2, 0) * m->up.x + m->covariance(2, 1) * m->up.y +
                                    m->covariance(2, 2) * m->up.z);
    EXPECT_LT(std::abs(along), 1e-3 * sigma_deg * sigma_deg);
    // Noisier disparities: a wider covariance, still a good measurement.
    const auto noisy = vfp.measure(corridor(pose, 0.3), trueUp(off));
    ASSERT_TRUE(noisy.has_value());
    const double noisy_sigma =
        std::sqrt(noisy->covariance(0, 0) + noisy->covariance(1, 1) + noisy->covariance(2, 2));
    EXPECT_GT(mrpt::RAD2DEG(noisy_sigma), 2 * sigma_deg);
    EXPECT_LT(angleDeg(noisy->up, truth), 3 * mrpt::RAD2DEG(noisy_sigma));
}

TEST(VerticalFromPlanes, aSlopeBeyondTheAngleIsNotAFloor)
{
    // The floor rises at 30 degrees (a ramp, stairs seen as one): only the
    // ceiling is level.
    const mrpt::poses::CPose3D pose(0, 0, 0, 0, 0, mrpt::DEG2RAD(-5.0));
    const VerticalFromPlanes vfp{VerticalFromPlanes::TParameters{}};
    const auto m = vfp.measure(corridor(pose, 0.05, mrpt::DEG2RAD(30.0)), trueUp(pose));
    ASSERT_TRUE(m.has_value());
    EXPECT_LT(angleDeg(m->up, trueUp(pose)), 0.2);
}

TEST(VerticalFromPlanes, noDisparityOrNoLevelPlaneGivesNothing)
{
    const mrpt::poses::CPose3D pose;
    const VerticalFromPlanes vfp{VerticalFromPlanes::TParameters{}};
    StereoFrame rgbd = corridor(pose, 0.05);
    rgbd.disparity.release();  // an RGB-D frame has no disparity image
    EXPECT_FALSE(vfp.measure(rgbd, trueUp(pose)).has_value());
    // Predicted up along the corridor: no plane faces that way (and the
    // wall, across it, is what a predicted up across it finds).
    EXPECT_FALSE(vfp.measure(corridor(pose, 0.05), TVector3D(0, 0, 1)).has_value());
    const auto wall = vfp.measure(corridor(pose, 0.05), TVector3D(1, 0, 0));
    ASSERT_TRUE(wall.has_value());
    EXPECT_LT(angleDeg(wall->up, TVector3D(1, 0, 0)), 0.2);
    EXPECT_FALSE(vfp.measure(corridor(pose, 0.05), TVector3D(0, 0, 0)).has_value());
    StereoFrame empty = corridor(pose, 0.05);
    empty.disparity.setTo(0);
    EXPECT_FALSE(vfp.measure(empty, trueUp(pose)).has_value());
}

TEST(VerticalFromPlanes, badParametersThrow)
{
    VerticalFromPlanes::TParameters p;
    p.patch_px = 3;
    EXPECT_THROW(VerticalFromPlanes{p}, std::invalid_argument);
    p = {};
    p.max_angle_deg = 90;
    EXPECT_THROW(VerticalFromPlanes{p}, std::invalid_argument);
    p = {};
    p.min_patches = 1;
    EXPECT_THROW(VerticalFromPlanes{p}, std::invalid_argument);
}
