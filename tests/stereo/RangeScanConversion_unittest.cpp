// SPDX-License-Identifier: BSD-3-Clause
#include "SyntheticStereo.h"

#include <emslam/stereo/RangeScanConversion.h>
#include <emslam/stereo/StereoMatcher.h>

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/T3DPointsProjectionParams.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

using namespace emslam::stereo;

namespace
{
StereoFrame planeFrame()
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, 200.0, 0.10);
    cv::Mat l, r;
    emslam::test::renderFrontoParallelPlane(cam, 2.0, 5, l, r);
    auto f = StereoMatcher().compute(l, r, cam);
    f.sensor_label = "STEREO";
    f.timestamp = mrpt::Clock::fromDouble(1234.5);
    return f;
}
}  // namespace

TEST(RangeScanConversion, usesMrptAxesForwardLeftUp)
{
    StereoFrame f;
    f.intensity = cv::Mat(240, 320, CV_8UC1, cv::Scalar(100));
    f.valid = cv::Mat::zeros(240, 320, CV_8UC1);
    f.camera = emslam::test::idealStereoCamera(320, 240, 200.0, 0.10);
    // A point right of and below the optical axis, 3 m ahead.
    f.points.emplace_back(0.5f, 0.25f, 3.0f);
    f.pixels.push_back(
        {static_cast<uint16_t>(159.5 + 200 * 0.5 / 3 + 0.5),
         static_cast<uint16_t>(119.5 + 200 * 0.25 / 3 + 0.5)});
    const auto obs = toRangeScan(f);
    ASSERT_EQ(obs->points3D_x.size(), 1u);
    EXPECT_FLOAT_EQ(obs->points3D_x[0], 3.0f);    // forward
    EXPECT_FLOAT_EQ(obs->points3D_y[0], -0.5f);   // left
    EXPECT_FLOAT_EQ(obs->points3D_z[0], -0.25f);  // up
    EXPECT_EQ(obs->rangeImage(f.pixels[0].v, f.pixels[0].u), 3000);
    EXPECT_TRUE(obs->range_is_depth);
}

TEST(RangeScanConversion, roundTripKeepsPointsPixelsAndImage)
{
    const auto f = planeFrame();
    ASSERT_GT(f.size(), 1000u);
    const auto obs = toRangeScan(f);
    const auto g = fromRangeScan(*obs);
    ASSERT_EQ(g.size(), f.size());
    for (std::size_t i = 0; i < f.size(); ++i)
    {
        EXPECT_EQ(g.pixels[i].u, f.pixels[i].u);
        EXPECT_EQ(g.pixels[i].v, f.pixels[i].v);
        EXPECT_NEAR(g.points[i].x, f.points[i].x, 1e-6);
        EXPECT_NEAR(g.points[i].z, f.points[i].z, 1e-6);
    }
    EXPECT_EQ(cv::norm(g.intensity, f.intensity, cv::NORM_INF), 0.0);
    EXPECT_EQ(g.sensor_label, "STEREO");
    EXPECT_EQ(g.timestamp, f.timestamp);
    EXPECT_NEAR(g.camera.leftCamera.fx(), 200.0, 1e-9);
}

TEST(RangeScanConversion, rangeImageAloneUnprojectsToTheSamePoints)
{
    const auto f = planeFrame();
    auto obs = toRangeScan(f);
    obs->hasPoints3D = false;
    obs->resizePoints3DVectors(0);
    const auto g = fromRangeScan(*obs);
    ASSERT_EQ(g.size(), f.size());
    // Depth is quantised to 1 mm in the range image.
    for (std::size_t i = 0; i < f.size(); i += 31)
    {
        EXPECT_NEAR(g.points[i].z, f.points[i].z, 0.0006);
        EXPECT_NEAR(g.points[i].x, f.points[i].x, 0.001);
    }
}

TEST(RangeScanConversion, agreesWithMrptUnprojection)
{
    const auto f = planeFrame();
    auto obs = toRangeScan(f);
    mrpt::maps::CSimplePointsMap pts;
    mrpt::obs::T3DPointsProjectionParams pp;
    pp.takeIntoAccountSensorPoseOnRobot = false;
    obs->unprojectInto(pts, pp);
    ASSERT_EQ(pts.size(), f.size());
    // MRPT's own unprojection of our range image lands on our points (to the 1 mm quantum).
    for (std::size_t i = 0; i < f.size(); i += 53)
    {
        float x, y, z;
        pts.getPoint(i, x, y, z);
        EXPECT_NEAR(x, f.points[i].z, 0.002);
        EXPECT_NEAR(y, -f.points[i].x, 0.002);
        EXPECT_NEAR(z, -f.points[i].y, 0.002);
    }
}

TEST(RangeScanConversion, serializesThroughAnMrptArchive)
{
    const auto f = planeFrame();
    const auto obs = toRangeScan(f);
    mrpt::io::CMemoryStream buf;
    auto out = mrpt::serialization::archiveFrom(buf);
    out << *obs;
    buf.Seek(0);
    auto in = mrpt::serialization::archiveFrom(buf);
    const auto read = in.ReadObject<mrpt::obs::CObservation3DRangeScan>();
    ASSERT_TRUE(read);
    const auto g = fromRangeScan(*read);
    EXPECT_EQ(g.size(), f.size());
}

TEST(RangeScanConversion, observationWithoutDataThrows)
{
    mrpt::obs::CObservation3DRangeScan obs;
    EXPECT_THROW(fromRangeScan(obs), std::exception);
    obs.hasIntensityImage = true;
    obs.intensityImage =
        mrpt::img::CImage(cv::Mat(10, 10, CV_8UC1, cv::Scalar(1)), mrpt::img::DEEP_COPY);
    EXPECT_THROW(fromRangeScan(obs), std::exception);
}
