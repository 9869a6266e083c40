// SPDX-License-Identifier: BSD-3-Clause
// CMapSession: a saved session reads back to the bit, and a file that is
// not one (missing, truncated, another MRPT object, random bytes, a session
// that contradicts itself) is refused naming the file and the cause.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/slam/CMapSession.h>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

using emslam::slam::CMapSession;
using mrpt::poses::CPose3D;

namespace
{
/** Three frames, two keyframes joined by an odometry and a loop edge, one scan. */
CMapSession sampleSession()
{
    CMapSession s;
    s.config = "[EntropySlam]\nmap_cell_size = 0.1\n";
    for (std::size_t i = 0; i < 3; ++i)
    {
        CMapSession::Frame f;
        f.timestamp = 1700000000.25 + 0.2 * static_cast<double>(i);
        f.keyframe = i < 2 ? 0 : 2;
        f.T_keyframe_frame = CPose3D(0.1 * static_cast<double>(i), 0.02, 0, 0.01, 0, 0);
        f.egomotion = CPose3D(0.3 * static_cast<double>(i), 0, 0.1, 0.2, 0.05, -0.03);
        f.online = CPose3D(0.29 * static_cast<double>(i), 0, 0.1, 0.2, 0.05, -0.03);
        f.accepted = i != 1;
        f.egomotion_ok = i != 1;
        f.final_matches = 40 + i;
        s.frames.push_back(f);
    }
    for (const std::size_t frame : {std::size_t{0}, std::size_t{2}})
    {
        emslam::slam::LoopCloser::Snapshot::Keyframe k;
        k.frame_index = frame;
        emslam::egomotion::Feature f;
        f.u = 12;
        f.v = 200;
        f.point = {0.5f, -0.25f, 3.0f};
        f.gradient_angle = 1.5f;
        f.gradient_magnitude = 80.0f;
        k.kept.features = {f, f};
        k.kept.dim = 3;
        k.kept.codes = {1, -2, 3, 127, -128, 0};
        k.kept.scales = {0.01f, 0.02f};
        k.kept.camera.fx(200);
        k.kept.baseline = 0.1;
        for (int d = 0; d < 6; ++d)
        {
            k.covariance(d, d) = 1e-4 * (d + 1);
        }
        k.covariance(0, 1) = k.covariance(1, 0) = 2e-5;
        if (frame > 0)
        {
            k.motion = CPose3D(0.6, 0, 0.2, 0.4, 0, 0);
            k.predicted = true;
            emslam::stereo::VerticalMeasurement v;
            v.up = {0.01, -0.999, 0.02};
            v.covariance(0, 0) = 1e-3;
            v.patches = 7;
            v.dispersion = 1.3;
            k.vertical = v;
        }
        s.graph.keyframes.push_back(k);
    }
    s.graph.nodes = {CPose3D(), CPose3D(0.6, 0, 0.2, 0.4, 0, 0)};
    emslam::rectify::PoseGraph::Edge odometry{0, 1, CPose3D(0.6, 0, 0.2, 0.4, 0, 0), {}, 0};
    odometry.information(2, 2) = 1e4;
    emslam::rectify::PoseGraph::Edge loop{1, 0, CPose3D(-0.5, 0, 0, -0.4, 0, 0), {}, 2};
    loop.information(5, 5) = 3e3;
    s.graph.edges = {odometry, loop};
    s.graph.loop_edges = {{2, 0, CPose3D(-0.5, 0, 0, -0.4, 0, 0), 57}};
    s.graph.loop_tag = 2;
    s.graph.local_misclosures = {3.5, 7.25};
    s.graph.largest_step_t = 0.61;
    s.graph.largest_step_r = 0.41;
    s.keyframe_poses = {CPose3D(0, 0, 0, 0.01, 0, 0), CPose3D(0.6, 0, 0.2, 0.41, 0, 0)};
    emslam::slam::KeyframeScan scan;
    scan.frame_index = 2;
    scan.cloud.points = {{1, 2, 3}, {-1, 0.5f, 4}};
    scan.cloud.intensity = {10, 250};
    scan.cloud.sigma = {0.01f, 0.2f};
    s.scans = {scan};
    return s;
}

std::string bytesOf(const std::string& file)
{
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void expectSamePose(const CPose3D& a, const CPose3D& b)
{
    EXPECT_EQ(
        a.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>(),
        b.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>());
}
}  // namespace

TEST(CMapSession, readsBackWhatItSaved)
{
    const std::string file = emslam::test::makeTempDir("map_session") + "/s.session";
    const CMapSession s = sampleSession();
    s.save(file);
    const auto r = CMapSession::load(file);
    EXPECT_EQ(r->config, s.config);
    ASSERT_EQ(r->frames.size(), 3U);
    for (std::size_t i = 0; i < 3; ++i)
    {
        EXPECT_EQ(r->frames[i].timestamp, s.frames[i].timestamp);
        EXPECT_EQ(r->frames[i].keyframe, s.frames[i].keyframe);
        expectSamePose(r->frames[i].T_keyframe_frame, s.frames[i].T_keyframe_frame);
        expectSamePose(r->frames[i].egomotion, s.frames[i].egomotion);
        expectSamePose(r->frames[i].online, s.frames[i].online);
        EXPECT_EQ(r->frames[i].accepted, s.frames[i].accepted);
        EXPECT_EQ(r->frames[i].egomotion_ok, s.frames[i].egomotion_ok);
        EXPECT_EQ(r->frames[i].final_matches, s.frames[i].final_matches);
    }
    ASSERT_EQ(r->graph.keyframes.size(), 2U);
    const auto& k = r->graph.keyframes[1];
    const auto& k0 = s.graph.keyframes[1];
    EXPECT_EQ(k.frame_index, 2U);
    ASSERT_EQ(k.kept.features.size(), 2U);
    EXPECT_EQ(k.kept.features[1].u, 12);
    EXPECT_EQ(k.kept.features[1].v, 200);
    EXPECT_EQ(k.kept.features[1].point.z, 3.0f);
    EXPECT_EQ(k.kept.features[1].gradient_angle, 1.5f);
    EXPECT_EQ(k.kept.codes, k0.kept.codes);
    EXPECT_EQ(k.kept.scales, k0.kept.scales);
    EXPECT_EQ(k.kept.dim, 3);
    EXPECT_EQ(k.kept.camera.fx(), 200);
    EXPECT_EQ(k.kept.baseline, 0.1);
    EXPECT_EQ(k.covariance, k0.covariance);
    ASSERT_TRUE(k.motion.has_value());
    expectSamePose(*k.motion, *k0.motion);
    EXPECT_TRUE(k.predicted);
    ASSERT_TRUE(k.vertical.has_value());
    EXPECT_EQ(k.vertical->up.y, -0.999);
    EXPECT_EQ(k.vertical->covariance, k0.vertical->covariance);
    EXPECT_EQ(k.vertical->patches, 7U);
    EXPECT_FALSE(r->graph.keyframes[0].motion.has_value());
    EXPECT_FALSE(r->graph.keyframes[0].vertical.has_value());
    ASSERT_EQ(r->graph.edges.size(), 2U);
    EXPECT_EQ(r->graph.edges[1].from, 1U);
    EXPECT_EQ(r->graph.edges[1].tag, 2U);
    EXPECT_EQ(r->graph.edges[1].information, s.graph.edges[1].information);
    expectSamePose(r->graph.edges[0].measurement, s.graph.edges[0].measurement);
    ASSERT_EQ(r->graph.loop_edges.size(), 1U);
    EXPECT_EQ(r->graph.loop_edges[0].matches, 57U);
    EXPECT_EQ(r->graph.local_misclosures, s.graph.local_misclosures);
    EXPECT_EQ(r->graph.largest_step_r, 0.41);
    expectSamePose(r->keyframe_poses[1], s.keyframe_poses[1]);
    ASSERT_EQ(r->scans.size(), 1U);
    EXPECT_EQ(r->scans[0].frame_index, 2U);
    EXPECT_EQ(r->scans[0].cloud.points[1].y, 0.5f);
    EXPECT_EQ(r->scans[0].cloud.intensity, s.scans[0].cloud.intensity);
    EXPECT_EQ(r->scans[0].cloud.sigma, s.scans[0].cloud.sigma);
    // Saved again, the same bytes.
    const std::string again = file + ".again";
    r->save(again);
    EXPECT_EQ(bytesOf(again), bytesOf(file));
}

TEST(CMapSession, whatIsNotASessionIsRefusedNamingFileAndCause)
{
    const std::string dir = emslam::test::makeTempDir("map_session_bad");
    emslam::test::expectThrowContaining(
        [&] { CMapSession::load(dir + "/missing.session"); }, {"missing.session", "cannot open"});

    const std::string good = dir + "/good.session";
    sampleSession().save(good);
    const std::string bytes = bytesOf(good);
    const std::string truncated = dir + "/truncated.session";
    emslam::test::writeFile(truncated, bytes.substr(0, bytes.size() / 2));
    emslam::test::expectThrowContaining(
        [&] { CMapSession::load(truncated); }, {"truncated.session", "not a readable"});

    const std::string noise = dir + "/noise.session";
    emslam::test::writeFile(noise, "this is a text file, not an archive\n");
    emslam::test::expectThrowContaining(
        [&] { CMapSession::load(noise); }, {"noise.session", "not a readable"});

    const std::string foreign = dir + "/pose.session";
    {
        mrpt::io::CFileGZOutputStream f(foreign);
        auto out = mrpt::serialization::archiveFrom(f);
        out << CPose3D(1, 2, 3, 0, 0, 0);
    }
    emslam::test::expectThrowContaining(
        [&] { CMapSession::load(foreign); }, {"pose.session", "CPose3D", "not an emslam session"});

    // A session whose keyframes are not its frames.
    CMapSession bad = sampleSession();
    bad.graph.keyframes[1].frame_index = 7;
    emslam::test::expectThrowContaining(
        [&] { bad.save(dir + "/bad.session"); }, {"inconsistent session", "frame 7"});
    CMapSession few = sampleSession();
    few.keyframe_poses.pop_back();
    emslam::test::expectThrowContaining([&] { few.validate(); }, {"2 keyframes", "1 world poses"});
}

TEST(CMapSession, aFailedSaveLeavesTheFormerFileWhole)
{
    const std::string dir = emslam::test::makeTempDir("map_session_keep");
    const std::string file = dir + "/s.session";
    sampleSession().save(file);
    const std::string before = bytesOf(file);
    CMapSession bad = sampleSession();
    bad.keyframe_poses.clear();
    EXPECT_ANY_THROW(bad.save(file));
    EXPECT_EQ(bytesOf(file), before);
    EXPECT_NO_THROW(CMapSession::load(file));
}
