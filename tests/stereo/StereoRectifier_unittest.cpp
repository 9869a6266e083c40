// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"

#include <emslam/io/CalibrationFiles.h>
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/stereo/StereoRectifier.h>

#include <mrpt/core/bits_math.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

using emslam::stereo::baselineOf;
using emslam::stereo::StereoRectifier;

namespace
{
mrpt::img::TStereoCamera rectifiedPair()
{
    mrpt::img::TStereoCamera c;
    for (auto* cam : {&c.leftCamera, &c.rightCamera})
    {
        cam->ncols = 320;
        cam->nrows = 240;
        cam->setIntrinsicParamsFromValues(300.0, 300.0, 160.5, 119.5);
        cam->distortion = mrpt::img::DistortionModel::none;
    }
    c.rightCameraPose = mrpt::math::TPose3DQuat(0.12, 0, 0, 1, 0, 0, 0);
    return c;
}

/** A raw pair: different intrinsics, radial-tangential distortion, the right
 * camera translated mostly along +x and slightly rotated. */
mrpt::img::TStereoCamera rawPair()
{
    mrpt::img::TStereoCamera c;
    c.leftCamera.ncols = c.rightCamera.ncols = 640;
    c.leftCamera.nrows = c.rightCamera.nrows = 480;
    c.leftCamera.setIntrinsicParamsFromValues(500.0, 505.0, 322.0, 238.0);
    c.leftCamera.setDistortionPlumbBob(-0.20, 0.05, 0.0010, -0.0005);
    c.rightCamera.setIntrinsicParamsFromValues(498.0, 502.0, 330.0, 244.0);
    c.rightCamera.setDistortionPlumbBob(-0.18, 0.04, -0.0008, 0.0006);
    using mrpt::DEG2RAD;
    const mrpt::poses::CPose3D T_left_right(
        0.12, 0.004, -0.003, DEG2RAD(1.0), DEG2RAD(0.5), DEG2RAD(-0.7));
    c.rightCameraPose = mrpt::poses::CPose3DQuat(T_left_right).asTPose();
    return c;
}

cv::Mat noiseImage(int w, int h, int seed)
{
    cv::Mat im(h, w, CV_8UC1);
    cv::RNG rng(static_cast<uint64_t>(seed));
    rng.fill(im, cv::RNG::UNIFORM, 0, 256);
    return im;
}

/** Projects a point given in the left camera frame into one raw camera. */
cv::Point2d projectRaw(const mrpt::img::TCamera& cam, const mrpt::math::TPoint3D& p)
{
    const cv::Matx33d k(cam.fx(), 0, cam.cx(), 0, cam.fy(), cam.cy(), 0, 0, 1);
    const std::vector<double> d = {cam.k1(), cam.k2(), cam.p1(), cam.p2(), cam.k3()};
    std::vector<cv::Point2d> uv;
    cv::projectPoints(
        std::vector<cv::Point3d>{{p.x, p.y, p.z}}, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, d,
        uv);
    return uv.front();
}

/** An image with one Gaussian dot (sigma 1.5 px) centred at `c`. */
cv::Mat dotImage(const mrpt::img::TCamera& cam, const cv::Point2d& c)
{
    cv::Mat im(static_cast<int>(cam.nrows), static_cast<int>(cam.ncols), CV_32FC1, 0.0f);
    for (int v = static_cast<int>(c.y) - 8; v <= static_cast<int>(c.y) + 8; v++)
    {
        for (int u = static_cast<int>(c.x) - 8; u <= static_cast<int>(c.x) + 8; u++)
        {
            const double r2 = (u - c.x) * (u - c.x) + (v - c.y) * (v - c.y);
            im.at<float>(v, u) = static_cast<float>(200.0 * std::exp(-r2 / (2 * 1.5 * 1.5)));
        }
    }
    return im;
}

cv::Point2d centroid(const cv::Mat& im)
{
    const cv::Moments m = cv::moments(im);
    return {m.m10 / m.m00, m.m01 / m.m00};
}

/** |dy| of left/right ORB matches that pass a ratio test and a mutual check. */
std::vector<double> matchedRowDifferences(const cv::Mat& left, const cv::Mat& right)
{
    auto orb = cv::ORB::create(3000);
    std::vector<cv::KeyPoint> kl, kr;
    cv::Mat dl, dr;
    orb->detectAndCompute(left, cv::noArray(), kl, dl);
    orb->detectAndCompute(right, cv::noArray(), kr, dr);
    if (dl.empty() || dr.empty())
    {
        return {};
    }
    const cv::BFMatcher matcher(cv::NORM_HAMMING);
    std::vector<std::vector<cv::DMatch>> lr, rl;
    matcher.knnMatch(dl, dr, lr, 2);
    matcher.knnMatch(dr, dl, rl, 2);
    auto best = [](const std::vector<cv::DMatch>& m) -> int
    {
        if (m.empty() || (m.size() > 1 && m[0].distance > 0.8f * m[1].distance))
        {
            return -1;
        }
        return m[0].trainIdx;
    };
    std::vector<cv::Point2f> pl, pr;
    for (std::size_t i = 0; i < lr.size(); i++)
    {
        const int j = best(lr[i]);
        if (j < 0 || best(rl[static_cast<std::size_t>(j)]) != static_cast<int>(i))
        {
            continue;
        }
        pl.push_back(kl[i].pt);
        pr.push_back(kr[static_cast<std::size_t>(j)].pt);
    }
    if (pl.empty())
    {
        return {};
    }
    // ORB keypoints sit on (scaled) integer pixels: refine them so that the
    // measured |dy| is not quantised to whole pixels.
    const cv::TermCriteria crit(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
    cv::cornerSubPix(left, pl, cv::Size(4, 4), cv::Size(-1, -1), crit);
    cv::cornerSubPix(right, pr, cv::Size(4, 4), cv::Size(-1, -1), crit);
    std::vector<double> dy;
    for (std::size_t i = 0; i < pl.size(); i++)
    {
        dy.push_back(std::abs(pl[i].y - pr[i].y));
    }
    return dy;
}

double median(std::vector<double> v)
{
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

}  // namespace

TEST(StereoRectifier, alreadyRectifiedPairIsIdentity)
{
    const auto cam = rectifiedPair();
    EXPECT_TRUE(StereoRectifier::isAlreadyRectified(cam));

    StereoRectifier r(cam);
    ASSERT_TRUE(r.isInitialized());
    EXPECT_TRUE(r.isIdentity());

    const cv::Mat left = noiseImage(320, 240, 1), right = noiseImage(320, 240, 2);
    cv::Mat rl, rr;
    r.rectify(left, right, rl, rr);
    EXPECT_EQ(cv::norm(left, rl, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(right, rr, cv::NORM_INF), 0.0);

    const auto& out = r.rectifiedCamera();
    EXPECT_EQ(out.leftCamera.fx(), 300.0);
    EXPECT_EQ(out.rightCamera.cx(), 160.5);
    EXPECT_EQ(out.rightCameraPose.x, 0.12);
    EXPECT_EQ(out.leftCamera.distortion, mrpt::img::DistortionModel::none);
}

TEST(StereoRectifier, isAlreadyRectifiedRejectsEachDeparture)
{
    auto c = rectifiedPair();
    c.rightCameraPose.x = 0.12 * (1 + 1e-9);
    c.rightCamera.fx(300.0 * (1 + 1e-8));  // within tolerance
    EXPECT_TRUE(StereoRectifier::isAlreadyRectified(c));

    c = rectifiedPair();
    c.leftCamera.setDistortionPlumbBob(-0.1, 0, 0, 0);
    EXPECT_FALSE(StereoRectifier::isAlreadyRectified(c));
    c = rectifiedPair();
    c.rightCamera.cy(121.5);
    EXPECT_FALSE(StereoRectifier::isAlreadyRectified(c));
    c = rectifiedPair();
    c.rightCameraPose.y = 0.001;
    EXPECT_FALSE(StereoRectifier::isAlreadyRectified(c));
    c = rectifiedPair();
    c.rightCameraPose.x = -0.12;  // right camera on the left
    EXPECT_FALSE(StereoRectifier::isAlreadyRectified(c));
    c = rectifiedPair();
    c.rightCameraPose =
        mrpt::poses::CPose3DQuat(mrpt::poses::CPose3D(0.12, 0, 0, 0.001, 0, 0)).asTPose();
    EXPECT_FALSE(StereoRectifier::isAlreadyRectified(c));
}

TEST(StereoRectifier, differentPrincipalColumnsStayRectified)
{
    // Cropped rectified pairs (Middlebury) differ only in cx: rows still align.
    auto c = rectifiedPair();
    c.rightCamera.cx(c.leftCamera.cx() + 270.0);
    const StereoRectifier r(c);
    EXPECT_TRUE(r.isIdentity());
    EXPECT_NEAR(
        r.rectifiedCamera().rightCamera.cx() - r.rectifiedCamera().leftCamera.cx(), 270.0, 1e-9);
}

TEST(StereoRectifier, kittiCalibrationIsAlreadyRectified)
{
    EMSLAM_REQUIRE_TEST_DATA(path, "kitti-odometry/sequences/06/calib.txt");
    const StereoRectifier r(emslam::io::loadKittiCalibration(path, 1226, 370));
    EXPECT_TRUE(r.isIdentity());
    EXPECT_NEAR(baselineOf(r.rectifiedCamera()), 0.5372, 1e-4);
}

TEST(StereoRectifier, syntheticRawPairAlignsRowsAndKeepsMetricDepth)
{
    const auto raw = rawPair();
    const StereoRectifier r(raw);
    ASSERT_FALSE(r.isIdentity());

    const auto& rc = r.rectifiedCamera();
    EXPECT_EQ(rc.leftCamera.distortion, mrpt::img::DistortionModel::none);
    EXPECT_EQ(rc.leftCamera.intrinsicParams, rc.rightCamera.intrinsicParams);
    EXPECT_NEAR(baselineOf(rc), baselineOf(raw), 1e-9);
    EXPECT_GT(rc.rightCameraPose.x, 0.0);
    EXPECT_TRUE(StereoRectifier::isAlreadyRectified(rc));

    // Oracle: points in the left camera frame are projected into both raw
    // cameras with MRPT's pose convention and OpenCV's distortion model, drawn
    // as dots and rectified. The dots must land on the same row, and depth
    // triangulated from the rectified pair must give back the point's range
    // (rectification only rotates the camera frame).
    const mrpt::poses::CPose3D T_left_right(mrpt::poses::CPose3DQuat(raw.rightCameraPose));
    const double f = rc.leftCamera.fx(), cx = rc.leftCamera.cx(), cy = rc.leftCamera.cy();
    const double b = baselineOf(rc);
    int n = 0;
    for (double z : {2.0, 3.5, 6.0})
    {
        for (double x : {-0.5, 0.0, 0.5})
        {
            for (double y : {-0.35, 0.0, 0.35})
            {
                const mrpt::math::TPoint3D p_left(x * z / 2, y * z / 2, z);
                mrpt::math::TPoint3D p_right;
                T_left_right.inverseComposePoint(p_left, p_right);
                cv::Mat rl, rr;
                r.rectify(
                    dotImage(raw.leftCamera, projectRaw(raw.leftCamera, p_left)),
                    dotImage(raw.rightCamera, projectRaw(raw.rightCamera, p_right)), rl, rr);
                const cv::Point2d ul = centroid(rl), ur = centroid(rr);
                EXPECT_NEAR(ul.y, ur.y, 0.05) << "point " << p_left.asString();

                const double depth = f * b / (ul.x - ur.x);
                const mrpt::math::TPoint3D p_rect(
                    (ul.x - cx) * depth / f, (ul.y - cy) * depth / f, depth);
                EXPECT_NEAR(p_rect.norm(), p_left.norm(), 0.005 * p_left.norm())
                    << "point " << p_left.asString();
                n++;
            }
        }
    }
    EXPECT_EQ(n, 27);
}

TEST(StereoRectifier, rebuildsOnlyWhenCalibrationChanges)
{
    StereoRectifier r;
    EXPECT_FALSE(r.isInitialized());
    cv::Mat out_l, out_r;
    EXPECT_THROW(
        r.rectify(noiseImage(640, 480, 1), noiseImage(640, 480, 2), out_l, out_r),
        std::runtime_error);

    r.setCalibration(rawPair());
    const auto first = r.rectifiedCamera().leftCamera.intrinsicParams;
    r.setCalibration(rawPair());  // same: cached
    EXPECT_EQ(r.rectifiedCamera().leftCamera.intrinsicParams, first);

    auto other = rawPair();
    other.rightCameraPose =
        mrpt::poses::CPose3DQuat(mrpt::poses::CPose3D(0.2, 0, 0, 0, 0, 0.03)).asTPose();
    r.setCalibration(other);
    EXPECT_NEAR(baselineOf(r.rectifiedCamera()), 0.2, 1e-9);
    EXPECT_NE(r.rectifiedCamera().leftCamera.intrinsicParams, first);

    r.setCalibration(rawPair(), 1.0);  // alpha changes the rectified intrinsics too
    EXPECT_NE(r.rectifiedCamera().leftCamera.intrinsicParams, first);

    r.setCalibration(rectifiedPair());
    EXPECT_TRUE(r.isIdentity());
}

TEST(StereoRectifier, rejectsBadInputs)
{
    // Right camera on the left camera's -x side.
    auto swapped = rawPair();
    swapped.rightCameraPose.x = -swapped.rightCameraPose.x;
    EXPECT_THROW(StereoRectifier{swapped}, std::runtime_error);

    // A failed setCalibration keeps the previous state.
    StereoRectifier r(rawPair());
    const auto before = r.rectifiedCamera().rightCameraPose.x;
    EXPECT_THROW(r.setCalibration(swapped), std::runtime_error);
    EXPECT_EQ(r.rectifiedCamera().rightCameraPose.x, before);

    cv::Mat out_l, out_r;
    EXPECT_THROW(
        r.rectify(noiseImage(320, 240, 1), noiseImage(640, 480, 2), out_l, out_r),
        std::runtime_error);
}

TEST(StereoRectifier, eurocRectificationAlignsMatchedFeatureRows)
{
    EMSLAM_REQUIRE_TEST_DATA(cam0_yaml, "euroc-v101-rest/mav0/cam0/sensor.yaml");
    EMSLAM_REQUIRE_TEST_DATA(cam1_yaml, "euroc-v101-rest/mav0/cam1/sensor.yaml");
    EMSLAM_REQUIRE_TEST_DATA(cam0_dir, "euroc-v101-rest/mav0/cam0/data");
    EMSLAM_REQUIRE_TEST_DATA(cam1_dir, "euroc-v101-rest/mav0/cam1/data");

    // First left image with a right image of the same timestamp.
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(cam0_dir))
    {
        if (e.path().extension() == ".png" &&
            std::filesystem::exists(cam1_dir + "/" + e.path().filename().string()))
        {
            names.push_back(e.path().filename().string());
        }
    }
    ASSERT_FALSE(names.empty());
    std::sort(names.begin(), names.end());
    const cv::Mat left = cv::imread(cam0_dir + "/" + names.front(), cv::IMREAD_GRAYSCALE);
    const cv::Mat right = cv::imread(cam1_dir + "/" + names.front(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(left.empty());
    ASSERT_FALSE(right.empty());

    const StereoRectifier r(emslam::io::loadEurocCalibration(cam0_yaml, cam1_yaml));
    ASSERT_FALSE(r.isIdentity());
    EXPECT_NEAR(baselineOf(r.rectifiedCamera()), 0.110, 0.002);
    EXPECT_GT(r.rectifiedCamera().rightCameraPose.x, 0.0);

    cv::Mat rect_left, rect_right;
    r.rectify(left, right, rect_left, rect_right);
    ASSERT_EQ(rect_left.size(), left.size());

    const auto dy_raw = matchedRowDifferences(left, right);
    const auto dy_rect = matchedRowDifferences(rect_left, rect_right);
    ASSERT_GE(dy_raw.size(), 50u);
    ASSERT_GE(dy_rect.size(), 50u);
    const double med_raw = median(dy_raw), med_rect = median(dy_rect);

    std::cout << "[ EuRoC    ] frame " << names.front() << ": median |dy| raw = " << med_raw
              << " px (" << dy_raw.size() << " matches), rectified = " << med_rect << " px ("
              << dy_rect.size() << " matches)\n";
    RecordProperty("median_abs_dy_raw_px", std::to_string(med_raw));
    RecordProperty("median_abs_dy_rectified_px", std::to_string(med_rect));

    EXPECT_GT(med_raw, 8.0);
    EXPECT_LT(med_rect, 1.0);
}
