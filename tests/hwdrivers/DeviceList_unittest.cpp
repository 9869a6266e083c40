// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/hwdrivers/DeviceList.h>

#include <gtest/gtest.h>

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
}
