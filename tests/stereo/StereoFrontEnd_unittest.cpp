// SPDX-License-Identifier: BSD-3-Clause
#include "SyntheticStereo.h"

#include <emslam/stereo/StereoFrontEnd.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

using namespace emslam::stereo;

namespace
{
mrpt::obs::CObservationStereoImages::Ptr planeObservation(double z)
{
    const auto cam = emslam::test::idealStereoCamera(320, 240, 200.0, 0.10);
    cv::Mat l, r;
    emslam::test::renderFrontoParallelPlane(cam, z, 9, l, r);
    auto obs = mrpt::obs::CObservationStereoImages::Create();
    obs->sensorLabel = "CAM";
    obs->timestamp = mrpt::Clock::fromDouble(10.0);
    obs->imageLeft = mrpt::img::CImage(l, mrpt::img::DEEP_COPY);
    obs->imageRight = mrpt::img::CImage(r, mrpt::img::DEEP_COPY);
    obs->hasImageRight = true;
    obs->setStereoCameraParams(cam);
    return obs;
}
}  // namespace

TEST(StereoFrontEnd, stereoObservationBecomesAFrame)
{
    StereoFrontEnd fe;
    const auto obs = planeObservation(2.5);
    StereoFrame f;
    ASSERT_TRUE(fe.process(static_cast<const mrpt::obs::CObservation&>(*obs), f));
    EXPECT_TRUE(fe.rectifier().isIdentity());
    EXPECT_EQ(f.sensor_label, "CAM");
    EXPECT_EQ(f.timestamp, obs->timestamp);
    ASSERT_GT(f.size(), 20000u);
    double sum = 0;
    for (const auto& p : f.points)
    {
        sum += p.z;
    }
    EXPECT_NEAR(sum / f.size(), 2.5, 0.02);
}

TEST(StereoFrontEnd, colourImagesAreAccepted)
{
    StereoFrontEnd fe;
    auto obs = planeObservation(2.0);
    cv::Mat l = obs->imageLeft.asCvMat<cv::Mat>(mrpt::img::DEEP_COPY), lc, rc;
    cv::Mat r = obs->imageRight.asCvMat<cv::Mat>(mrpt::img::DEEP_COPY);
    cv::cvtColor(l, lc, cv::COLOR_GRAY2BGR);
    cv::cvtColor(r, rc, cv::COLOR_GRAY2BGR);
    obs->imageLeft = mrpt::img::CImage(lc, mrpt::img::DEEP_COPY);
    obs->imageRight = mrpt::img::CImage(rc, mrpt::img::DEEP_COPY);
    const auto f = fe.process(*obs);
    EXPECT_EQ(f.intensity.channels(), 1);
    EXPECT_GT(f.size(), 20000u);
}

TEST(StereoFrontEnd, badStereoObservationsThrowNamingTheCause)
{
    StereoFrontEnd fe;
    auto no_right = planeObservation(2.0);
    no_right->hasImageRight = false;
    EXPECT_THROW(fe.process(*no_right), std::exception);

    auto sizes = planeObservation(2.0);
    sizes->imageRight =
        mrpt::img::CImage(cv::Mat(200, 320, CV_8UC1, cv::Scalar(3)), mrpt::img::DEEP_COPY);
    try
    {
        fe.process(*sizes);
        FAIL() << "size mismatch accepted";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("right image is 320x200"), std::string::npos)
            << e.what();
    }

    auto calib = planeObservation(2.0);
    auto cam = calib->getStereoCameraParams();
    cam.leftCamera.ncols = 640;
    cam.rightCamera.ncols = 640;
    calib->setStereoCameraParams(cam);
    EXPECT_THROW(fe.process(*calib), std::exception);

    auto empty = planeObservation(2.0);
    empty->imageLeft = mrpt::img::CImage();
    EXPECT_THROW(fe.process(*empty), std::exception);
}

TEST(StereoFrontEnd, otherObservationClassesAreNotHandled)
{
    StereoFrontEnd fe;
    mrpt::obs::CObservationImage img;
    StereoFrame f;
    EXPECT_FALSE(fe.process(img, f));
}

TEST(StereoFrontEnd, rgbdObservationFromMrptSampleBecomesAFrame)
{
    // mrpt-common ships one Kinect observation; skip if the package is absent.
    const std::string file = "/usr/share/mrpt/datasets/tests_rgbd.rawlog";
    if (!mrpt::system::fileExists(file))
    {
        GTEST_SKIP() << file << " not installed (package mrpt-common)";
    }
    mrpt::io::CFileGZInputStream in(file);
    auto arch = mrpt::serialization::archiveFrom(in);
    mrpt::obs::CObservation3DRangeScan::Ptr obs;
    while (!obs)
    {
        auto o = arch.ReadObject();
        obs = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o);
    }
    StereoFrontEnd fe;
    StereoFrame f;
    ASSERT_TRUE(fe.process(static_cast<const mrpt::obs::CObservation&>(*obs), f));
    EXPECT_EQ(f.intensity.cols, static_cast<int>(obs->intensityImage.getWidth()));
    EXPECT_GT(f.size(), 1000u);
    for (std::size_t i = 0; i < f.size(); i += 101)
    {
        EXPECT_GT(f.points[i].z, 0.0f);
        EXPECT_LT(f.points[i].z, 15.0f);
    }
}

// Sparse mode: points only at the selected pixels, at full size; the map's
// dense cloud from a task that owns its images, at image_scale.
TEST(StereoFrontEnd, sparseModeGivesPointsAtTheSelectedPixelsAndADenseMapFrameTask)
{
    StereoMatcher::TParameters p;
    p.image_scale = 0.5;
    p.num_disparities = 32;  // 64 at full size
    p.sparse_at_features = true;
    StereoFrontEnd fe(p);
    EXPECT_FALSE(fe.sparse());  // no selector yet
    std::vector<PixelCoord> asked;
    for (int v = 20; v < 220; v += 10)
    {
        for (int u = 100; u < 300; u += 10)
        {
            asked.push_back({static_cast<std::uint16_t>(u), static_cast<std::uint16_t>(v)});
        }
    }
    fe.setPixelSelector(
        [&](const cv::Mat& gray)
        {
            EXPECT_EQ(gray.type(), CV_8UC1);
            return asked;
        });
    ASSERT_TRUE(fe.sparse());
    auto obs = planeObservation(2.5);
    const StereoFrame f = fe.process(*obs);
    EXPECT_EQ(f.intensity.cols, 320);
    EXPECT_EQ(f.camera.leftCamera.ncols, 320U);
    EXPECT_GT(f.size(), asked.size() * 9 / 10);
    for (std::size_t i = 0; i < f.size(); ++i)
    {
        EXPECT_EQ(f.pixels[i].u % 10, 0);
        EXPECT_NEAR(f.points[i].z, 2.5, 0.02);
    }
    auto task = fe.mapFrameTask(f);
    ASSERT_TRUE(task);
    // The caller may reuse its image buffers before the task runs.
    obs->imageLeft.asCvMatRef().setTo(cv::Scalar(0));
    const StereoFrame dense = task();
    EXPECT_EQ(dense.intensity.cols, 160);
    EXPECT_EQ(dense.timestamp, f.timestamp);
    EXPECT_GT(dense.size(), 5000U);
    double sum = 0;
    for (const auto& pt : dense.points)
    {
        sum += pt.z;
    }
    EXPECT_NEAR(sum / static_cast<double>(dense.size()), 2.5, 0.05);

    // Without sparse_at_features (or for RGB-D) there is no task: the frame
    // process() returns is the map's cloud.
    p.sparse_at_features = false;
    StereoFrontEnd dense_fe(p);
    dense_fe.setPixelSelector([&](const cv::Mat&) { return asked; });
    EXPECT_FALSE(dense_fe.sparse());
    EXPECT_FALSE(dense_fe.mapFrameTask(dense_fe.process(*planeObservation(2.5))));
}
