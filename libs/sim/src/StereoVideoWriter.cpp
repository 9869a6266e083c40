// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/sim/StereoVideoWriter.h>

#include <mrpt/core/format.h>

#include <cmath>
#include <stdexcept>

namespace emslam::sim
{
StereoVideoWriter::StereoVideoWriter(
    const std::string& file,
    double fps,
    cv::Size camera_size,
    const std::string& codec,
    bool colour)
    : m_file(file), m_camera_size(camera_size), m_type(colour ? CV_8UC3 : CV_8UC1)
{
    if (codec.size() != 4)
    {
        throw std::invalid_argument(
            "StereoVideoWriter: codec '" + codec +
            "' must be a four-character code (FFV1, MJPG, ...)");
    }
    if (!(fps > 0 && fps <= 1000))
    {
        throw std::invalid_argument(
            mrpt::format("StereoVideoWriter: fps %g must be in (0, 1000]", fps));
    }
    if (camera_size.width <= 0 || camera_size.height <= 0)
    {
        throw std::invalid_argument("StereoVideoWriter: empty camera size");
    }
    const int fourcc = cv::VideoWriter::fourcc(codec[0], codec[1], codec[2], codec[3]);
    const cv::Size frame(2 * camera_size.width, camera_size.height);
    // FFmpeg: the only backend of Debian's OpenCV that writes FFV1 and the containers.
    if (!m_writer.open(file, cv::CAP_FFMPEG, fourcc, fps, frame, colour))
    {
        throw std::runtime_error(
            "StereoVideoWriter: OpenCV cannot write '" + file + "' with codec '" + codec +
            "' (unknown codec or container for its extension, or the folder is not writable)");
    }
}

void StereoVideoWriter::write(const cv::Mat& left, const cv::Mat& right)
{
    for (const cv::Mat* m : {&left, &right})
    {
        if (m->size() != m_camera_size || m->type() != m_type)
        {
            throw std::invalid_argument(mrpt::format(
                "StereoVideoWriter '%s': image of %dx%d and type %d, expected %dx%d of type %d",
                m_file.c_str(), m->cols, m->rows, m->type(), m_camera_size.width,
                m_camera_size.height, m_type));
        }
    }
    if (!m_writer.isOpened())
    {
        throw std::logic_error("StereoVideoWriter '" + m_file + "': write() after close()");
    }
    cv::Mat frame;
    cv::hconcat(left, right, frame);
    m_writer.write(frame);
    ++m_frames;
}

void StereoVideoWriter::close()
{
    m_writer.release();
}

}  // namespace emslam::sim
