// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/DataFile.h>
#include <emslam/io/DatasetStamps.h>
#include <emslam/io/ImageFile.h>
#include <emslam/io/TextParsing.h>
#include <emslam/io/TumRgbdSequence.h>
#include <emslam/io/TumTrajectory.h>

#include <mrpt/core/Clock.h>
#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>

namespace fs = std::filesystem;

namespace emslam::io
{
namespace
{
struct ListEntry
{
    double t;
    std::string file;
};

/** Reads rgb.txt / depth.txt: "timestamp filename" per line, '#' comments;
 * the stamps are plausible and strictly increasing (DatasetStamps.h). */
std::vector<ListEntry> readList(const std::string& dir, const std::string& name)
{
    const std::string file = dir + "/" + name;
    auto f = openTextFile(file, "TUM RGB-D list");
    std::vector<ListEntry> out;
    IncreasingStamps<double> order(file);
    forEachDataLine(
        f,
        [&](const std::string& line, std::size_t line_no)
        {
            std::istringstream ss(line);
            std::string ts, fname, extra;
            ss >> ts >> fname;
            double t = 0;
            // A leading '+' was never accepted in these lists (parseDouble() takes one).
            const bool ts_ok = !ts.empty() && ts.front() != '+' && parseDouble(ts, t);
            if (fname.empty() || (ss >> extra) || !ts_ok)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: expected 'timestamp filename', got %s", file.c_str(), line_no,
                    quotedExcerpt(line).c_str());
            }
            requirePlausibleStampSeconds(t, ts, file, line_no);
            order.add(t, ts, line_no);
            std::string path = dir;
            path += "/";
            path += fname;
            out.push_back({t, std::move(path)});
        });
    if (out.empty())
    {
        THROW_EXCEPTION_FMT("TUM RGB-D list '%s' lists no image", file.c_str());
    }
    return out;
}

cv::Mat loadDepth(const std::string& file, const cv::Size& expected, const std::string& source)
{
    cv::Mat d = loadImageFile(file, expected, source);
    if (d.type() != CV_16UC1)
    {
        THROW_EXCEPTION_FMT(
            "Depth image '%s' is not a 16-bit single-channel image (OpenCV type %d)", file.c_str(),
            d.type());
    }
    return d;
}

/** Index of the element of sorted `ts` nearest to `t`, or npos if beyond `max_dt`. */
std::size_t nearest(const std::vector<double>& ts, double t, double max_dt)
{
    const auto it = std::lower_bound(ts.begin(), ts.end(), t);
    std::size_t best = std::string::npos;
    double best_dt = std::numeric_limits<double>::infinity();
    for (auto c : {it, it == ts.begin() ? ts.end() : std::prev(it)})
    {
        if (c != ts.end() && std::abs(*c - t) < best_dt)
        {
            best_dt = std::abs(*c - t);
            best = static_cast<std::size_t>(c - ts.begin());
        }
    }
    return best_dt <= max_dt ? best : std::string::npos;
}
/** Per colour image, the index of its depth image (npos: none within
 * max_dt): greedy association by increasing |dt|, each image used at most
 * once. */
std::vector<std::size_t> associateGreedily(
    const std::vector<ListEntry>& rgb, const std::vector<ListEntry>& depth, double max_dt)
{
    std::vector<double> depth_t(depth.size());
    for (std::size_t j = 0; j < depth.size(); j++)
    {
        depth_t[j] = depth[j].t;
    }
    struct Candidate
    {
        double dt;
        std::size_t i, j;
    };
    std::vector<Candidate> cand;
    for (std::size_t i = 0; i < rgb.size(); i++)
    {
        auto j = static_cast<std::size_t>(
            std::lower_bound(depth_t.begin(), depth_t.end(), rgb[i].t - max_dt) - depth_t.begin());
        for (; j < depth_t.size() && depth_t[j] <= rgb[i].t + max_dt; j++)
        {
            cand.push_back({std::abs(depth_t[j] - rgb[i].t), i, j});
        }
    }
    std::stable_sort(
        cand.begin(), cand.end(),
        [](const Candidate& a, const Candidate& b) { return a.dt < b.dt; });
    std::vector<std::size_t> match(rgb.size(), std::string::npos);
    std::vector<bool> depth_used(depth.size(), false);
    for (const auto& c : cand)
    {
        if (match[c.i] == std::string::npos && !depth_used[c.j])
        {
            match[c.i] = c.j;
            depth_used[c.j] = true;
        }
    }
    return match;
}

/** Per time, the pose of the trajectory's nearest within max_dt, or none. */
std::vector<std::optional<mrpt::poses::CPose3D>> posesAtTimes(
    TumTrajectory traj, const std::vector<double>& times, double max_dt)
{
    std::stable_sort(
        traj.poses.begin(), traj.poses.end(),
        [](const auto& a, const auto& b) { return a.t < b.t; });
    std::vector<double> gt_t(traj.size());
    for (std::size_t k = 0; k < traj.size(); k++)
    {
        gt_t[k] = traj.poses[k].t;
    }
    std::vector<std::optional<mrpt::poses::CPose3D>> gt(times.size());
    for (std::size_t i = 0; i < times.size(); i++)
    {
        const std::size_t k = nearest(gt_t, times[i], max_dt);
        if (k != std::string::npos)
        {
            gt[i] = traj.poses[k].pose;
        }
    }
    return gt;
}
}  // namespace

TumRgbdSequence::TumRgbdSequence()
{
    intrinsics.ncols = 640;
    intrinsics.nrows = 480;
    intrinsics.setIntrinsicParamsFromValues(525.0, 525.0, 319.5, 239.5);
    intrinsics.distortion = mrpt::img::DistortionModel::none;
    intrinsics.dist.fill(0);
}

void TumRgbdSequence::open(const std::string& rgbd_dir)
{
    m_dir.clear();
    m_rgb_t.clear();
    m_depth_t.clear();
    m_rgb_files.clear();
    m_depth_files.clear();
    m_gt.clear();
    m_has_gt = false;
    m_unassociated = 0;

    ASSERT_GT_(depth_factor, 0.0);
    ASSERT_GT_(intrinsics.fx(), 0.0);
    ASSERT_GT_(intrinsics.fy(), 0.0);
    std::error_code ec;
    if (!fs::is_directory(rgbd_dir, ec))
    {
        THROW_EXCEPTION_FMT("TUM RGB-D folder '%s' does not exist", rgbd_dir.c_str());
    }
    const auto rgb = readList(rgbd_dir, "rgb.txt");
    const auto depth = readList(rgbd_dir, "depth.txt");

    const std::vector<std::size_t> match = associateGreedily(rgb, depth, max_association_dt);
    std::vector<double> rgb_t, d_t;
    std::vector<std::string> rgb_files, depth_files;
    for (std::size_t i = 0; i < rgb.size(); i++)
    {
        if (match[i] == std::string::npos)
        {
            ++m_unassociated;
            continue;
        }
        rgb_t.push_back(rgb[i].t);
        rgb_files.push_back(rgb[i].file);
        d_t.push_back(depth[match[i]].t);
        depth_files.push_back(depth[match[i]].file);
    }
    if (rgb_t.empty())
    {
        THROW_EXCEPTION_FMT(
            "TUM RGB-D folder '%s': no colour image has a depth image within %g s",
            rgbd_dir.c_str(), max_association_dt);
    }
    for (std::size_t i = 0; i < rgb_t.size(); i++)
    {
        for (const auto* file : {&rgb_files[i], &depth_files[i]})
        {
            if (!fs::is_regular_file(*file, ec))
            {
                THROW_EXCEPTION_FMT("TUM RGB-D image '%s' is missing", file->c_str());
            }
        }
    }

    // Sizes from the headers: a huge image is refused before it is decoded.
    const cv::Size c0 = imageFileSize(rgb_files[0]);
    const cv::Size d0 = imageFileSize(depth_files[0]);
    if (c0 != d0)
    {
        THROW_EXCEPTION_FMT(
            "Colour/depth image size mismatch: '%s' is %dx%d but '%s' is %dx%d",
            rgb_files[0].c_str(), c0.width, c0.height, depth_files[0].c_str(), d0.width, d0.height);
    }
    loadImageFile(rgb_files[0], c0, "its header");  // the first pair must decode
    loadDepth(depth_files[0], d0, "its header");
    m_width = static_cast<unsigned int>(c0.width);
    m_height = static_cast<unsigned int>(c0.height);
    intrinsics.ncols = m_width;
    intrinsics.nrows = m_height;

    std::vector<std::optional<mrpt::poses::CPose3D>> gt(rgb_t.size());
    const std::string gt_file = rgbd_dir + "/groundtruth.txt";
    if (fs::exists(gt_file, ec))
    {
        gt = posesAtTimes(TumTrajectory::fromFile(gt_file), rgb_t, gt_max_dt);
        m_has_gt = true;
    }

    m_rgb_t = std::move(rgb_t);
    m_depth_t = std::move(d_t);
    m_rgb_files = std::move(rgb_files);
    m_depth_files = std::move(depth_files);
    m_gt = std::move(gt);
    m_dir = rgbd_dir;
}

double TumRgbdSequence::timestamp(std::size_t i) const
{
    ASSERT_LT_(i, m_rgb_t.size());
    return m_rgb_t[i];
}

double TumRgbdSequence::depthTimestamp(std::size_t i) const
{
    ASSERT_LT_(i, m_depth_t.size());
    return m_depth_t[i];
}

std::optional<mrpt::poses::CPose3D> TumRgbdSequence::groundTruth(std::size_t i) const
{
    ASSERT_LT_(i, m_gt.size());
    return m_gt[i];
}

std::size_t TumRgbdSequence::framesWithoutGroundTruth() const
{
    return static_cast<std::size_t>(
        std::count_if(m_gt.begin(), m_gt.end(), [](const auto& g) { return !g.has_value(); }));
}

std::vector<std::string> TumRgbdSequence::inputFiles() const
{
    std::vector<std::string> files{
        m_dir + "/rgb.txt", m_dir + "/depth.txt", m_dir + "/groundtruth.txt"};
    files.insert(files.end(), m_rgb_files.begin(), m_rgb_files.end());
    files.insert(files.end(), m_depth_files.begin(), m_depth_files.end());
    return files;
}

std::string TumRgbdSequence::rgbImageFile(std::size_t i) const
{
    ASSERT_LT_(i, m_rgb_files.size());
    return m_rgb_files[i];
}

std::string TumRgbdSequence::depthImageFile(std::size_t i) const
{
    ASSERT_LT_(i, m_depth_files.size());
    return m_depth_files[i];
}

TumRgbdSequence::Frame TumRgbdSequence::frame(std::size_t i) const
{
    ASSERTMSG_(isOpen(), "TumRgbdSequence: open() a sequence first");
    ASSERT_LT_(i, m_rgb_t.size());
    const cv::Size size(static_cast<int>(m_width), static_cast<int>(m_height));
    const cv::Mat colour = loadImageFile(m_rgb_files[i], size, "first frame");
    const cv::Mat depth = loadDepth(m_depth_files[i], size, "first frame");

    Frame f;
    f.t = m_rgb_t[i];
    auto obs = mrpt::obs::CObservation3DRangeScan::Create();
    obs->timestamp = mrpt::Clock::fromDouble(f.t);
    obs->sensorLabel = sensor_label;
    obs->hasIntensityImage = true;
    obs->intensityImage = mrpt::img::CImage(colour, mrpt::img::SHALLOW_COPY);
    obs->intensityImageChannel = mrpt::obs::CObservation3DRangeScan::CH_VISIBLE;
    obs->hasRangeImage = true;
    obs->range_is_depth = true;
    obs->rangeUnits = static_cast<float>(1.0 / depth_factor);
    obs->rangeImage_setSize(static_cast<int>(m_height), static_cast<int>(m_width));
    for (int r = 0; r < depth.rows; r++)
    {
        const auto* row = depth.ptr<std::uint16_t>(r);
        for (int c = 0; c < depth.cols; c++)
        {
            obs->rangeImage(r, c) = row[c];
        }
    }
    obs->hasPoints3D = false;
    obs->cameraParams = intrinsics;
    obs->cameraParamsIntensity = intrinsics;
    obs->maxRange = static_cast<float>(65535.0 / depth_factor);
    // Robot frame = colour camera optical frame: sensorPose is the inverse of
    // the (default) pose of the optical frame in MRPT's range-scan frame.
    obs->sensorPose = -obs->relativePoseIntensityWRTDepth;
    f.obs = obs;
    f.ground_truth = m_gt[i];
    return f;
}

SequenceFrame TumRgbdSequence::readFrame(std::size_t i) const
{
    Frame f = frame(i);
    return {std::move(f.obs), std::move(f.ground_truth), f.t};
}

}  // namespace emslam::io
