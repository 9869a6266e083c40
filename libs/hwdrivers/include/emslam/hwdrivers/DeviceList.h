// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace emslam::hwdrivers
{
/** One device found by listDevices(). \ingroup emslam_hwdrivers_grp */
struct DeviceInfo
{
    /** "IIDC" (a camera libdc1394 can open, IEEE-1394 or USB), "USB" or
     * "V4L2" (a video device node, for CVideoStereoCamera). */
    std::string bus;
    /** IIDC: the camera's 64-bit GUID (the CDigiclopsStereoCamera `camera_guid`). */
    std::uint64_t guid{0};
    /** IIDC: unit number of a multi-unit camera. */
    int unit{0};
    /** USB: vendor and product ids. */
    std::uint16_t vendor_id{0}, product_id{0};
    /** USB: bus number and device address (as in /dev/bus/usb/BBB/DDD). */
    int usb_bus{0}, usb_address{0};
    /** V4L2: the device node, e.g. /dev/video0 (CVideoStereoCamera's `source`). */
    std::string node;
    /** Vendor, model / product and serial strings (empty when unreadable). */
    std::string vendor, model, serial;
    /** Why something could not be read (e.g. permission), or a hint. */
    std::string note;
};

/** What listDevices() found, and why it may have found nothing.
 * \ingroup emslam_hwdrivers_grp */
struct DeviceReport
{
    /** Cameras libdc1394 enumerated (IEEE-1394 and USB IIDC). */
    std::vector<DeviceInfo> iidc_cameras;
    /** All USB devices libusb sees. */
    std::vector<DeviceInfo> usb_devices;
    /** V4L2 video device nodes (listVideoDevices()). */
    std::vector<DeviceInfo> video_devices;
    /** Diagnostics: missing buses, device nodes without permission, library errors. */
    std::vector<std::string> notes;

    /** A human-readable listing (several lines). */
    std::string toText() const;
};

/** USB vendor id of Point Grey Research (now FLIR / Teledyne), the maker of the Digiclops. */
constexpr std::uint16_t POINT_GREY_USB_VENDOR_ID = 0x1e10;

/** Enumerates IIDC cameras through libdc1394 (vendor, model, GUID), every
 * USB device through libusb-1.0 (ids, strings, serial) and the V4L2 video
 * nodes (listVideoDevices()), and checks the device nodes (/dev/fw*,
 * /dev/bus/usb, /dev/video*) so that the report says why a camera is not
 * found. Never throws: problems go to `notes`.
 * \ingroup emslam_hwdrivers_grp */
DeviceReport listDevices();

/** The V4L2 video device nodes `<dev_dir>/videoN`, in N order, with the name
 * the driver gives in `<sysfs_dir>/videoN/name` (model); a node the user
 * cannot open for reading and writing gets a note. Never throws.
 * \ingroup emslam_hwdrivers_grp */
std::vector<DeviceInfo> listVideoDevices(
    const std::string& dev_dir = "/dev", const std::string& sysfs_dir = "/sys/class/video4linux");

}  // namespace emslam::hwdrivers
