// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/hwdrivers/DeviceList.h>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

TEST(DeviceList, reportsWhatItFoundAndWhy)
{
    const auto r = emslam::hwdrivers::listDevices();
    const std::string text = r.toText();
    EXPECT_NE(
        text.find(
            "IIDC cameras (libdc1394, IEEE-1394 and USB): " +
            std::to_string(r.iidc_cameras.size())),
        std::string::npos)
        << text;
    EXPECT_NE(
        text.find("USB devices (libusb-1.0): " + std::to_string(r.usb_devices.size())),
        std::string::npos)
        << text;
    std::error_code ec;
    if (!std::filesystem::exists("/dev/bus/usb", ec))
    {
        // No USB controller is visible (a container): the report says so.
        EXPECT_TRUE(r.usb_devices.empty());
        EXPECT_NE(text.find("no /dev/bus/usb"), std::string::npos) << text;
    }
    if (r.iidc_cameras.empty())
    {
        EXPECT_NE(text.find("No camera usable by CDigiclopsStereoCamera"), std::string::npos);
        EXPECT_FALSE(r.notes.empty());
    }
    for (const auto& d : r.usb_devices)
    {
        EXPECT_EQ(d.bus, "USB");
        EXPECT_GT(d.usb_bus, 0);
    }
    EXPECT_NE(
        text.find(
            "V4L2 video devices (CVideoStereoCamera source): " +
            std::to_string(r.video_devices.size())),
        std::string::npos)
        << text;
    if (r.video_devices.empty())
    {
        EXPECT_NE(text.find("no /dev/video* device nodes"), std::string::npos) << text;
    }
}

// Video nodes in number order, named from sysfs, without permission noted.
TEST(DeviceList, listsVideoNodesWithTheirNames)
{
    const std::string dir = emslam::test::makeTempDir("device_list_v4l2");
    std::filesystem::create_directories(dir + "/dev");
    for (const char* n : {"video10", "video2", "videox", "vide", "tty0"})
    {
        emslam::test::writeFile(dir + "/dev/" + n, "");
    }
    std::filesystem::create_directories(dir + "/sys/video2");
    emslam::test::writeFile(dir + "/sys/video2/name", "ZED 2i: ZED 2i\n");
    ::chmod((dir + "/dev/video10").c_str(), 0);
    const auto v = emslam::hwdrivers::listVideoDevices(dir + "/dev", dir + "/sys");
    ASSERT_EQ(v.size(), 2U);
    EXPECT_EQ(v[0].node, dir + "/dev/video2");
    EXPECT_EQ(v[0].bus, "V4L2");
    EXPECT_EQ(v[0].model, "ZED 2i: ZED 2i");
    EXPECT_TRUE(v[0].note.empty());
    EXPECT_EQ(v[1].node, dir + "/dev/video10");
    EXPECT_TRUE(v[1].model.empty());
    // root reads any file: the permission note is then absent.
    if (::geteuid() != 0)
    {
        EXPECT_NE(v[1].note.find("permission"), std::string::npos);
    }
    EXPECT_TRUE(emslam::hwdrivers::listVideoDevices(dir + "/none", dir + "/sys").empty());
}
