// SPDX-License-Identifier: BSD-3-Clause
// Loop closing as EntropySlam drives it, under ThreadSanitizer: the producer
// adds keyframes and rectified poses, a BackgroundWorker runs update(), a
// third thread reads the current poses, and close() ends the run.
#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/rectify/ActionCovariance.h>
#include <emslam/slam/BackgroundWorker.h>
#include <emslam/slam/LoopCloser.h>

#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <opencv2/core.hpp>
#include <thread>
#include <vector>

using emslam::egomotion::EgomotionEstimator;
using emslam::slam::LoopCloser;
using mrpt::poses::CPose3D;

namespace
{
/** A textured plane 3 m away, tilted in depth; texture `seed`. */
EgomotionEstimator::Description describe(EgomotionEstimator& e, unsigned seed)
{
    emslam::stereo::StereoFrame f;
    f.intensity = cv::Mat(120, 160, CV_8UC1);
    cv::RNG(seed).fill(f.intensity, cv::RNG::UNIFORM, 0, 256);
    f.valid = cv::Mat(f.intensity.size(), CV_8UC1, cv::Scalar(255));
    for (int v = 0; v < 120; ++v)
    {
        for (int u = 0; u < 160; ++u)
        {
            f.points.emplace_back((u - 80) * 0.01f, (v - 60) * 0.01f, 3.0f + 0.01f * u);
            f.pixels.push_back({static_cast<std::uint16_t>(u), static_cast<std::uint16_t>(v)});
        }
    }
    e.reset();
    e.process(f);
    return e.lastDescription();
}
}  // namespace

TEST(LoopClosingUnderTsan, producerWorkerAndReaderDoNotRace)
{
    LoopCloser::TParameters p;
    p.enabled = true;
    p.local_edges = 2;
    p.place_candidates = 0;
    p.min_path_length = 3;
    LoopCloser closer(p);
    EgomotionEstimator producer_estimator, worker_estimator;
    emslam::slam::BackgroundWorker worker([&] { closer.update(worker_estimator); });
    std::atomic<bool> reading{true};
    std::size_t seen = 0;
    std::thread reader(
        [&]
        {
            while (reading)
            {
                seen = std::max(seen, closer.currentPoses().size());
                (void)closer.lastPose();
                (void)closer.processedCount();
            }
        });
    // A circle of 24 keyframes walked twice: the second lap sees the first's
    // textures again, so registrations, consensus and solves all run.
    const auto cov = emslam::rectify::diagonalCovariance(0.02, mrpt::DEG2RAD(1.0));
    const CPose3D step(0, 0, 0.5, 0, mrpt::DEG2RAD(15.0), 0);  // a turn about the vertical (y)
    std::vector<LoopCloser::KeyframePose> rectified;
    CPose3D pose;
    for (std::size_t k = 0; k < 48; ++k)
    {
        if (k > 0)
        {
            pose = pose + step;
        }
        closer.addKeyframe(
            k, describe(producer_estimator, static_cast<unsigned>(k % 24)), cov,
            k == 0 ? std::nullopt : std::optional<CPose3D>(step));
        rectified.push_back({k, pose});
        if (k % 8 == 7)
        {
            closer.setRectifiedPoses(rectified);
        }
        worker.notify();
    }
    worker.drain();
    worker.stop();
    reading = false;
    reader.join();
    std::vector<CPose3D> poses;
    for (const auto& r : rectified)
    {
        poses.push_back(r.pose);
    }
    const auto closed = closer.close(poses, worker_estimator);
    EXPECT_EQ(closed.size(), 48u);
    EXPECT_EQ(closer.processedCount(), 48u);
    EXPECT_GT(closer.stats().registrations, 0u);
    EXPECT_GT(closer.stats().loop_edges, 0u);
}
