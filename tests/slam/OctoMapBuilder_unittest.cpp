// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/OctoMapBuilder.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <stdexcept>

using emslam::slam::KeyframeScan;
using emslam::slam::OctoMapBuilder;

namespace
{
/** A 2 x 2 m wall 3 m ahead of the camera (z = 3), a point every 5 cm. */
KeyframeScan wallScan(std::size_t frame)
{
    KeyframeScan s;
    s.frame_index = frame;
    for (int i = -20; i <= 20; ++i)
    {
        for (int j = -20; j <= 20; ++j)
        {
            s.cloud.points.emplace_back(0.05F * i, 0.05F * j, 3.0F);
            s.cloud.intensity.push_back(100);
        }
    }
    return s;
}

emslam::rectify::TimedPose poseAt(std::size_t frame, double x)
{
    emslam::rectify::TimedPose p;
    p.frame_index = frame;
    p.T_world_frame = mrpt::poses::CPose3D(x, 0, 0, 0, 0, 0);
    return p;
}

/** +1 occupied, -1 free, 0 unknown. */
int state(const octomap::OcTree& t, double x, double y, double z)
{
    const auto* n = t.search(x, y, z);
    return n == nullptr ? 0 : (t.isNodeOccupied(n) ? 1 : -1);
}
}  // namespace

TEST(OctoMapBuilder, wallsAreOccupiedAndTheSpaceBeforeThemFree)
{
    OctoMapBuilder::TParameters p;
    p.resolution = 0.1;
    p.max_range = 6;
    OctoMapBuilder b(p);
    // Two scans of the same wall from 0.5 m apart; a third whose frame has no pose.
    const auto tree =
        b.build({wallScan(3), wallScan(7), wallScan(9)}, {poseAt(3, 0.0), poseAt(7, 0.5)});
    ASSERT_TRUE(tree);
    EXPECT_DOUBLE_EQ(tree->getResolution(), 0.1);
    EXPECT_EQ(b.stats().scans, 2U);
    EXPECT_EQ(b.stats().points, 2U * 41 * 41);
    // Frame 7's wall is 0.5 m to the right: x in [-0.5, 1.5] at z = 3.
    EXPECT_EQ(state(*tree, 0.25, 0.25, 3.0), 1);
    EXPECT_EQ(state(*tree, 1.25, 0.25, 3.0), 1);
    EXPECT_EQ(state(*tree, 0.25, 0.25, 1.5), -1);
    EXPECT_EQ(state(*tree, 0.05, 0.05, 0.35), -1);
    EXPECT_EQ(state(*tree, 0.25, 0.25, 3.5), 0) << "behind the wall: never seen";
    EXPECT_EQ(state(*tree, 0.25, 2.5, 1.5), 0) << "outside every ray";
}

TEST(OctoMapBuilder, raysBeyondMaxRangeOnlyCarveFreeSpace)
{
    OctoMapBuilder::TParameters p;
    p.max_range = 2.0;
    OctoMapBuilder b(p);
    const auto tree = b.build({wallScan(0)}, {poseAt(0, 0.0)});
    EXPECT_EQ(state(*tree, 0.05, 0.05, 1.5), -1);
    EXPECT_EQ(state(*tree, 0.05, 0.05, 3.0), 0);
    EXPECT_EQ(state(*tree, 0.05, 0.05, 2.5), 0);
}

TEST(OctoMapBuilder, parametersRoundTripAndBadOnesAreRefused)
{
    OctoMapBuilder::TParameters p;
    p.resolution = 0.2;
    p.max_range = 9;
    mrpt::config::CConfigFileMemory c;
    p.saveToConfigFile(c, "OctoMapBuilder");
    mrpt::config::CConfigFileMemory reparsed(c.getContent());
    OctoMapBuilder::TParameters q;
    q.loadFromConfigFile(reparsed, "OctoMapBuilder");
    EXPECT_DOUBLE_EQ(q.resolution, 0.2);
    EXPECT_DOUBLE_EQ(q.max_range, 9);

    p.resolution = 0.001;
    EXPECT_THROW(p.validate(), std::invalid_argument);
    p.resolution = 0.1;
    p.max_range = 0;
    EXPECT_THROW(OctoMapBuilder{p}, std::invalid_argument);
    p.max_range = 6;
    p.resolution = 0;
    EXPECT_THROW(OctoMapBuilder(p).build({}, {}), std::invalid_argument);
}
