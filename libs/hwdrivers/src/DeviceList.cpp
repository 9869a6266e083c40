// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/hwdrivers/DeviceList.h>

#include <dc1394/dc1394.h>
#include <libusb-1.0/libusb.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace emslam::hwdrivers
{
namespace
{
std::string hex(std::uint64_t v, int digits)
{
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%0*llx", digits, static_cast<unsigned long long>(v));
    return buf;
}

std::string dec3(int v)
{
    char buf[16];
    std::snprintf(buf, sizeof(buf), "%03d", v);
    return buf;
}

void checkFirewireNodes(DeviceReport& r)
{
    std::error_code ec;
    int n = 0;
    if (fs::is_directory("/dev", ec))
    {
        for (const auto& e : fs::directory_iterator("/dev", ec))
        {
            const std::string name = e.path().filename().string();
            if (name.rfind("fw", 0) != 0)
            {
                continue;
            }
            ++n;
            if (::access(e.path().c_str(), R_OK | W_OK) != 0)
            {
                r.notes.push_back(
                    "IEEE-1394: no read/write permission on " + e.path().string() +
                    " (add a udev rule or join its group)");
            }
        }
    }
    if (n == 0)
    {
        r.notes.push_back(
            "IEEE-1394: no /dev/fw* device nodes (no FireWire controller, or the firewire-ohci "
            "kernel module is not loaded)");
    }
}

std::string usbString(libusb_device_handle* h, std::uint8_t index)
{
    if (h == nullptr || index == 0)
    {
        return {};
    }
    unsigned char buf[256];
    const int n = libusb_get_string_descriptor_ascii(h, index, buf, sizeof(buf));
    return n > 0 ? std::string(reinterpret_cast<char*>(buf), static_cast<std::size_t>(n))
                 : std::string();
}

void listIidc(DeviceReport& r)
{
    dc1394_t* ctx = dc1394_new();
    if (ctx == nullptr)
    {
        r.notes.push_back("libdc1394: dc1394_new() failed (no IEEE-1394 or USB access)");
        return;
    }
    dc1394camera_list_t* list = nullptr;
    const dc1394error_t err = dc1394_camera_enumerate(ctx, &list);
    if (err != DC1394_SUCCESS || list == nullptr)
    {
        r.notes.push_back(
            std::string("libdc1394: camera enumeration failed: ") + dc1394_error_get_string(err));
        dc1394_free(ctx);
        return;
    }
    for (std::uint32_t i = 0; i < list->num; ++i)
    {
        DeviceInfo d;
        d.bus = "IIDC";
        d.guid = list->ids[i].guid;
        d.unit = list->ids[i].unit;
        dc1394camera_t* cam = dc1394_camera_new_unit(ctx, d.guid, d.unit);
        if (cam != nullptr)
        {
            d.vendor = cam->vendor != nullptr ? cam->vendor : "";
            d.model = cam->model != nullptr ? cam->model : "";
            d.vendor_id = static_cast<std::uint16_t>(cam->vendor_id);
            d.product_id = static_cast<std::uint16_t>(cam->model_id);
            dc1394_camera_free(cam);
        }
        else
        {
            d.note = "enumerated but cannot be opened (permission on its device node?)";
        }
        r.iidc_cameras.push_back(d);
    }
    dc1394_camera_free_list(list);
    dc1394_free(ctx);
}

void listUsb(DeviceReport& r)
{
    std::error_code ec;
    if (!fs::is_directory("/dev/bus/usb", ec))
    {
        r.notes.push_back(
            "USB: no /dev/bus/usb (no USB controller visible, e.g. inside a container)");
    }
    libusb_context* ctx = nullptr;
    const int rc = libusb_init(&ctx);
    if (rc != 0)
    {
        r.notes.push_back(std::string("libusb: initialisation failed: ") + libusb_error_name(rc));
        return;
    }
    libusb_device** devs = nullptr;
    const ssize_t n = libusb_get_device_list(ctx, &devs);
    if (n < 0)
    {
        r.notes.push_back(
            std::string("libusb: cannot list devices: ") + libusb_error_name(static_cast<int>(n)));
        libusb_exit(ctx);
        return;
    }
    for (ssize_t i = 0; i < n; ++i)
    {
        libusb_device_descriptor desc{};
        if (libusb_get_device_descriptor(devs[i], &desc) != 0)
        {
            continue;
        }
        DeviceInfo d;
        d.bus = "USB";
        d.vendor_id = desc.idVendor;
        d.product_id = desc.idProduct;
        d.usb_bus = libusb_get_bus_number(devs[i]);
        d.usb_address = libusb_get_device_address(devs[i]);
        libusb_device_handle* h = nullptr;
        const int orc = libusb_open(devs[i], &h);
        if (orc == 0)
        {
            d.vendor = usbString(h, desc.iManufacturer);
            d.model = usbString(h, desc.iProduct);
            d.serial = usbString(h, desc.iSerialNumber);
            libusb_close(h);
        }
        else
        {
            d.note =
                std::string("strings unreadable: ") + libusb_error_name(orc) +
                (orc == LIBUSB_ERROR_ACCESS ? " (no permission on /dev/bus/usb/" + dec3(d.usb_bus) +
                                                  "/" + dec3(d.usb_address) + "; add a udev rule)"
                                            : std::string());
        }
        if (d.vendor_id == POINT_GREY_USB_VENDOR_ID)
        {
            d.note += (d.note.empty() ? "" : "; ") + std::string("Point Grey / FLIR camera");
        }
        r.usb_devices.push_back(d);
    }
    libusb_free_device_list(devs, 1);
    libusb_exit(ctx);
}

/** N of "videoN", or -1. */
long videoNumber(const std::string& name)
{
    if (name.size() <= 5 || name.compare(0, 5, "video") != 0 || name.size() > 12 ||
        !std::all_of(
            name.begin() + 5, name.end(), [](unsigned char c) { return std::isdigit(c) != 0; }))
    {
        return -1;
    }
    return std::stol(name.substr(5));
}
}  // namespace

std::vector<DeviceInfo> listVideoDevices(const std::string& dev_dir, const std::string& sysfs_dir)
{
    std::vector<std::pair<long, DeviceInfo>> found;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dev_dir, ec))
    {
        const std::string name = e.path().filename().string();
        const long n = videoNumber(name);
        if (n < 0)
        {
            continue;
        }
        DeviceInfo d;
        d.bus = "V4L2";
        d.node = e.path().string();
        std::ifstream in(sysfs_dir + "/" + name + "/name");
        std::getline(in, d.model);
        if (::access(d.node.c_str(), R_OK | W_OK) != 0)
        {
            d.note = "no read/write permission (add the user to the 'video' group)";
        }
        found.emplace_back(n, d);
    }
    std::sort(
        found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<DeviceInfo> out;
    for (auto& [n, d] : found)
    {
        out.push_back(std::move(d));
    }
    return out;
}

DeviceReport listDevices()
{
    DeviceReport r;
    checkFirewireNodes(r);
    listIidc(r);
    listUsb(r);
    r.video_devices = listVideoDevices();
    if (r.video_devices.empty())
    {
        r.notes.push_back(
            "V4L2: no /dev/video* device nodes (no UVC / V4L2 camera connected, or none visible, "
            "e.g. inside a container)");
    }
    return r;
}

std::string DeviceReport::toText() const
{
    std::ostringstream s;
    s << "IIDC cameras (libdc1394, IEEE-1394 and USB): " << iidc_cameras.size() << "\n";
    for (const auto& d : iidc_cameras)
    {
        s << "  GUID 0x" << hex(d.guid, 16) << " unit " << d.unit << "  vendor '" << d.vendor
          << "' (0x" << hex(d.vendor_id, 4) << ")  model '" << d.model << "' (0x"
          << hex(d.product_id, 4) << ")";
        if (!d.note.empty())
        {
            s << "  [" << d.note << "]";
        }
        s << "\n";
    }
    s << "USB devices (libusb-1.0): " << usb_devices.size() << "\n";
    for (const auto& d : usb_devices)
    {
        s << "  bus " << dec3(d.usb_bus) << " device " << dec3(d.usb_address) << "  "
          << hex(d.vendor_id, 4) << ":" << hex(d.product_id, 4);
        if (!d.vendor.empty() || !d.model.empty())
        {
            s << "  '" << d.vendor << "' '" << d.model << "'";
        }
        if (!d.serial.empty())
        {
            s << "  serial " << d.serial;
        }
        if (!d.note.empty())
        {
            s << "  [" << d.note << "]";
        }
        s << "\n";
    }
    s << "V4L2 video devices (CVideoStereoCamera source): " << video_devices.size() << "\n";
    for (const auto& d : video_devices)
    {
        s << "  " << d.node << "  '" << d.model << "'";
        if (!d.note.empty())
        {
            s << "  [" << d.note << "]";
        }
        s << "\n";
    }
    for (const auto& n : notes)
    {
        s << "note: " << n << "\n";
    }
    if (iidc_cameras.empty())
    {
        s << "No camera usable by CDigiclopsStereoCamera was found.\n";
    }
    if (video_devices.empty())
    {
        s << "No camera usable by CVideoStereoCamera was found (video files and GStreamer "
             "pipelines need none).\n";
    }
    return s.str();
}

}  // namespace emslam::hwdrivers
