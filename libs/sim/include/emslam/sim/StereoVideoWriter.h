// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>
#include <string>

namespace emslam::sim
{
/** Writes stereo pairs as one side-by-side video (each frame: left | right,
 * twice the camera's width) through cv::VideoWriter and its FFmpeg backend:
 * what a side-by-side USB stereo camera delivers, for CVideoStereoCamera.
 * The container follows the file's extension (.avi, .mkv, ...).
 *
 * Codecs checked with Debian 12's OpenCV 4.6 on grey 8-bit frames: `FFV1`
 * (the default) and `PNG ` are lossless in .avi and .mkv; `HFYU` (HuffYUV)
 * stores grey as YUV and is off by one grey level; `MJPG` and `H264`
 * are lossy (JPEG-like noise of a few grey levels on textured images).
 * \ingroup emslam_sim_grp */
class StereoVideoWriter
{
public:
    /** Opens `file` for frames of two `camera_size` images at `fps` [Hz] with
     * the four-character `codec`, grey frames unless `colour`. Throws
     * std::runtime_error naming the file and the codec if OpenCV cannot open
     * it, std::invalid_argument on a bad size, rate or codec name. */
    StereoVideoWriter(
        const std::string& file,
        double fps,
        cv::Size camera_size,
        const std::string& codec = "FFV1",
        bool colour = false);

    /** Appends one frame: `left` and `right` side by side. Both must be
     * 8-bit images of the camera size, grey (CV_8UC1) for a grey video, BGR
     * (CV_8UC3) for a colour one. Throws std::invalid_argument otherwise. */
    void write(const cv::Mat& left, const cv::Mat& right);

    /** Finishes the file (also done by the destructor). */
    void close();

    std::size_t framesWritten() const { return m_frames; }

private:
    std::string m_file;
    cv::Size m_camera_size;
    int m_type{0};
    cv::VideoWriter m_writer;
    std::size_t m_frames{0};
};

}  // namespace emslam::sim
