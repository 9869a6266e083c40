// SPDX-License-Identifier: BSD-3-Clause
// StereoOdometry on frames of the simulator, whose every pose is exact: the
// per-step error, the chained pose, and what a frame it cannot use does.
#include "SmallLoopWorld.h"
#include "TestHelpers.h"

#include <emslam/slam/StereoOdometry.h>

#include <mrpt/obs/CObservationOdometry.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <opencv2/core.hpp>

using emslam::slam::StereoOdometry;
using emslam::test::rotationDeg;
using emslam::test::smallLoopFrames;
using emslam::test::TruthFrame;
using mrpt::poses::CPose3D;

namespace
{
constexpr double FPS = 4.0;         // 0.25 m per frame at 1 m/s
constexpr std::size_t FRAMES = 28;  // 6.7 m: along a wall, round the first corner
const emslam::stereo::StereoMatcher::TParameters STEREO;
const emslam::egomotion::EgomotionEstimator::TParameters EGOMOTION;

/** A copy of `obs` whose images are both uniformly grey (same size and
 * calibration): nothing to match. */
mrpt::obs::CObservationStereoImages::Ptr textureless(const mrpt::obs::CObservationStereoImages& obs)
{
    auto out = std::make_shared<mrpt::obs::CObservationStereoImages>(obs);
    const cv::Mat& left = obs.imageLeft.asCvMatRef();
    const cv::Mat grey(left.rows, left.cols, left.type(), cv::Scalar::all(128));
    out->imageLeft = mrpt::img::CImage(grey.clone(), mrpt::img::DEEP_COPY);
    out->imageRight = mrpt::img::CImage(grey.clone(), mrpt::img::DEEP_COPY);
    return out;
}
}  // namespace

TEST(StereoOdometry, stepsAndChainedPoseFollowTheExactMotion)
{
    const std::vector<TruthFrame>& frames = smallLoopFrames(FPS, FRAMES);
    ASSERT_EQ(frames.size(), FRAMES);
    StereoOdometry odometry{STEREO, EGOMOTION};
    double worst_m = 0, worst_deg = 0, travelled = 0, turned = 0;
    for (std::size_t i = 0; i < frames.size(); ++i)
    {
        StereoOdometry::Step step;
        ASSERT_TRUE(odometry.process(*frames[i].obs, step));
        EXPECT_EQ(step.first, i == 0);
        EXPECT_FALSE(step.predicted) << "frame " << i << ": " << step.egomotion.failure_reason;
        if (i == 0)
        {
            EXPECT_TRUE(step.action == CPose3D());
            continue;
        }
        const CPose3D truth = frames[i].T_first_left - frames[i - 1].T_first_left;
        const CPose3D error = step.action - truth;
        worst_m = std::max(worst_m, error.translation().norm());
        worst_deg = std::max(worst_deg, rotationDeg(error));
        travelled += truth.translation().norm();
        turned += rotationDeg(truth);
        EXPECT_TRUE(step.egomotion.ok) << "frame " << i << ": " << step.egomotion.failure_reason;
        EXPECT_GT(step.egomotion.final_matches, 100U) << "frame " << i;
    }
    const CPose3D drift = odometry.pose() - frames.back().T_first_left;
    std::printf(
        "%zu frames, %.2f m, %.0f deg: worst step error %.4f m, %.3f deg; end %.4f m, %.3f deg "
        "off\n",
        frames.size(), travelled, turned, worst_m, worst_deg, drift.translation().norm(),
        rotationDeg(drift));
    // Steps of 0.25 m and up to 15 deg: staying still, or chaining in the
    // wrong order through the corner, would be off by that much.
    ASSERT_GT(travelled, 6.0);
    ASSERT_GT(turned, 80.0);
    EXPECT_EQ(odometry.frameCount(), FRAMES);
    EXPECT_EQ(odometry.failures(), 0U);
    // Measured: worst step 0.011 m and 0.17 deg; end 0.015 m and 0.19 deg.
    EXPECT_LT(worst_m, 0.025);
    EXPECT_LT(worst_deg, 0.4);
    EXPECT_LT(drift.translation().norm(), 0.05);
    EXPECT_LT(rotationDeg(drift), 0.5);
}

TEST(StereoOdometry, aTexturelessFrameIsPredictedAtConstantVelocity)
{
    const std::vector<TruthFrame>& frames = smallLoopFrames(FPS, FRAMES);
    StereoOdometry odometry{STEREO, EGOMOTION};
    StereoOdometry::Step step;
    for (std::size_t i = 0; i < 3; ++i)
    {
        ASSERT_TRUE(odometry.process(*frames[i].obs, step));
    }
    ASSERT_FALSE(step.predicted);
    const CPose3D last_step = step.action;
    const CPose3D before = odometry.pose();
    ASSERT_TRUE(odometry.process(*textureless(*frames[3].obs), step));
    std::printf(
        "textureless frame: %zu points, %zu features, ok %d (%s)\n", step.frame.size(),
        step.egomotion.features_cur, step.egomotion.ok, step.egomotion.failure_reason.c_str());
    EXPECT_FALSE(step.egomotion.ok);
    EXPECT_FALSE(step.egomotion.failure_reason.empty());
    EXPECT_TRUE(step.predicted);
    EXPECT_FALSE(step.first);
    EXPECT_TRUE(step.action == last_step);
    EXPECT_LT(emslam::test::maxPoseDifference(odometry.pose(), before + last_step), 1e-12);
    EXPECT_EQ(odometry.failures(), 1U);
    EXPECT_EQ(odometry.frameCount(), 4U);
}

TEST(StereoOdometry, anUnusableObservationChangesNothing)
{
    const std::vector<TruthFrame>& frames = smallLoopFrames(FPS, FRAMES);
    StereoOdometry odometry{STEREO, EGOMOTION};
    StereoOdometry::Step step;
    ASSERT_TRUE(odometry.process(*frames[0].obs, step));
    ASSERT_TRUE(odometry.process(*frames[1].obs, step));
    const CPose3D pose = odometry.pose();

    // Not a camera: refused, nothing counted.
    EXPECT_FALSE(odometry.process(mrpt::obs::CObservationOdometry(), step));
    // Empty images: the front-end's exception passes on, nothing counted.
    auto empty = std::make_shared<mrpt::obs::CObservationStereoImages>(*frames[2].obs);
    empty->imageLeft = mrpt::img::CImage();
    empty->imageRight = mrpt::img::CImage();
    EXPECT_THROW(odometry.process(*empty, step), std::exception);
    EXPECT_EQ(odometry.frameCount(), 2U);
    EXPECT_EQ(odometry.failures(), 0U);
    EXPECT_TRUE(odometry.pose() == pose);

    // The next good frame is measured from the last good one.
    ASSERT_TRUE(odometry.process(*frames[2].obs, step));
    EXPECT_TRUE(step.egomotion.ok) << step.egomotion.failure_reason;
    const CPose3D error = odometry.pose() - frames[2].T_first_left;
    std::printf("after the refused frames: %.4f m off\n", error.translation().norm());
    // Measured 0.004 m; a step taken from the refused frame would be 0.25 m off.
    EXPECT_LT(error.translation().norm(), 0.02);
    EXPECT_EQ(odometry.frameCount(), 3U);
}
