// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/hwdrivers/CStereoImageFolderCamera.h>
#include <emslam/hwdrivers/SensorStatus.h>
#include <emslam/io/KittiSequence.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CObservationStereoImages.h>

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <string>

using emslam::hwdrivers::CStereoImageFolderCamera;

TEST(CStereoImageFolderCamera, loadsKeysAndRoundTrips)
{
    const mrpt::config::CConfigFileMemory c(
        "[F]\nformat = euroc\nfolder = /data/mav0\nfirst_frame = 4\nmax_frames = 9\nloop = "
        "true\ntimestamps = now\ntime_offset = 123.5\n");
    CStereoImageFolderCamera::TParameters p;
    p.loadFromConfigFile(c, "F");
    EXPECT_EQ(p.format, "euroc");
    EXPECT_EQ(p.folder, "/data/mav0");
    EXPECT_EQ(p.first_frame, 4U);
    EXPECT_EQ(p.max_frames, 9U);
    EXPECT_TRUE(p.loop);
    EXPECT_EQ(p.timestamps, "now");
    EXPECT_EQ(p.time_offset, 123.5);
    mrpt::config::CConfigFileMemory out;
    p.saveToConfigFile(out, "G");
    const mrpt::config::CConfigFileMemory reparsed(out.getContent());
    CStereoImageFolderCamera::TParameters q;
    q.loadFromConfigFile(reparsed, "G");
    EXPECT_EQ(q.format, p.format);
    EXPECT_EQ(q.folder, p.folder);
    EXPECT_EQ(q.first_frame, p.first_frame);
    EXPECT_EQ(q.max_frames, p.max_frames);
    EXPECT_EQ(q.loop, p.loop);
    EXPECT_EQ(q.timestamps, p.timestamps);
    EXPECT_EQ(q.time_offset, p.time_offset);
}

TEST(CStereoImageFolderCamera, invalidValuesThrow)
{
    using emslam::test::expectThrowContaining;
    CStereoImageFolderCamera cam;
    expectThrowContaining(
        [&] {
            cam.loadConfig(mrpt::config::CConfigFileMemory("[F]\nformat = tum\nfolder = x\n"), "F");
        },
        {"format", "tum"});
    expectThrowContaining(
        [&] { cam.loadConfig(mrpt::config::CConfigFileMemory("[F]\nformat = kitti\n"), "F"); },
        {"folder", "mandatory"});
    expectThrowContaining(
        [&]
        { cam.loadConfig(mrpt::config::CConfigFileMemory("[F]\nfolder = /no/such/seq\n"), "F"); },
        {"/no/such/seq", "does not exist"});
    // An existing folder that is not a KITTI sequence: the reader's error is passed on.
    const std::string empty = emslam::test::makeTempDir("folder_cam_empty");
    expectThrowContaining(
        [&]
        { cam.loadConfig(mrpt::config::CConfigFileMemory("[F]\nfolder = " + empty + "\n"), "F"); },
        {"CStereoImageFolderCamera, section F", "image_0"});
    expectThrowContaining(
        [&] {
            cam.loadConfig(
                mrpt::config::CConfigFileMemory("[F]\nfolder = x\nfirst_frame = -2\n"), "F");
        },
        {"first_frame = '-2'", "whole number"});
    expectThrowContaining(
        [&] {
            cam.loadConfig(
                mrpt::config::CConfigFileMemory("[F]\nfolder = x\ntime_offset = nan\n"), "F");
        },
        {"time_offset", "nan", "1e11"});
}

TEST(CStereoImageFolderCamera, replaysKittiFramesAsTheReaderLoadsThem)
{
    EMSLAM_REQUIRE_TEST_DATA(seq_dir, "kitti-odometry/sequences/06");
    CStereoImageFolderCamera cam;
    cam.loadConfig(
        mrpt::config::CConfigFileMemory(
            "[F]\nsensorLabel = STEREO\nfolder = " + seq_dir + "\nfirst_frame = 48\n"),
        "F");
    EXPECT_EQ(cam.folderSize(), 51U);
    // No process_rate: KITTI's ~10 Hz.
    EXPECT_NEAR(cam.getProcessRate(), 10.0, 0.5);
    for (int i = 0; i < 3; ++i)
    {
        cam.doProcess();
    }
    EXPECT_THROW(cam.doProcess(), emslam::hwdrivers::EndOfStream);
    const auto objs = cam.getObservations();
    ASSERT_EQ(objs.size(), 3U);
    emslam::io::KittiSequence ref(seq_dir);
    std::size_t i = 48;
    for (const auto& [t, o] : objs)
    {
        const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(o);
        ASSERT_TRUE(obs);
        EXPECT_TRUE(obs->hasImageRight);
        EXPECT_DOUBLE_EQ(mrpt::Clock::toDouble(obs->timestamp), ref.timestamp(i));
        const auto r = ref.frame(i);
        EXPECT_EQ(
            cv::norm(obs->imageRight.asCvMatRef(), r.obs->imageRight.asCvMatRef(), cv::NORM_INF),
            0.0);
        ++i;
    }
}
