// SPDX-License-Identifier: BSD-3-Clause
// The sparse stereo front-end as Mapper drives it, under ThreadSanitizer:
// each keyframe's dense map cloud is computed by a task on a second thread
// while the front-end processes the next observations (whose buffers the
// caller reuses).
#include <emslam/stereo/StereoFrontEnd.h>

#include <gtest/gtest.h>

#include <future>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

using namespace emslam::stereo;

namespace
{
mrpt::img::TStereoCamera camera()
{
    mrpt::img::TStereoCamera c;
    for (auto* cam : {&c.leftCamera, &c.rightCamera})
    {
        cam->ncols = 160;
        cam->nrows = 120;
        cam->setIntrinsicParamsFromValues(100, 100, 79.5, 59.5);
        cam->dist.fill(0);
    }
    c.rightCameraPose = mrpt::math::TPose3DQuat(0.1, 0, 0, 1, 0, 0, 0);  // 10 cm along +x
    return c;
}
}  // namespace

TEST(SparseFrontEndUnderTsan, mapFrameTasksRunBesideTheNextFrames)
{
    StereoMatcher::TParameters p;
    p.sparse_at_features = true;
    p.num_disparities = 32;
    // Full size: the dense frame copies the left image with memcpy, which
    // ThreadSanitizer sees (OpenCV's own loops are not instrumented).
    p.image_scale = 1.0;
    StereoFrontEnd front(p);
    std::vector<PixelCoord> pixels;
    for (int v = 10; v < 110; v += 6)
    {
        for (int u = 40; u < 150; u += 6)
        {
            pixels.push_back({static_cast<std::uint16_t>(u), static_cast<std::uint16_t>(v)});
        }
    }
    front.setPixelSelector([&](const cv::Mat&) { return pixels; });
    ASSERT_TRUE(front.sparse());

    // One observation object whose images are rewritten for every frame, as
    // a grabber reusing its buffers would.
    mrpt::obs::CObservationStereoImages obs;
    obs.setStereoCameraParams(camera());
    obs.hasImageRight = true;
    cv::Mat left(120, 160, CV_8UC1), right(120, 160, CV_8UC1);
    obs.imageLeft = mrpt::img::CImage(left, mrpt::img::SHALLOW_COPY);
    obs.imageRight = mrpt::img::CImage(right, mrpt::img::SHALLOW_COPY);
    cv::RNG rng(3);
    std::optional<std::future<StereoFrame>> pending;
    std::size_t dense_points = 0;
    for (int i = 0; i < 12; ++i)
    {
        cv::Mat texture(120, 200, CV_8UC1);
        rng.fill(texture, cv::RNG::UNIFORM, 0, 255);
        texture(cv::Rect(20, 0, 160, 120)).copyTo(obs.imageLeft.asCvMatRef());
        texture(cv::Rect(28, 0, 160, 120)).copyTo(obs.imageRight.asCvMatRef());  // d = 8 px
        const StereoFrame f = front.process(obs);
        EXPECT_GT(f.size(), pixels.size() / 2);
        if (pending)
        {
            dense_points += pending->get().size();
            pending.reset();
        }
        if (i % 2 == 0)
        {
            pending = std::async(std::launch::async, front.mapFrameTask(f));
        }
    }
    if (pending)
    {
        dense_points += pending->get().size();
    }
    EXPECT_GT(dense_points, 0U);
}
