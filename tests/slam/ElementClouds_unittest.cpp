// SPDX-License-Identifier: BSD-3-Clause
// The map cloud kept per trajectory element: it follows the trajectory's
// compression, stays bounded, and its points land at their frames' final poses.
#include "PaperRectifierOptions.h"

#include <emslam/rectify/RectificationRunner.h>
#include <emslam/rectify/Trajectory.h>
#include <emslam/slam/ElementClouds.h>
#include <emslam/slam/IntensityCloud.h>

#include <mrpt/core/bits_math.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

using emslam::rectify::TimedPose;
using emslam::rectify::Trajectory;
using emslam::slam::ElementClouds;
using emslam::slam::IntensityCloud;
using mrpt::math::TPoint3D;
using mrpt::poses::CPose3D;

namespace
{
constexpr double CELL = 0.1;  //!< [m] map_cell_size of the tests

/** Landmarks 0.5 m apart (at cell centres of the world grid) on a wall 6 m
 * ahead of the first camera; each has its own grey level. */
std::vector<TPoint3D> wallLandmarks()
{
    std::vector<TPoint3D> p;
    for (int i = 0; i < 21; ++i)
    {
        for (int j = 0; j < 5; ++j)
        {
            p.emplace_back(-5.0 + 0.05 + 0.5 * i, -1.0 + 0.05 + 0.5 * j, 6.05);
        }
    }
    return p;
}

std::uint8_t greyOf(std::size_t landmark)
{
    return static_cast<std::uint8_t>(10 + 2 * landmark);
}

/** Frame k of a camera driving along the wall, turning a little. */
CPose3D truePose(std::size_t k)
{
    const double s = static_cast<double>(k);
    return CPose3D(-3.0 + 0.15 * s, 0.0, 0.02 * s, mrpt::DEG2RAD(2.0 * std::sin(0.3 * s)), 0, 0);
}

/** What frame `T_world_cam` sees of the landmarks (within 3 m sideways), in
 * its own frame. */
IntensityCloud view(const CPose3D& T_world_cam, const std::vector<TPoint3D>& landmarks)
{
    IntensityCloud c;
    for (std::size_t i = 0; i < landmarks.size(); ++i)
    {
        const TPoint3D p = T_world_cam.inverseComposePoint(landmarks[i]);
        if (std::abs(p.x) < 3.0)
        {
            c.points.emplace_back(
                static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
            c.intensity.push_back(greyOf(i));
        }
    }
    return c;
}

emslam::maps::WeightedPointCloud weighted(const IntensityCloud& c)
{
    emslam::maps::WeightedPointCloud w;
    for (const auto& p : c.points)
    {
        w.push_back(p, 1.f);
    }
    return w;
}

emslam::CEntropyVoxelMap::TCreationOptions mapOptions()
{
    emslam::CEntropyVoxelMap::TCreationOptions o;
    o.cell_size = 0.15;
    o.energy = emslam::maps::EnergyType::Unstructured;
    o.dof = 6;
    return o;
}

/** Expects `cloud` to hold exactly the `expected` positions (a point of grey
 * g within 1e-4 m of an expected position of grey g, every one covered). */
void expectPointsAt(
    const IntensityCloud& cloud, const std::multimap<std::uint8_t, TPoint3D>& expected)
{
    std::vector<bool> covered(expected.size(), false);
    for (std::size_t i = 0; i < cloud.size(); ++i)
    {
        const TPoint3D p(cloud.points[i]);
        bool found = false;
        std::size_t k = 0;
        for (auto it = expected.begin(); it != expected.end(); ++it, ++k)
        {
            if (it->first == cloud.intensity[i] && (it->second - p).norm() < 1e-4)
            {
                covered[k] = true;
                found = true;
            }
        }
        EXPECT_TRUE(found) << "point " << p.asString() << " grey " << int(cloud.intensity[i]);
    }
    std::size_t k = 0;
    for (auto it = expected.begin(); it != expected.end(); ++it, ++k)
    {
        EXPECT_TRUE(covered[k]) << "nothing at " << it->second.asString();
    }
}
}  // namespace

TEST(ElementClouds, followsTheTrajectorysCompressionWithOneCloudPerElement)
{
    const auto landmarks = wallLandmarks();
    const std::size_t n_max = 6;
    Trajectory t(mapOptions());
    ElementClouds clouds(n_max, CELL);
    std::size_t frame_points = 0;
    for (std::size_t k = 0; k < 80; ++k)
    {
        const IntensityCloud c = view(truePose(k), landmarks);
        frame_points += c.size();
        const CPose3D action = k == 0 ? truePose(0) : truePose(k) - truePose(k - 1);
        t.append(action, weighted(c), 0.1 * k, k);
        if (t.size() > n_max)
        {
            t.compress();
        }
        clouds.append(k, c);
        clouds.fuse(t.framePoses());
        ASSERT_EQ(clouds.elementCount(), t.size()) << "frame " << k;
        EXPECT_FALSE(clouds.hasPendingFusions());
        EXPECT_EQ(clouds.cloudCount(), clouds.elementCount());
        EXPECT_LE(clouds.cloudCount(), n_max);
    }
    EXPECT_GT(t.compressionCount(), 3u);
    EXPECT_NO_THROW(clouds.requireSameElementsAs(t));
    // Fused elements keep one point per landmark they saw: far fewer points
    // than the frames had.
    EXPECT_LE(clouds.pointCount(), clouds.elementCount() * landmarks.size());
    EXPECT_LT(clouds.pointCount(), frame_points / 4);

    // Another N_max makes other elements, and the check says so.
    ElementClouds other(n_max + 1, CELL);
    for (std::size_t k = 0; k < 80; ++k)
    {
        other.append(k, {});
    }
    EXPECT_THROW(other.requireSameElementsAs(t), std::logic_error);
}

TEST(ElementClouds, pointsLandAtTheirFramesRectifiedPoses)
{
    const auto landmarks = wallLandmarks();
    const std::size_t n_max = 4;
    Trajectory t(mapOptions());
    ElementClouds clouds(n_max, CELL);
    std::vector<std::vector<std::size_t>> seen_by(40);  // landmarks of each frame
    for (std::size_t k = 0; k < 40; ++k)
    {
        const IntensityCloud c = view(truePose(k), landmarks);
        for (std::size_t i = 0; i < landmarks.size(); ++i)
        {
            if (std::abs(truePose(k).inverseComposePoint(landmarks[i]).x) < 3.0)
            {
                seen_by[k].push_back(i);
            }
        }
        const CPose3D action = k == 0 ? truePose(0) : truePose(k) - truePose(k - 1);
        t.append(action, weighted(c), 0.1 * k, k);
        if (t.size() > n_max)
        {
            t.compress();
        }
        clouds.append(k, c);
        clouds.fuse(t.framePoses());
    }
    ASSERT_GE(t.size(), 3u);
    ASSERT_EQ(clouds.cloudCount(), t.size());

    // At the poses the frames had, the map is the wall, one point per landmark.
    std::multimap<std::uint8_t, TPoint3D> wall;
    for (std::size_t i = 0; i < landmarks.size(); ++i)
    {
        wall.emplace(greyOf(i), landmarks[i]);
    }
    expectPointsAt(clouds.worldCloud(t.framePoses()), wall);

    // A rectification changes a_1: the elements from 1 on move with it (a
    // second copy of the landmarks they saw, 0.25 m away), element 0 stays.
    const CPose3D delta(0.25, 0.0, 0.0, 0, 0, 0);
    const CPose3D before = t.pose(1);
    t.changeActions({{1, t.action(1) + delta}});
    const CPose3D M = (before + delta) + (-before);  // world motion of elements 1..N-1
    std::multimap<std::uint8_t, TPoint3D> expected;
    std::vector<bool> in_first(landmarks.size()), in_moved(landmarks.size());
    for (std::size_t i = 0; i < t.size(); ++i)
    {
        for (const auto& f : t.framesOf(i))
        {
            for (std::size_t l : seen_by[f.frame_index])
            {
                (i == 0 ? in_first : in_moved)[l] = true;
            }
        }
    }
    for (std::size_t l = 0; l < landmarks.size(); ++l)
    {
        if (in_first[l])
        {
            expected.emplace(greyOf(l), landmarks[l]);
        }
        if (in_moved[l])
        {
            expected.emplace(greyOf(l), M.composePoint(landmarks[l]));
        }
    }
    expectPointsAt(clouds.worldCloud(t.framePoses()), expected);
}

TEST(ElementClouds, waitsForTheTrajectoryToCompressBeforeFusing)
{
    // As in AnyTime mode: the frame that makes the trajectory compress is
    // still in the runner's buffer, so the rectifier may move the frames yet.
    const auto landmarks = wallLandmarks();
    Trajectory t(mapOptions());
    ElementClouds clouds(4, CELL);
    for (std::size_t k = 0; k < 5; ++k)
    {
        clouds.append(k, view(truePose(k), landmarks));
    }
    for (std::size_t k = 0; k < 4; ++k)
    {
        t.append(k == 0 ? truePose(0) : truePose(k) - truePose(k - 1), {}, 0.1 * k, k);
    }
    EXPECT_EQ(clouds.elementCount(), 3u);
    clouds.fuse(t.framePoses());
    EXPECT_TRUE(clouds.hasPendingFusions());
    EXPECT_EQ(clouds.cloudCount(), 5u);

    t.append(truePose(4) - truePose(3), {}, 0.4, 4);
    t.compress();
    clouds.fuse(t.framePoses());
    EXPECT_FALSE(clouds.hasPendingFusions());
    EXPECT_EQ(clouds.cloudCount(), 3u);
    EXPECT_NO_THROW(clouds.requireSameElementsAs(t));
}

TEST(ElementClouds, withoutCompressionTheMapIsTheUnionOfTheFrameClouds)
{
    const auto landmarks = wallLandmarks();
    Trajectory t(mapOptions());
    ElementClouds clouds(0, CELL);
    IntensityCloud reference;
    for (std::size_t k = 0; k < 12; ++k)
    {
        const IntensityCloud c = view(truePose(k), landmarks);
        t.append(k == 0 ? truePose(0) : truePose(k) - truePose(k - 1), weighted(c), 0.1 * k, k);
        clouds.append(k, c);
        clouds.fuse(t.framePoses());
        reference.appendTransformed(c, t.framePoses().back().T_world_frame);
    }
    EXPECT_EQ(clouds.cloudCount(), 12u);
    reference = emslam::slam::voxelDownsample(reference, CELL);
    const IntensityCloud world = clouds.worldCloud(t.framePoses());
    ASSERT_EQ(world.size(), reference.size());
    for (std::size_t i = 0; i < world.size(); ++i)
    {
        EXPECT_EQ(world.points[i], reference.points[i]);
        EXPECT_EQ(world.intensity[i], reference.intensity[i]);
    }
    EXPECT_THROW(clouds.worldCloud({}), std::logic_error);
}

TEST(ElementClouds, takeScansHandsOverEveryCloudInItsFrame)
{
    const auto landmarks = wallLandmarks();
    Trajectory t(mapOptions());
    ElementClouds clouds(4, CELL);  // compressed: fused elements hold one cloud
    for (std::size_t k = 0; k < 12; ++k)
    {
        const IntensityCloud c = view(truePose(k), landmarks);
        t.append(k == 0 ? truePose(0) : truePose(k) - truePose(k - 1), weighted(c), 0.1 * k, k);
        if (t.size() > 4)
        {
            t.compress();
        }
        clouds.append(k, c);
        clouds.fuse(t.framePoses());
    }
    const IntensityCloud world = clouds.worldCloud(t.framePoses());
    const std::size_t points = clouds.pointCount();
    const auto scans = clouds.takeScans();
    ASSERT_EQ(scans.size(), t.size());
    // Placed at their frames' poses, the scans are the map cloud.
    std::map<std::size_t, CPose3D> pose_of;
    for (const auto& p : t.framePoses())
    {
        pose_of[p.frame_index] = p.T_world_frame;
    }
    IntensityCloud placed;
    std::size_t taken = 0;
    for (std::size_t e = 0; e < scans.size(); ++e)
    {
        EXPECT_EQ(scans[e].frame_index, t.framesOf(e).front().frame_index);
        placed.appendTransformed(scans[e].cloud, pose_of.at(scans[e].frame_index));
        taken += scans[e].cloud.size();
    }
    EXPECT_EQ(taken, points);
    EXPECT_EQ(emslam::slam::voxelDownsample(placed, CELL).size(), world.size());
    EXPECT_EQ(clouds.pointCount(), 0u);
}

TEST(ElementClouds, followsAnAnyTimeRunnerWhileItRectifies)
{
    // Slightly drifted actions, so the rectifier moves the frames while they
    // arrive; fusing an element before the runner compressed it would freeze
    // a relative pose the rectifier changes afterwards.
    const auto landmarks = wallLandmarks();
    emslam::rectify::TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.mode = emslam::rectify::RectificationMode::AnyTime;
    opt.n_max = 4;
    opt.buffer_size = 3;
    opt.vertical_band = false;
    auto runner = emslam::rectify::createRectificationRunner(opt, mapOptions());
    ElementClouds clouds(4, CELL);
    std::vector<IntensityCloud> frames;
    const CPose3D drift(0.002, 0.0, 0.004, mrpt::DEG2RAD(0.02), 0, 0);
    for (std::size_t k = 0; k < 30; ++k)
    {
        frames.push_back(view(truePose(k), landmarks));
        const CPose3D action = k == 0 ? truePose(0) : (truePose(k) - truePose(k - 1)) + drift;
        runner->addFrame(action, weighted(frames.back()), 0.1 * k, k);
        clouds.append(k, frames.back());
        clouds.fuse(runner->framePoses());
    }
    runner->finish();
    const auto poses = runner->framePoses();
    clouds.fuse(poses);
    EXPECT_FALSE(clouds.hasPendingFusions());
    EXPECT_NO_THROW(clouds.requireSameElementsAs(runner->trajectory()));

    // Every point sits where its frames' final poses put it. (The wall is
    // periodic, so the rectifier may align an element one landmark over and
    // a cell may mix two landmarks' grey levels: positions only.)
    std::vector<TPoint3D> expected;
    for (const TimedPose& p : poses)
    {
        for (const auto& q : frames[p.frame_index].points)
        {
            expected.push_back(p.T_world_frame.composePoint(TPoint3D(q)));
        }
    }
    const IntensityCloud world = clouds.worldCloud(poses);
    EXPECT_FALSE(world.empty());
    for (const auto& q : world.points)
    {
        const TPoint3D p(q);
        double nearest = 1e9;
        for (const auto& e : expected)
        {
            nearest = std::min(nearest, (e - p).norm());
        }
        // A cell's centroid lies within the cell of the copies it averages.
        EXPECT_LT(nearest, CELL * std::sqrt(3.0)) << "point " << p.asString();
    }
}
