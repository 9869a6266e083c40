// SPDX-License-Identifier: BSD-3-Clause
#include "StereoPairFiles.h"

#include <emslam/io/CalibrationFiles.h>
#include <emslam/io/ImageFile.h>
#include <emslam/io/KittiSequence.h>
#include <emslam/io/KittiTrajectory.h>
#include <emslam/io/TextParsing.h>

#include <mrpt/core/Clock.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/CMatrixFixed.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <utility>

namespace fs = std::filesystem;

namespace emslam::io
{
namespace
{
std::size_t countPngs(const std::string& dir)
{
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir))
    {
        if (e.path().extension() == ".png")
        {
            ++n;
        }
    }
    return n;
}

std::string imageFile(const std::string& dir, const char* sub, std::size_t i)
{
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.png", i);
    return dir + "/" + sub + "/" + name;
}
}  // namespace

std::vector<mrpt::poses::CPose3D> KittiSequence::readPosesFile(const std::string& file)
{
    return KittiTrajectory::readPoses(file);
}

void KittiSequence::open(const std::string& sequence_dir, const std::string& poses_file)
{
    m_dir.clear();
    m_times.clear();
    m_poses.clear();

    std::error_code ec;
    if (!fs::is_directory(sequence_dir, ec))
    {
        THROW_EXCEPTION_FMT("KITTI sequence folder '%s' does not exist", sequence_dir.c_str());
    }
    for (const char* sub : {"image_0", "image_1"})
    {
        const std::string d = sequence_dir + "/" + sub;
        if (!fs::is_directory(d, ec))
        {
            THROW_EXCEPTION_FMT(
                "KITTI sequence folder '%s' has no '%s' folder", sequence_dir.c_str(), sub);
        }
    }

    const std::string times_file = sequence_dir + "/times.txt";
    std::vector<double> times = KittiTrajectory::readTimes(times_file);
    for (const char* sub : {"image_0", "image_1"})
    {
        const std::size_t n = countPngs(sequence_dir + "/" + sub);
        if (n != times.size())
        {
            THROW_EXCEPTION_FMT(
                "'%s' lists %zu frames but '%s/%s' holds %zu PNG images", times_file.c_str(),
                times.size(), sequence_dir.c_str(), sub, n);
        }
    }
    for (std::size_t i = 0; i < times.size(); i++)
    {
        for (const char* sub : {"image_0", "image_1"})
        {
            const std::string file = imageFile(sequence_dir, sub, i);
            if (!fs::is_regular_file(file, ec))
            {
                THROW_EXCEPTION_FMT("KITTI image '%s' is missing", file.c_str());
            }
        }
    }

    // Image size from the headers of the first pair (a huge image is refused
    // before it is decoded), then the calibration.
    const std::string left0 = imageFile(sequence_dir, "image_0", 0);
    const std::string right0 = imageFile(sequence_dir, "image_1", 0);
    const cv::Size left = imageFileSize(left0);
    const cv::Size right = imageFileSize(right0);
    if (left != right)
    {
        THROW_EXCEPTION_FMT(
            "Left/right image size mismatch: '%s' is %dx%d but '%s' is %dx%d", left0.c_str(),
            left.width, left.height, right0.c_str(), right.width, right.height);
    }
    loadImageFile(left0, left, "its header");  // the first pair must decode
    loadImageFile(right0, right, "its header");
    m_width = static_cast<unsigned int>(left.width);
    m_height = static_cast<unsigned int>(left.height);
    m_calib = loadKittiCalibration(sequence_dir + "/calib.txt", m_width, m_height);

    if (!poses_file.empty())
    {
        auto poses = readPosesFile(poses_file);
        if (poses.size() != times.size())
        {
            THROW_EXCEPTION_FMT(
                "KITTI poses file '%s' has %zu poses but the sequence '%s' has %zu frames "
                "(times.txt)",
                poses_file.c_str(), poses.size(), sequence_dir.c_str(), times.size());
        }
        m_poses = std::move(poses);
    }
    m_times = std::move(times);
    m_dir = sequence_dir;
}

double KittiSequence::timestamp(std::size_t i) const
{
    return time_offset + sequenceTime(i);
}

double KittiSequence::sequenceTime(std::size_t i) const
{
    ASSERT_LT_(i, m_times.size());
    return m_times[i];
}

const mrpt::poses::CPose3D& KittiSequence::groundTruth(std::size_t i) const
{
    ASSERTMSG_(hasGroundTruth(), "KittiSequence: no poses file was given");
    ASSERT_LT_(i, m_poses.size());
    return m_poses[i];
}

std::vector<std::string> KittiSequence::inputFiles() const
{
    std::vector<std::string> files{m_dir + "/times.txt", m_dir + "/calib.txt"};
    for (std::size_t i = 0; i < size(); ++i)
    {
        files.push_back(leftImageFile(i));
        files.push_back(rightImageFile(i));
    }
    return files;
}

std::string KittiSequence::leftImageFile(std::size_t i) const
{
    return imageFile(m_dir, "image_0", i);
}

std::string KittiSequence::rightImageFile(std::size_t i) const
{
    return imageFile(m_dir, "image_1", i);
}

KittiSequence::Frame KittiSequence::frame(std::size_t i) const
{
    ASSERTMSG_(isOpen(), "KittiSequence: open() a sequence first");
    ASSERT_LT_(i, m_times.size());
    Frame f;
    f.t = timestamp(i);
    f.obs = loadStereoPairObservation(
        leftImageFile(i), rightImageFile(i), m_calib, "first frame, calib");
    f.obs->timestamp = mrpt::Clock::fromDouble(f.t);
    f.obs->sensorLabel = sensor_label;
    if (hasGroundTruth())
    {
        f.ground_truth = m_poses[i];
    }
    return f;
}

SequenceFrame KittiSequence::readFrame(std::size_t i) const
{
    Frame f = frame(i);
    return {std::move(f.obs), std::move(f.ground_truth), f.t};
}

}  // namespace emslam::io
