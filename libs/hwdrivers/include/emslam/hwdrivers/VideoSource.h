// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>
#include <string>

namespace emslam::hwdrivers
{
/** What a `source` string of CVideoStereoCamera names. */
enum class VideoSourceKind
{
    DEVICE_INDEX,  //!< "0", "1": the n-th camera (V4L2 on Linux)
    DEVICE_PATH,   //!< "/dev/video0", "/dev/v4l/by-id/...": a V4L2 device node
    PIPELINE,      //!< a GStreamer pipeline (contains '!'), ending in appsink
    FILE           //!< anything else: a video file or an image sequence ("img_%04d.png")
};

/** "device index", "V4L2 device", "GStreamer pipeline", "video file". */
std::string toString(VideoSourceKind k);

/** The kind of `source` (see VideoSourceKind; leading and trailing blanks ignored). */
VideoSourceKind classifyVideoSource(const std::string& source);

/** A camera device (index or node): it has no end, so a failed read means
 * it stopped (unplugged); files and pipelines can end. */
inline bool isLiveSource(VideoSourceKind k)
{
    return k == VideoSourceKind::DEVICE_INDEX || k == VideoSourceKind::DEVICE_PATH;
}

/** How to open a source; the sizes, rate and pixel format are requested
 * from camera devices only (0 / empty: the device's own). */
struct VideoCaptureRequest
{
    /** OpenCV backend: "auto" (from the kind: V4L2 for devices, GStreamer for
     * pipelines, FFmpeg then any other for files), "v4l2", "ffmpeg",
     * "gstreamer" or "any". */
    std::string backend{"auto"};
    int width{0};        //!< [px] whole frame width (side by side: both images)
    int height{0};       //!< [px]
    double fps{0.0};     //!< [Hz]
    std::string fourcc;  //!< pixel format, e.g. MJPG or YUYV
};

/** One cv::VideoCapture opened from a `source` string, with the errors a
 * user can act on: a missing device node or file, a device that exists but
 * cannot be opened (busy, no permission), a pipeline OpenCV cannot start, a
 * file no backend decodes. \ingroup emslam_hwdrivers_grp \sa CVideoStereoCamera */
class VideoSource
{
public:
    /** Opens `source`; throws std::runtime_error naming `what` (e.g.
     * "source"), the source and the cause. Devices get `request`'s settings. */
    VideoSource(
        const std::string& what, const std::string& source, const VideoCaptureRequest& request);

    VideoSourceKind kind() const { return m_kind; }
    const std::string& source() const { return m_source; }
    /** The backend OpenCV chose ("V4L2", "FFMPEG", "GSTREAMER", ...). */
    std::string backendName() const;
    /** Frame rate the source reports [Hz]; 0 if unknown and for image
     * sequences (whose 25 Hz from FFmpeg is a default, not their rate). */
    double reportedFps() const;
    /** Frames in a file as its container reports them; 0 if unknown. */
    std::size_t reportedFrameCount() const;

    /** grab() then retrieve(): split for two devices (grab both, then decode). */
    bool grab() { return m_cap.grab(); }
    bool retrieve(cv::Mat& frame) { return m_cap.retrieve(frame); }

private:
    VideoSourceKind m_kind;
    std::string m_source;
    cv::VideoCapture m_cap;
};

}  // namespace emslam::hwdrivers
