// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/hwdrivers/VideoSource.h>

#include <mrpt/core/format.h>
#include <mrpt/system/string_utils.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace emslam::hwdrivers
{
namespace
{
int apiOf(const std::string& backend, VideoSourceKind kind)
{
    if (backend == "v4l2")
    {
        return cv::CAP_V4L2;
    }
    if (backend == "ffmpeg")
    {
        return cv::CAP_FFMPEG;
    }
    if (backend == "gstreamer")
    {
        return cv::CAP_GSTREAMER;
    }
    if (backend == "any")
    {
        return cv::CAP_ANY;
    }
    // auto
    switch (kind)
    {
        case VideoSourceKind::DEVICE_INDEX:
        case VideoSourceKind::DEVICE_PATH:
            return cv::CAP_V4L2;
        case VideoSourceKind::PIPELINE:
            return cv::CAP_GSTREAMER;
        case VideoSourceKind::FILE:
            break;
    }
    return cv::CAP_FFMPEG;
}
}  // namespace

std::string toString(VideoSourceKind k)
{
    switch (k)
    {
        case VideoSourceKind::DEVICE_INDEX:
            return "device index";
        case VideoSourceKind::DEVICE_PATH:
            return "V4L2 device";
        case VideoSourceKind::PIPELINE:
            return "GStreamer pipeline";
        case VideoSourceKind::FILE:
            break;
    }
    return "video file";
}

VideoSourceKind classifyVideoSource(const std::string& source)
{
    const std::string s = mrpt::system::trim(source);
    if (!s.empty() && s.size() <= 4 &&
        std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c) != 0; }))
    {
        return VideoSourceKind::DEVICE_INDEX;
    }
    if (s.find('!') != std::string::npos)
    {
        return VideoSourceKind::PIPELINE;
    }
    if (s.rfind("/dev/", 0) == 0)
    {
        return VideoSourceKind::DEVICE_PATH;
    }
    return VideoSourceKind::FILE;
}

namespace
{
/** Throws if `source` cannot be there: a missing device node or file, or a
 * node without permission (OpenCV would only say "cannot open"). */
void requireReachable(VideoSourceKind kind, const std::string& source, const std::string& where)
{
    std::error_code ec;
    if (kind == VideoSourceKind::DEVICE_PATH)
    {
        if (!std::filesystem::exists(source, ec))
        {
            throw std::runtime_error(
                where +
                ": no such device (camera not connected, or another /dev/videoN; "
                "'v4l2-ctl --list-devices' or 'emslam-grabber --list-devices' lists them)");
        }
        if (::access(source.c_str(), R_OK | W_OK) != 0)
        {
            throw std::runtime_error(
                where +
                ": no read/write permission on the device node (add the user to the "
                "'video' group)");
        }
    }
    if (kind == VideoSourceKind::FILE && source.find('%') == std::string::npos &&
        !std::filesystem::is_regular_file(source, ec))
    {
        throw std::runtime_error(
            where + ": file not found (relative paths are taken from the working folder '" +
            std::filesystem::current_path().string() + "')");
    }
}

/** The open() properties of a camera device: pixel format, then frame size. */
std::vector<int> captureProperties(VideoSourceKind kind, const VideoCaptureRequest& request)
{
    std::vector<int> props;
    if (!isLiveSource(kind))
    {
        return props;
    }
    if (request.fourcc.size() == 4)
    {
        const auto& f = request.fourcc;
        props.insert(
            props.end(), {cv::CAP_PROP_FOURCC, cv::VideoWriter::fourcc(f[0], f[1], f[2], f[3])});
    }
    if (request.width > 0)
    {
        props.insert(props.end(), {cv::CAP_PROP_FRAME_WIDTH, request.width});
    }
    if (request.height > 0)
    {
        props.insert(props.end(), {cv::CAP_PROP_FRAME_HEIGHT, request.height});
    }
    return props;
}

/** Why a source that is there did not open, by kind. */
std::string whyNotOpened(VideoSourceKind kind, const std::string& source)
{
    std::error_code ec;
    switch (kind)
    {
        case VideoSourceKind::DEVICE_INDEX:
            return "no camera with this index (none connected, or busy; '/dev/video" + source +
                   "' " +
                   (std::filesystem::exists("/dev/video" + source, ec) ? "exists"
                                                                       : "does not exist") +
                   ")";
        case VideoSourceKind::DEVICE_PATH:
            return "the device exists but cannot be opened (busy, or not a capture device)";
        case VideoSourceKind::PIPELINE:
            return "GStreamer cannot start the pipeline (a missing plugin or a syntax error; "
                   "it must end in appsink; try it with gst-launch-1.0 and fakesink)";
        case VideoSourceKind::FILE:
            break;
    }
    return "no OpenCV backend decodes it (not a video, or an unsupported codec)";
}
}  // namespace

VideoSource::VideoSource(
    const std::string& what, const std::string& source, const VideoCaptureRequest& request)
    : m_kind(classifyVideoSource(source)), m_source(mrpt::system::trim(source))
{
    const std::string where = what + " '" + m_source + "' (" + toString(m_kind) + ")";
    requireReachable(m_kind, m_source, where);
    const int api = apiOf(request.backend, m_kind);
    const std::vector<int> props = captureProperties(m_kind, request);
    bool opened = false;
    try
    {
        if (m_kind == VideoSourceKind::DEVICE_INDEX)
        {
            opened = m_cap.open(std::stoi(m_source), api, props);
        }
        else
        {
            opened = m_cap.open(m_source, api, props);
            // An image sequence, or a file FFmpeg does not read: the other file
            // decoder. Not CAP_ANY: it also probes camera backends (gphoto2 walks
            // the USB bus and leaks), which never read a file.
            if (!opened && m_kind == VideoSourceKind::FILE && request.backend == "auto")
            {
                opened = m_cap.open(
                    m_source,
                    m_source.find('%') != std::string::npos ? cv::CAP_IMAGES : cv::CAP_GSTREAMER,
                    props);
            }
        }
    }
    catch (const cv::Exception& e)
    {
        throw std::runtime_error(where + ": OpenCV: " + e.what());
    }
    if (!opened || !m_cap.isOpened())
    {
        throw std::runtime_error(where + ": cannot open: " + whyNotOpened(m_kind, m_source));
    }
    if (isLiveSource(m_kind) && request.fps > 0)
    {
        m_cap.set(cv::CAP_PROP_FPS, request.fps);
    }
}

std::string VideoSource::backendName() const
{
    try
    {
        return m_cap.getBackendName();
    }
    catch (const cv::Exception&)
    {
        return "unknown";
    }
}

double VideoSource::reportedFps() const
{
    if (m_kind == VideoSourceKind::FILE && m_source.find('%') != std::string::npos)
    {
        return 0.0;  // an image sequence has no rate (FFmpeg's image2 reader says 25)
    }
    const double fps = m_cap.get(cv::CAP_PROP_FPS);
    return std::isfinite(fps) && fps > 0 && fps <= 10000 ? fps : 0.0;
}

std::size_t VideoSource::reportedFrameCount() const
{
    const double n = m_cap.get(cv::CAP_PROP_FRAME_COUNT);
    return std::isfinite(n) && n > 0 && n < 1e12 ? static_cast<std::size_t>(n) : 0;
}

}  // namespace emslam::hwdrivers
