// SPDX-License-Identifier: BSD-3-Clause
// map_top.png: the floor plan is not blank, walls are dark, trajectory
// pixels lie where the trajectories are, and the ceiling cut matters.
#include "MapDrawingFixture.h"
#include "TestData.h"

#include <emslam/apps/MapStyle.h>
#include <emslam/apps/MapTopView.h>

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <utility>

using namespace emslam::apps;

namespace
{
/** Pixels within `radius` of `px` whose colour is close to `style`'s. */
int pixelsOfColorNear(
    const cv::Mat& bgr, const cv::Point2d& px, int radius, const TrajectoryStyle& style)
{
    int n = 0;
    for (int v = static_cast<int>(px.y) - radius; v <= static_cast<int>(px.y) + radius; ++v)
    {
        for (int u = static_cast<int>(px.x) - radius; u <= static_cast<int>(px.x) + radius; ++u)
        {
            if (u < 0 || v < 0 || u >= bgr.cols || v >= bgr.rows)
            {
                continue;
            }
            const auto c = bgr.at<cv::Vec3b>(v, u);
            n += std::abs(c[2] - 255.0 * style.r) < 60 && std::abs(c[1] - 255.0 * style.g) < 60 &&
                 std::abs(c[0] - 255.0 * style.b) < 60;
        }
    }
    return n;
}

/** Darkest and mean grey level of a square of `radius` around `px`. */
std::pair<double, double> greyNear(const cv::Mat& bgr, const cv::Point2d& px, int radius)
{
    const cv::Rect box(
        static_cast<int>(px.x) - radius, static_cast<int>(px.y) - radius, 2 * radius + 1,
        2 * radius + 1);
    cv::Mat grey;
    cv::cvtColor(bgr(box & cv::Rect(0, 0, bgr.cols, bgr.rows)), grey, cv::COLOR_BGR2GRAY);
    double lo = 0;
    cv::minMaxLoc(grey, &lo);
    return {lo, cv::mean(grey)[0]};
}

int nonWhitePixels(const cv::Mat& bgr)
{
    cv::Mat grey;
    cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
    return cv::countNonZero(grey < 250);
}

int darkPixels(const cv::Mat& bgr)
{
    int n = 0;
    for (int v = 0; v < bgr.rows; ++v)
    {
        for (int u = 0; u < bgr.cols; ++u)
        {
            const auto c = bgr.at<cv::Vec3b>(v, u);
            n += c[0] < 128 && c[1] < 128 && c[2] < 128;
        }
    }
    return n;
}
}  // namespace

TEST(MapTopView, floorPlanIsNotBlankAndTrajectoriesAreWhereExpected)
{
    const emslam::test::MapDrawingFixture f;
    auto c = f.content();
    c.max_height = 1.5;  // below the ceiling: the walls show as lines
    TopViewOptions o;
    o.max_side = 600;
    const MapTopView view = renderTopView(c, o);
    ASSERT_FALSE(view.image.empty());
    EXPECT_EQ(view.image.type(), CV_8UC3);
    EXPECT_LE(std::max(view.image.cols, view.image.rows), 600 + 1);
    // Room 10 m (forward, image x) by 6 m: the scale fits 10 m in 540 px.
    EXPECT_NEAR(view.pixels_per_metre, 54.0, 1.0);
    EXPECT_GT(view.image.cols, view.image.rows);

    // Walls: one dark dot per wall column (points every 0.1 m): 2 x 101 + 2 x 61.
    EXPECT_GT(darkPixels(view.image), 250);
    // The wall at x = +3 (the camera's right) has dark dots; the open floor has none.
    EXPECT_LT(greyNear(view.image, view.toPixel({3.0, 0.0, 5.0}), 3).first, 128.0);

    // Each trajectory's pixels at its own corners (trajectories are 0.5 m apart).
    for (const auto& [traj, style] :
         {std::make_pair(&f.egomotion, EGOMOTION_STYLE), std::make_pair(&f.slam, SLAM_STYLE),
          std::make_pair(&f.ground_truth, GROUND_TRUTH_STYLE)})
    {
        for (std::size_t i : {std::size_t{0}, traj->size() / 4, traj->size() / 2})
        {
            const auto px = view.toPixel(traj->poses[i].pose.asTPose().translation());
            EXPECT_GE(pixelsOfColorNear(view.image, px, 3, style), 3)
                << style.label << " pose " << i << " at " << px;
        }
    }
    // The loop closure: orange at its middle, not beyond its end.
    const auto& [a, b] = f.loops.front();
    const mrpt::math::TPoint3D middle{(a.x + b.x) / 2, 0.0, (a.z + b.z) / 2};
    EXPECT_GE(pixelsOfColorNear(view.image, view.toPixel(middle), 2, LOOP_STYLE), 2);
    const mrpt::math::TPoint3D beyond{b.x + 0.5 * (b.x - a.x), 0.0, b.z + 0.5 * (b.z - a.z)};
    EXPECT_EQ(pixelsOfColorNear(view.image, view.toPixel(beyond), 2, LOOP_STYLE), 0);
    const auto floor = greyNear(view.image, view.toPixel({0.0, 0.0, 5.0}), 3);
    EXPECT_GT(floor.first, 150.0);
    EXPECT_GT(floor.second, 220.0);
}

TEST(MapTopView, theCeilingCutRemovesTheCeilingFromThePlan)
{
    // Only the fixture's ceiling (2 m above the camera): it covers the room
    // in the plan, and nothing is left of it below a 1.5 m cut.
    const emslam::test::MapDrawingFixture f;
    emslam::slam::IntensityCloud ceiling;
    for (std::size_t i = 0; i < f.cloud.size(); ++i)
    {
        if (f.cloud.points[i].y < -1.99f)
        {
            ceiling.points.push_back(f.cloud.points[i]);
            ceiling.intensity.push_back(f.cloud.intensity[i]);
        }
    }
    ASSERT_EQ(ceiling.size(), 61U * 101U + 2U * (61U + 101U));
    emslam::apps::MapDrawingContent c;
    c.cloud = &ceiling;
    c.slam = &f.slam;  // fixes the extent when the cloud is cut away
    TopViewOptions o;
    o.max_side = 300;
    o.legend = false;
    const int slam_only = [&]
    {
        emslam::apps::MapDrawingContent t;
        t.slam = c.slam;
        t.cloud = nullptr;
        return nonWhitePixels(renderTopView(t, o).image);
    }();
    const int covered = nonWhitePixels(renderTopView(c, o).image) - slam_only;
    c.max_height = 1.5;
    const int cut = nonWhitePixels(renderTopView(c, o).image) - slam_only;
    EXPECT_GT(covered, 3000);  // ~6000 ceiling points, one pixel per 0.04 m
    EXPECT_EQ(cut, 0);
}

TEST(MapTopView, writesAPngAndRejectsBadOptions)
{
    const emslam::test::MapDrawingFixture f;
    const std::string file = emslam::test::makeTempDir("map_top") + "/map_top.png";
    writeTopView(f.content(), file);
    const cv::Mat back = cv::imread(file);
    ASSERT_FALSE(back.empty());
    EXPECT_NEAR(std::max(back.cols, back.rows), 1000, 1);
    TopViewOptions bad;
    bad.max_side = 10;
    EXPECT_THROW(renderTopView(f.content(), bad), std::invalid_argument);
}
