// SPDX-License-Identifier: BSD-3-Clause
// CDigiclopsStereoCamera: the libdc1394 half (open, configure, capture, close).
#include <emslam/hwdrivers/CDigiclopsStereoCamera.h>
#include <emslam/hwdrivers/DeviceList.h>

#include <mrpt/core/format.h>

#include <dc1394/dc1394.h>

#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

namespace emslam::hwdrivers
{
struct CDigiclopsStereoCamera::Device
{
    dc1394_t* ctx{nullptr};
    dc1394camera_t* cam{nullptr};
    bool capturing{false};
    bool transmitting{false};
    double last_timestamp_us{-1.0};
    double frame_period_us{0.0};

    Device() = default;
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;
    ~Device()
    {
        if (transmitting)
        {
            dc1394_video_set_transmission(cam, DC1394_OFF);
        }
        if (capturing)
        {
            dc1394_capture_stop(cam);
        }
        if (cam != nullptr)
        {
            dc1394_camera_free(cam);
        }
        if (ctx != nullptr)
        {
            dc1394_free(ctx);
        }
    }
};

namespace
{
const std::vector<std::pair<const char*, dc1394video_mode_t>>& videoModes()
{
    static const std::vector<std::pair<const char*, dc1394video_mode_t>> modes = {
        {"160x120_YUV444", DC1394_VIDEO_MODE_160x120_YUV444},
        {"320x240_YUV422", DC1394_VIDEO_MODE_320x240_YUV422},
        {"640x480_YUV411", DC1394_VIDEO_MODE_640x480_YUV411},
        {"640x480_YUV422", DC1394_VIDEO_MODE_640x480_YUV422},
        {"640x480_RGB8", DC1394_VIDEO_MODE_640x480_RGB8},
        {"640x480_MONO8", DC1394_VIDEO_MODE_640x480_MONO8},
        {"640x480_MONO16", DC1394_VIDEO_MODE_640x480_MONO16},
        {"800x600_YUV422", DC1394_VIDEO_MODE_800x600_YUV422},
        {"800x600_RGB8", DC1394_VIDEO_MODE_800x600_RGB8},
        {"800x600_MONO8", DC1394_VIDEO_MODE_800x600_MONO8},
        {"800x600_MONO16", DC1394_VIDEO_MODE_800x600_MONO16},
        {"1024x768_YUV422", DC1394_VIDEO_MODE_1024x768_YUV422},
        {"1024x768_RGB8", DC1394_VIDEO_MODE_1024x768_RGB8},
        {"1024x768_MONO8", DC1394_VIDEO_MODE_1024x768_MONO8},
        {"1024x768_MONO16", DC1394_VIDEO_MODE_1024x768_MONO16},
        {"1280x960_YUV422", DC1394_VIDEO_MODE_1280x960_YUV422},
        {"1280x960_RGB8", DC1394_VIDEO_MODE_1280x960_RGB8},
        {"1280x960_MONO8", DC1394_VIDEO_MODE_1280x960_MONO8},
        {"1280x960_MONO16", DC1394_VIDEO_MODE_1280x960_MONO16},
        {"1600x1200_YUV422", DC1394_VIDEO_MODE_1600x1200_YUV422},
        {"1600x1200_RGB8", DC1394_VIDEO_MODE_1600x1200_RGB8},
        {"1600x1200_MONO8", DC1394_VIDEO_MODE_1600x1200_MONO8},
        {"1600x1200_MONO16", DC1394_VIDEO_MODE_1600x1200_MONO16},
        {"FORMAT7_0", DC1394_VIDEO_MODE_FORMAT7_0},
        {"FORMAT7_1", DC1394_VIDEO_MODE_FORMAT7_1},
        {"FORMAT7_2", DC1394_VIDEO_MODE_FORMAT7_2},
        {"FORMAT7_3", DC1394_VIDEO_MODE_FORMAT7_3},
        {"FORMAT7_4", DC1394_VIDEO_MODE_FORMAT7_4},
        {"FORMAT7_5", DC1394_VIDEO_MODE_FORMAT7_5},
        {"FORMAT7_6", DC1394_VIDEO_MODE_FORMAT7_6},
        {"FORMAT7_7", DC1394_VIDEO_MODE_FORMAT7_7},
    };
    return modes;
}

std::string modeName(dc1394video_mode_t m)
{
    for (const auto& [name, mode] : videoModes())
    {
        if (mode == m)
        {
            return name;
        }
    }
    return "mode#" + std::to_string(static_cast<int>(m));
}

const std::vector<std::pair<double, dc1394framerate_t>>& frameRates()
{
    static const std::vector<std::pair<double, dc1394framerate_t>> rates = {
        {1.875, DC1394_FRAMERATE_1_875}, {3.75, DC1394_FRAMERATE_3_75}, {7.5, DC1394_FRAMERATE_7_5},
        {15, DC1394_FRAMERATE_15},       {30, DC1394_FRAMERATE_30},     {60, DC1394_FRAMERATE_60},
        {120, DC1394_FRAMERATE_120},     {240, DC1394_FRAMERATE_240},
    };
    return rates;
}

double rateValue(dc1394framerate_t r)
{
    for (const auto& [v, rate] : frameRates())
    {
        if (rate == r)
        {
            return v;
        }
    }
    return 0.0;
}

/** Why no camera was found, from the device report. */
std::string noCameraDiagnosis()
{
    const DeviceReport r = listDevices();
    std::string s;
    for (const auto& n : r.notes)
    {
        s += "; " + n;
    }
    std::size_t pg = 0;
    for (const auto& d : r.usb_devices)
    {
        pg += d.vendor_id == POINT_GREY_USB_VENDOR_ID ? 1 : 0;
    }
    s += "; USB: " + std::to_string(r.usb_devices.size()) + " device(s) visible";
    if (pg > 0)
    {
        s += ", " + std::to_string(pg) +
             " of them Point Grey (vendor 1e10) but not usable by libdc1394 (permission on "
             "/dev/bus/usb?)";
    }
    return s;
}

void check(dc1394error_t err, const std::string& what)
{
    if (err != DC1394_SUCCESS)
    {
        throw std::runtime_error(
            "CDigiclopsStereoCamera: " + what + " failed: " + dc1394_error_get_string(err));
    }
}

void setFeature(dc1394camera_t* cam, dc1394feature_t f, int value, const char* key)
{
    if (value < 0)
    {
        // Not every camera has an automatic mode for every feature: best effort.
        dc1394_feature_set_mode(cam, f, DC1394_FEATURE_MODE_AUTO);
        return;
    }
    check(
        dc1394_feature_set_mode(cam, f, DC1394_FEATURE_MODE_MANUAL),
        std::string("setting ") + key + " to manual");
    check(
        dc1394_feature_set_value(cam, f, static_cast<std::uint32_t>(value)),
        std::string("setting ") + key + " = " + std::to_string(value));
}
/** The camera the parameters name (camera_guid, else camera_index) among
 * those libdc1394 enumerates. */
dc1394camera_id_t chooseCamera(dc1394_t* ctx, const CDigiclopsStereoCamera::TParameters& p)
{
    dc1394camera_list_t* list = nullptr;
    check(dc1394_camera_enumerate(ctx, &list), "enumerating IIDC cameras");
    std::vector<dc1394camera_id_t> ids(list->ids, list->ids + list->num);
    dc1394_camera_free_list(list);
    if (ids.empty())
    {
        throw std::runtime_error(
            "CDigiclopsStereoCamera: no device: libdc1394 found no IIDC camera on IEEE-1394 or "
            "USB" +
            noCameraDiagnosis() + "; run 'emslam-grabber --list-devices'");
    }
    const dc1394camera_id_t* id = nullptr;
    std::string found;
    for (const auto& c : ids)
    {
        found += mrpt::format(" 0x%016llx", static_cast<unsigned long long>(c.guid));
        if (p.camera_guid != 0 && c.guid == p.camera_guid)
        {
            id = &c;
        }
    }
    if (p.camera_guid == 0)
    {
        if (static_cast<std::size_t>(p.camera_index) >= ids.size())
        {
            throw std::runtime_error(
                "CDigiclopsStereoCamera: no device: camera_index " +
                std::to_string(p.camera_index) + " but only " + std::to_string(ids.size()) +
                " camera(s) found:" + found);
        }
        id = &ids[static_cast<std::size_t>(p.camera_index)];
    }
    if (id == nullptr)
    {
        throw std::runtime_error(
            mrpt::format(
                "CDigiclopsStereoCamera: no device: no camera with GUID 0x%016llx; found:",
                static_cast<unsigned long long>(p.camera_guid)) +
            found);
    }
    return *id;
}

/** Sets video_mode (checked against the camera's) and iso_speed. */
dc1394video_mode_t setVideoMode(
    dc1394camera_t* cam, const CDigiclopsStereoCamera::TParameters& p, const std::string& cam_name)
{
    dc1394video_mode_t mode{};
    bool known = false;
    for (const auto& [name, m] : videoModes())
    {
        if (p.video_mode == name)
        {
            mode = m;
            known = true;
        }
    }
    if (!known)
    {
        throw std::invalid_argument(
            "CDigiclopsStereoCamera: mode unsupported: unknown video_mode '" + p.video_mode +
            "' (expected WxH_CODING such as 640x480_RGB8, or FORMAT7_0..FORMAT7_7)");
    }
    dc1394video_modes_t modes;
    check(dc1394_video_get_supported_modes(cam, &modes), "reading the supported modes");
    bool supported = false;
    std::string mode_list;
    for (std::uint32_t i = 0; i < modes.num; ++i)
    {
        supported = supported || modes.modes[i] == mode;
        mode_list += " " + modeName(modes.modes[i]);
    }
    if (!supported)
    {
        throw std::runtime_error(
            "CDigiclopsStereoCamera: mode unsupported: camera '" + cam_name +
            "' does not support video_mode " + p.video_mode + "; it supports:" + mode_list);
    }
    if (p.iso_speed == 800)
    {
        check(
            dc1394_video_set_operation_mode(cam, DC1394_OPERATION_MODE_1394B),
            "switching to 1394B (iso_speed 800)");
    }
    const dc1394speed_t speed = p.iso_speed == 100   ? DC1394_ISO_SPEED_100
                                : p.iso_speed == 200 ? DC1394_ISO_SPEED_200
                                : p.iso_speed == 400 ? DC1394_ISO_SPEED_400
                                                     : DC1394_ISO_SPEED_800;
    check(dc1394_video_set_iso_speed(cam, speed), "setting iso_speed");
    check(dc1394_video_set_mode(cam, mode), "setting video_mode " + p.video_mode);
    return mode;
}

/** Sets the frame size (Format 7) or the lowest frame rate >= framerate;
 * returns the frame period [us]. */
double setFrameRate(
    dc1394camera_t* cam,
    dc1394video_mode_t mode,
    const CDigiclopsStereoCamera::TParameters& p,
    const std::string& cam_name)
{
    const PackedFrameFormat fmt = p.frameFormat();
    if (dc1394_is_video_mode_scalable(mode) == DC1394_TRUE)
    {
        const dc1394color_coding_t coding =
            fmt.layout == PackedLayout::PIXEL_INTERLEAVED_24  ? DC1394_COLOR_CODING_RGB8
            : fmt.layout == PackedLayout::BYTE_INTERLEAVED_16 ? DC1394_COLOR_CODING_MONO16
                                                              : DC1394_COLOR_CODING_MONO8;
        const std::uint32_t h =
            fmt.layout == PackedLayout::PLANAR_8 ? fmt.height * fmt.channels() : fmt.height;
        check(
            dc1394_format7_set_roi(cam, mode, coding, DC1394_USE_MAX_AVAIL, 0, 0, fmt.width, h),
            mrpt::format("setting the %s region %ux%u", p.video_mode.c_str(), fmt.width, h));
        return 1e6 / p.framerate;
    }
    else
    {
        dc1394framerates_t rates;
        check(
            dc1394_video_get_supported_framerates(cam, mode, &rates),
            "reading the supported frame rates");
        dc1394framerate_t best{};
        double best_v = 0;
        std::string rate_list;
        for (std::uint32_t i = 0; i < rates.num; ++i)
        {
            const double v = rateValue(rates.framerates[i]);
            rate_list += mrpt::format(" %g", v);
            if (v >= p.framerate - 1e-9 && (best_v == 0 || v < best_v))
            {
                best = rates.framerates[i];
                best_v = v;
            }
        }
        if (best_v == 0)
        {
            throw std::runtime_error(
                mrpt::format(
                    "CDigiclopsStereoCamera: mode unsupported: no frame rate >= %g fps in "
                    "video_mode ",
                    p.framerate) +
                p.video_mode + " of camera '" + cam_name + "'; supported [fps]:" + rate_list);
        }
        check(dc1394_video_set_framerate(cam, best), "setting the frame rate");
        return 1e6 / best_v;
    }
}
}  // namespace

CDigiclopsStereoCamera::CDigiclopsStereoCamera() = default;

CDigiclopsStereoCamera::~CDigiclopsStereoCamera()
{
    closeDevice();
}

void CDigiclopsStereoCamera::openDevice()
{
    closeDevice();
    const TParameters& p = m_params;
    auto dev = std::make_unique<Device>();
    dev->ctx = dc1394_new();
    if (dev->ctx == nullptr)
    {
        throw std::runtime_error(
            "CDigiclopsStereoCamera: no device: libdc1394 could not be initialised" +
            noCameraDiagnosis());
    }
    const dc1394camera_id_t id = chooseCamera(dev->ctx, p);
    dev->cam = dc1394_camera_new_unit(dev->ctx, id.guid, id.unit);
    if (dev->cam == nullptr)
    {
        throw std::runtime_error(mrpt::format(
            "CDigiclopsStereoCamera: permission: camera GUID 0x%016llx was enumerated but "
            "cannot be opened (no read/write permission on its /dev/fw* or /dev/bus/usb "
            "node?)",
            static_cast<unsigned long long>(id.guid)));
    }
    const std::string cam_name = std::string(dev->cam->vendor ? dev->cam->vendor : "") + " " +
                                 (dev->cam->model ? dev->cam->model : "");

    const dc1394video_mode_t mode = setVideoMode(dev->cam, p, cam_name);
    dev->frame_period_us = setFrameRate(dev->cam, mode, p, cam_name);
    setFeature(dev->cam, DC1394_FEATURE_SHUTTER, p.shutter, "shutter");
    setFeature(dev->cam, DC1394_FEATURE_GAIN, p.gain, "gain");
    setFeature(dev->cam, DC1394_FEATURE_EXPOSURE, p.exposure, "exposure");

    const dc1394error_t cap = dc1394_capture_setup(
        dev->cam, static_cast<std::uint32_t>(p.dma_buffers), DC1394_CAPTURE_FLAGS_DEFAULT);
    if (cap != DC1394_SUCCESS)
    {
        throw std::runtime_error(
            std::string("CDigiclopsStereoCamera: cannot start DMA capture (permission on the "
                        "device node, or not enough bus bandwidth for this mode and rate): ") +
            dc1394_error_get_string(cap));
    }
    dev->capturing = true;
    check(dc1394_video_set_transmission(dev->cam, DC1394_ON), "starting transmission");
    dev->transmitting = true;
    m_dev = std::move(dev);
    m_dropped = 0;
}

void CDigiclopsStereoCamera::closeDevice()
{
    m_dev.reset();
}

bool CDigiclopsStereoCamera::grabFrame()
{
    dc1394video_frame_t* frame = nullptr;
    check(
        dc1394_capture_dequeue(m_dev->cam, DC1394_CAPTURE_POLICY_WAIT, &frame),
        "waiting for a frame");
    if (frame == nullptr)
    {
        return false;
    }
    struct Requeue
    {
        dc1394camera_t* cam;
        dc1394video_frame_t* f;
        ~Requeue() { dc1394_capture_enqueue(cam, f); }
    } requeue{m_dev->cam, frame};

    const double t_us = static_cast<double>(frame->timestamp);
    if (m_dev->last_timestamp_us > 0 && m_dev->frame_period_us > 0)
    {
        const double gap = (t_us - m_dev->last_timestamp_us) / m_dev->frame_period_us;
        if (gap > 1.5)
        {
            m_dropped += static_cast<std::size_t>(std::lround(gap)) - 1;
        }
    }
    m_dev->last_timestamp_us = t_us;
    if (dc1394_capture_is_frame_corrupt(m_dev->cam, frame) == DC1394_TRUE)
    {
        ++m_dropped;
        return false;
    }
    appendObservations(
        convertFrame(frame->image, frame->image_bytes, mrpt::Clock::fromDouble(t_us * 1e-6)));
    return true;
}

}  // namespace emslam::hwdrivers
