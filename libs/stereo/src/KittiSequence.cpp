// SPDX-License-Identifier: BSD-3-Clause
#include "ImageFile.h"

#include <emslam/stereo/CalibrationReaders.h>
#include <emslam/stereo/KittiSequence.h>
#include <emslam/stereo/TextParsing.h>

#include <mrpt/core/Clock.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/CMatrixFixed.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace emslam::stereo
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
    std::ifstream f(file);
    if (!f.is_open())
    {
        THROW_EXCEPTION_FMT("Cannot open KITTI poses file '%s'", file.c_str());
    }
    std::vector<mrpt::poses::CPose3D> poses;
    std::vector<double> v;
    std::string line;
    std::size_t line_no = 0;
    while (std::getline(f, line))
    {
        ++line_no;
        if (isBlank(line))
        {
            continue;
        }
        if (!parseNumbers(line, v) || v.size() != 12)
        {
            THROW_EXCEPTION_FMT(
                "%s:%zu: expected 12 numbers (a 3x4 row-major pose matrix)", file.c_str(), line_no);
        }
        Eigen::Matrix3d M;
        mrpt::math::CVectorFixedDouble<3> t;
        for (int r = 0; r < 3; r++)
        {
            for (int c = 0; c < 3; c++)
            {
                M(r, c) = v[4 * r + c];
            }
            t[r] = v[4 * r + 3];
        }
        // Nearest rotation (the file rounds to 7 digits): U * V^T of the SVD.
        const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
        const Eigen::Matrix3d Rn = svd.matrixU() * svd.matrixV().transpose();
        if (!M.allFinite() || Rn.determinant() < 0 || (Rn - M).norm() > 1e-3)
        {
            THROW_EXCEPTION_FMT(
                "%s:%zu: the 3x3 part is not a rotation matrix", file.c_str(), line_no);
        }
        mrpt::math::CMatrixDouble33 R;
        R.asEigen() = Rn;
        poses.emplace_back(R, t);
    }
    return poses;
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

    // times.txt
    const std::string times_file = sequence_dir + "/times.txt";
    std::ifstream ft(times_file);
    if (!ft.is_open())
    {
        THROW_EXCEPTION_FMT("Cannot open KITTI timestamps file '%s'", times_file.c_str());
    }
    std::vector<double> times;
    {
        std::string line;
        std::vector<double> v;
        std::size_t line_no = 0;
        while (std::getline(ft, line))
        {
            ++line_no;
            if (isBlank(line))
            {
                continue;
            }
            if (!parseNumbers(line, v) || v.size() != 1)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: expected one timestamp [s], got '%s'", times_file.c_str(), line_no,
                    line.c_str());
            }
            // Finite, in a range a clock can hold (1e10 s: year 2286), increasing.
            if (!std::isfinite(v[0]) || v[0] < 0 || v[0] >= 1e10)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: timestamp '%s' must be a finite number of seconds in [0, 1e10)",
                    times_file.c_str(), line_no, line.c_str());
            }
            if (!times.empty() && !(v[0] > times.back()))
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: timestamp %.9g does not follow the previous one (%.9g): "
                    "times must increase",
                    times_file.c_str(), line_no, v[0], times.back());
            }
            times.push_back(v[0]);
        }
    }
    if (times.empty())
    {
        THROW_EXCEPTION_FMT("KITTI timestamps file '%s' is empty", times_file.c_str());
    }
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

    // Image size from the first pair, then the calibration.
    const cv::Mat left = loadImageFile(imageFile(sequence_dir, "image_0", 0));
    const cv::Mat right = loadImageFile(imageFile(sequence_dir, "image_1", 0));
    if (left.size() != right.size())
    {
        THROW_EXCEPTION_FMT(
            "Left/right image size mismatch: '%s' is %dx%d but '%s' is %dx%d",
            imageFile(sequence_dir, "image_0", 0).c_str(), left.cols, left.rows,
            imageFile(sequence_dir, "image_1", 0).c_str(), right.cols, right.rows);
    }
    m_width = static_cast<unsigned int>(left.cols);
    m_height = static_cast<unsigned int>(left.rows);
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
    const std::string fl = leftImageFile(i);
    const std::string fr = rightImageFile(i);
    const cv::Mat left = loadImageFile(fl);
    const cv::Mat right = loadImageFile(fr);
    for (const auto& [im, file] : {std::pair{&left, &fl}, std::pair{&right, &fr}})
    {
        if (static_cast<unsigned int>(im->cols) != m_width ||
            static_cast<unsigned int>(im->rows) != m_height)
        {
            THROW_EXCEPTION_FMT(
                "Image size mismatch: '%s' is %dx%d, expected %ux%u (first frame, calib)",
                file->c_str(), im->cols, im->rows, m_width, m_height);
        }
    }

    Frame f;
    f.t = timestamp(i);
    f.obs = mrpt::obs::CObservationStereoImages::Create();
    f.obs->timestamp = mrpt::Clock::fromDouble(f.t);
    f.obs->sensorLabel = sensor_label;
    f.obs->imageLeft = mrpt::img::CImage(left, mrpt::img::SHALLOW_COPY);
    f.obs->imageRight = mrpt::img::CImage(right, mrpt::img::SHALLOW_COPY);
    f.obs->hasImageRight = true;
    f.obs->hasImageDisparity = false;
    f.obs->setStereoCameraParams(m_calib);
    f.obs->cameraPose = mrpt::poses::CPose3DQuat();
    if (hasGroundTruth())
    {
        f.ground_truth = m_poses[i];
    }
    return f;
}

}  // namespace emslam::stereo
