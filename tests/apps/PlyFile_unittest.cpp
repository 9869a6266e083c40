// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/PlyFile.h>

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

using emslam::apps::loadPly;

TEST(PlyFile, referenceSurfaceRoundTrips)
{
    emslam::eval::ReferenceSurface r;
    r.spacing = 0.025;
    for (int i = 0; i < 100; ++i)
    {
        const auto f = static_cast<float>(i);
        r.points.emplace_back(f, -f / 3, 0.5F);
        r.normals.emplace_back(0.0F, 0.6F, 0.8F);
        r.seen_range.push_back(f / 10);
    }
    const std::string file = emslam::test::makeTempDir("ply_ref") + "/ref.ply";
    emslam::apps::saveReferencePly(r, file);
    const auto back = loadPly(file);
    EXPECT_DOUBLE_EQ(back.spacing, 0.025);
    ASSERT_EQ(back.points.size(), 100U);
    ASSERT_EQ(back.normals.size(), 100U);
    ASSERT_EQ(back.seen_range.size(), 100U);
    for (std::size_t i = 0; i < 100; ++i)
    {
        EXPECT_EQ(back.points[i], r.points[i]);
        EXPECT_EQ(back.normals[i], r.normals[i]);
        EXPECT_EQ(back.seen_range[i], r.seen_range[i]);
    }
}

TEST(PlyFile, readsTheMappersCloudAndAsciiFiles)
{
    const std::string dir = emslam::test::makeTempDir("ply_read");
    emslam::slam::IntensityCloud cloud;
    cloud.points = {{1, 2, 3}, {-4, 5.5F, 6}};
    cloud.intensity = {10, 200};
    emslam::apps::savePly(cloud, dir + "/map.ply");
    const auto map = loadPly(dir + "/map.ply");
    ASSERT_EQ(map.points.size(), 2U);
    EXPECT_EQ(map.points[1], cloud.points[1]);
    EXPECT_TRUE(map.normals.empty());
    EXPECT_TRUE(map.seen_range.empty());
    EXPECT_EQ(map.spacing, 0.0);

    emslam::test::writeFile(
        dir + "/a.ply",
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty short y\n"
        "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"
        "0.5 -3 2\n1e-3 7 -1\n");
    const auto a = loadPly(dir + "/a.ply");
    ASSERT_EQ(a.points.size(), 2U);
    EXPECT_EQ(a.points[0], mrpt::math::TPoint3Df(0.5F, -3.0F, 2.0F));
    EXPECT_EQ(a.points[1], mrpt::math::TPoint3Df(0.001F, 7.0F, -1.0F));
}

TEST(PlyFile, badFilesNameTheFileAndTheCause)
{
    const std::string dir = emslam::test::makeTempDir("ply_bad");
    const auto expectBad = [&](const std::string& text, const std::string& cause)
    {
        emslam::test::writeFile(dir + "/b.ply", text);
        emslam::test::expectThrowContaining(
            [&] { loadPly(dir + "/b.ply"); }, {dir + "/b.ply", cause});
    };
    expectBad("solid stl\n", "not a PLY file");
    expectBad(
        "ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n",
        "unsupported PLY format");
    expectBad(
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n", "no x, y, z");
    expectBad(
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n1 2 3\n4 5\n",
        "short or holds a bad number");
    expectBad(
        "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
        "property float y\nproperty float z\nend_header\n0123456789",
        "truncated");
    expectBad("ply\nformat ascii 1.0\nelement vertex 1\n", "no end_header");
    emslam::test::expectThrowContaining(
        [&] { loadPly(dir + "/none.ply"); }, {"cannot open", "none.ply"});
}
