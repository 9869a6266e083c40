// SPDX-License-Identifier: BSD-3-Clause
// map.3Dscene: named objects (cloud, trajectories, ground truth, entropy
// voxels, legend), the ceiling cut, and the scene read back from a file.
#include "MapDrawingFixture.h"
#include "TestData.h"

#include <emslam/apps/EntropyVoxelObject.h>
#include <emslam/apps/MapScene.h>
#include <emslam/apps/MapStyle.h>

#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/CText.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

using namespace emslam::apps;

namespace
{
template <class T>
std::shared_ptr<T> byName(const mrpt::opengl::COpenGLScene& scene, const std::string& name)
{
    return std::dynamic_pointer_cast<T>(
        const_cast<mrpt::opengl::COpenGLScene&>(scene).getByName(name));
}

/** Highest point of the scene's cloud above the first camera [m]. */
double maxHeight(const mrpt::opengl::CPointCloudColoured& cloud)
{
    double h = -1e9;
    for (std::size_t i = 0; i < cloud.size(); ++i)
    {
        h = std::max(h, -static_cast<double>(cloud.getPoint3Df(i).y));
    }
    return h;
}
}  // namespace

TEST(MapScene, hasEveryNamedObjectAndALegendLinePerObject)
{
    const emslam::test::MapDrawingFixture f;
    const std::string file = emslam::test::makeTempDir("map_scene") + "/map.3Dscene";
    writeMapScene(f.content(), file);
    mrpt::opengl::COpenGLScene scene;
    ASSERT_TRUE(scene.loadFromFile(file));

    const auto cloud = byName<mrpt::opengl::CPointCloudColoured>(scene, MAP_CLOUD_NAME);
    ASSERT_TRUE(cloud);
    EXPECT_EQ(cloud->size(), f.cloud.size());
    for (const auto& [name, traj] :
         {std::make_pair(EGOMOTION_NAME, &f.egomotion), std::make_pair(SLAM_NAME, &f.slam),
          std::make_pair(GROUND_TRUTH_NAME, &f.ground_truth)})
    {
        const auto lines = byName<mrpt::opengl::CSetOfLines>(scene, name);
        ASSERT_TRUE(lines) << name;
        EXPECT_EQ(lines->size(), traj->size() - 1) << name;
    }
    const auto loops = byName<mrpt::opengl::CSetOfLines>(scene, LOOPS_NAME);
    ASSERT_TRUE(loops);
    EXPECT_EQ(loops->size(), f.loops.size());
    const auto red = byName<mrpt::opengl::CSetOfLines>(scene, EGOMOTION_NAME)->getColor_u8();
    EXPECT_GT(red.R, 200);
    EXPECT_LT(red.G, 50);

    const auto voxels = byName<mrpt::opengl::CSetOfObjects>(scene, ENTROPY_VOXELS_NAME);
    ASSERT_TRUE(voxels);
    const auto cells =
        std::dynamic_pointer_cast<mrpt::opengl::CPointCloudColoured>(*voxels->begin());
    ASSERT_TRUE(cells);
    EXPECT_GT(cells->size(), 500U);
    EXPECT_LE(cells->size(), 20000U);

    // Legend: cloud, 3 trajectories, loops, voxels, axes.
    const auto legend = byName<mrpt::opengl::CSetOfObjects>(scene, LEGEND_NAME);
    ASSERT_TRUE(legend);
    std::string text;
    std::size_t labels = 0;
    for (const auto& o : *legend)
    {
        if (const auto t = std::dynamic_pointer_cast<mrpt::opengl::CText>(o))
        {
            text += t->getString() + "\n";
            ++labels;
        }
    }
    EXPECT_EQ(labels, 7U) << text;
    for (const char* word :
         {"height", "egomotion", "SLAM", "ground truth", "loop closures: 1", "entropy voxels"})
    {
        EXPECT_NE(text.find(word), std::string::npos) << word << " missing in\n" << text;
    }
}

TEST(MapScene, ceilingCutRemovesThePointsAboveTheHeight)
{
    const emslam::test::MapDrawingFixture f;
    auto c = f.content();
    const auto all = buildMapScene(c);
    const auto full = byName<mrpt::opengl::CPointCloudColoured>(*all, MAP_CLOUD_NAME);
    ASSERT_TRUE(full);
    EXPECT_NEAR(maxHeight(*full), 2.0, 1e-5);  // the ceiling

    c.max_height = 1.5;
    const auto cut_scene = buildMapScene(c);
    const auto cut = byName<mrpt::opengl::CPointCloudColoured>(*cut_scene, MAP_CLOUD_NAME);
    ASSERT_TRUE(cut);
    EXPECT_LE(maxHeight(*cut), 1.5);
    EXPECT_GT(maxHeight(*cut), 1.3);  // the walls stay up to the cut
    // The ceiling (61 x 101 points) and the wall rows above 1.5 m are gone.
    const std::size_t removed = full->size() - cut->size();
    EXPECT_GE(removed, 61U * 101U);
    EXPECT_LT(removed, 61U * 101U * 2);
    bool cut_named = false;
    for (const auto& o : *byName<mrpt::opengl::CSetOfObjects>(*cut_scene, LEGEND_NAME))
    {
        const auto t = std::dynamic_pointer_cast<mrpt::opengl::CText>(o);
        cut_named =
            cut_named || (t && t->getString().find("cut above 1.50 m") != std::string::npos);
    }
    EXPECT_TRUE(cut_named);
}

TEST(MapScene, withoutGroundTruthOrEntropyMapThoseObjectsAreAbsent)
{
    const emslam::test::MapDrawingFixture f;
    auto c = f.content();
    c.ground_truth = nullptr;
    c.entropy_map = nullptr;
    c.loops = nullptr;
    const auto scene = buildMapScene(c);
    EXPECT_FALSE(byName<mrpt::opengl::CSetOfLines>(*scene, GROUND_TRUTH_NAME));
    EXPECT_FALSE(byName<mrpt::opengl::CSetOfLines>(*scene, LOOPS_NAME));
    EXPECT_FALSE(byName<mrpt::opengl::CSetOfObjects>(*scene, ENTROPY_VOXELS_NAME));
    EXPECT_TRUE(byName<mrpt::opengl::CSetOfLines>(*scene, SLAM_NAME));
}

TEST(MapScene, groundTruthIsLaidOnTheEstimate)
{
    // The truth in its own frame: the estimate turned 90° about the vertical
    // and moved; brought into the map frame, it lands on the estimate.
    const emslam::test::MapDrawingFixture f;
    const mrpt::poses::CPose3D T_gt_map(5, -1, 2, 0, M_PI / 2, 0);
    emslam::io::TumTrajectory gt;
    for (const auto& p : f.egomotion.poses)
    {
        gt.add(p.t, T_gt_map + p.pose);
    }
    const auto in_map = groundTruthInMapFrame(gt, f.egomotion);
    ASSERT_EQ(in_map.size(), f.egomotion.size());
    for (std::size_t i = 0; i < in_map.size(); ++i)
    {
        EXPECT_NEAR(in_map.poses[i].pose.distanceTo(f.egomotion.poses[i].pose), 0.0, 1e-6);
    }
}
