// SPDX-License-Identifier: BSD-3-Clause
// The depth uncertainty of stereo and RGB-D points: sigma_z = z^2 sigma_d / (f b).
#include <emslam/slam/DepthNoiseModel.h>

#include <mrpt/img/TStereoCamera.h>

#include <gtest/gtest.h>

using emslam::slam::DepthNoiseModel;

namespace
{
/** The simulator's camera: f = 200 px, baseline 0.1 m. */
mrpt::img::TStereoCamera simCamera()
{
    mrpt::img::TStereoCamera c;
    c.leftCamera.setIntrinsicParamsFromValues(200, 200, 159.5, 119.5);
    c.rightCamera = c.leftCamera;
    c.rightCameraPose = mrpt::math::TPose3DQuat(0.1, 0, 0, 1, 0, 0, 0);
    return c;
}
}  // namespace

TEST(DepthNoiseModel, stereoSigmaGrowsWithTheSquareOfTheDepth)
{
    const DepthNoiseModel m(simCamera(), 0.25, 0.0015);
    // 0.25 px at f b = 20 px m: 0.2 m at 4 m, as doc/apps/emslam-eval.md says.
    EXPECT_NEAR(m.coefficient(), 0.25 / 20.0, 1e-12);
    EXPECT_NEAR(m.sigmaAt(4.0), 0.2, 1e-12);
    EXPECT_NEAR(m.sigmaAt(8.0), 4 * m.sigmaAt(4.0), 1e-12);
    // A baseline along another axis counts by its length.
    auto c = simCamera();
    c.rightCameraPose = mrpt::math::TPose3DQuat(-0.06, 0.08, 0, 1, 0, 0, 0);
    EXPECT_NEAR(DepthNoiseModel(c, 0.25, 0.0015).sigmaAt(4.0), 0.2, 1e-12);
}

TEST(DepthNoiseModel, withoutABaselineTheSensorCoefficientIsUsed)
{
    auto c = simCamera();
    c.rightCameraPose = mrpt::math::TPose3DQuat();  // RGB-D: no stereo pair
    const DepthNoiseModel m(c, 0.25, 0.0015);
    EXPECT_NEAR(m.coefficient(), 0.0015, 1e-15);
    EXPECT_NEAR(m.sigmaAt(2.0), 0.006, 1e-12);
}
