// SPDX-License-Identifier: BSD-3-Clause
#include "StereoPairFiles.h"

#include <emslam/io/CalibrationFiles.h>
#include <emslam/io/DataFile.h>
#include <emslam/io/DatasetStamps.h>
#include <emslam/io/EurocSequence.h>
#include <emslam/io/ImageFile.h>
#include <emslam/io/TextParsing.h>

#include <mrpt/core/Clock.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/math/CQuaternion.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <utility>

namespace fs = std::filesystem;

namespace emslam::io
{
namespace
{
/** Opens the EuRoC CSV file `file` (throws "Cannot open EuRoC <what> '<file>'"
 * if it cannot) and calls `on_row(fields, line, line_no)` for every line that is
 * not blank or a `#` comment: `fields` are its comma-separated fields,
 * trimmed; `line_no` counts from 1. */
template <typename RowFn>
void forEachCsvRow(const std::string& file, const char* what, RowFn&& on_row)
{
    auto f = openTextFile(file, std::string("EuRoC ") + what);
    forEachDataLine(
        f,
        [&](const std::string& line, std::size_t line_no)
        { on_row(splitCommaFields(line), line, line_no); },
        file);
}

constexpr const char* MAX_NS_TEXT = "9223372036854775807";

struct CsvImage
{
    std::int64_t t_ns;
    std::string file;
};

/** The images of `cam_dir`/data.csv, in the order of the file: their stamps
 * are plausible and strictly increasing (parseImageStampNs(), IncreasingStamps). */
std::vector<CsvImage> readDataCsv(const std::string& cam_dir)
{
    const std::string file = cam_dir + "/data.csv";
    std::vector<CsvImage> out;
    IncreasingStamps<std::int64_t> order(file);
    forEachCsvRow(
        file, "image list",
        [&](const std::vector<std::string>& fields, const std::string& line, std::size_t line_no)
        {
            if (fields.size() != 2 || fields[1].empty())
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: expected 'timestamp_ns,filename', got %s", file.c_str(), line_no,
                    quotedExcerpt(line).c_str());
            }
            const std::int64_t t = parseImageStampNs(fields[0], file, line_no);
            order.add(t, fields[0], line_no);
            out.push_back({t, cam_dir + "/data/" + fields[1]});
        });
    if (out.empty())
    {
        THROW_EXCEPTION_FMT("EuRoC image list '%s' lists no image", file.c_str());
    }
    return out;
}

mrpt::Clock::time_point fromNs(std::int64_t t_ns)
{
    // Exact: the UNIX epoch plus whole 100 ns ticks (a double would lose
    // sub-microsecond digits of a 2014 timestamp). Rounded without computing
    // t_ns + 50, which overflows near INT64_MAX; t_ns >= 0 (parseImageStampNs).
    ASSERT_GE_(t_ns, 0);
    const std::int64_t ticks = t_ns / 100 + (t_ns % 100 >= 50 ? 1 : 0);
    return mrpt::Clock::fromDouble(0.0) + mrpt::Clock::duration(ticks);
}

/** |a - b| of two non-negative stamps (their difference cannot overflow). */
std::int64_t absDifferenceNs(std::int64_t a, std::int64_t b)
{
    return a > b ? a - b : b - a;
}
}  // namespace

std::vector<EurocSequence::GtRow> EurocSequence::readGroundTruthCsv(const std::string& file)
{
    std::vector<GtRow> rows;
    forEachCsvRow(
        file, "ground-truth file",
        [&](const std::vector<std::string>& fields, const std::string& line, std::size_t line_no)
        {
            if (fields.size() == 17)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: 17 columns: this looks like EuRoC's state_groundtruth_estimate0 "
                    "(body/IMU pose, quaternion w first). Expected the left camera's pose: "
                    "'timestamp_ns,x,y,z,qx,qy,qz,qw'",
                    file.c_str(), line_no);
            }
            if (fields.size() != 8)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: expected 8 fields 'timestamp_ns,x,y,z,qx,qy,qz,qw', got %zu",
                    file.c_str(), line_no, fields.size());
            }
            GtRow row;
            double v[7];
            if (!parseNanoseconds(fields[0], row.t_ns))
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: timestamp %s is not an integer number of nanoseconds in [0, %s]",
                    file.c_str(), line_no, quotedExcerpt(fields[0]).c_str(), MAX_NS_TEXT);
            }
            bool ok = true;
            for (int k = 0; k < 7 && ok; k++)
            {
                ok = parseDouble(fields[k + 1], v[k]) && std::isfinite(v[k]);
            }
            if (!ok)
            {
                THROW_EXCEPTION_FMT(
                    "%s:%zu: not a number in %s", file.c_str(), line_no,
                    quotedExcerpt(line).c_str());
            }
            const double norm = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
            if (norm < 1e-9)
            {
                THROW_EXCEPTION_FMT("%s:%zu: zero quaternion", file.c_str(), line_no);
            }
            const mrpt::math::CQuaternionDouble q(
                v[6] / norm, v[3] / norm, v[4] / norm, v[5] / norm);
            row.pose = mrpt::poses::CPose3D(q, v[0], v[1], v[2]);
            rows.push_back(row);
        });
    if (rows.empty())
    {
        THROW_EXCEPTION_FMT("EuRoC ground-truth file '%s' holds no pose", file.c_str());
    }
    std::stable_sort(
        rows.begin(), rows.end(), [](const GtRow& a, const GtRow& b) { return a.t_ns < b.t_ns; });
    return rows;
}

namespace
{
/** The folder holding cam0 and cam1: mav0_dir itself or its mav0. */
std::string cameraFolder(const std::string& mav0_dir)
{
    std::error_code ec;
    if (!fs::is_directory(mav0_dir, ec))
    {
        THROW_EXCEPTION_FMT("EuRoC folder '%s' does not exist", mav0_dir.c_str());
    }
    std::string dir = mav0_dir;
    if (!fs::is_directory(dir + "/cam0", ec) && fs::is_directory(dir + "/mav0/cam0", ec))
    {
        dir += "/mav0";
    }
    for (const char* cam : {"cam0", "cam1"})
    {
        if (!fs::is_directory(dir + "/" + cam, ec))
        {
            THROW_EXCEPTION_FMT("EuRoC folder '%s' has no '%s' folder", dir.c_str(), cam);
        }
    }
    return dir;
}

/** The image pairs of equal stamps, their files checked to exist. */
struct StereoPairs
{
    std::vector<std::int64_t> stamps;
    std::vector<std::string> left, right;
};

/** Both lists rise strictly: one merge pass pairs equal stamps; an image
 * the other camera has no image for is dropped. */
StereoPairs pairByStamp(
    const std::vector<CsvImage>& left, const std::vector<CsvImage>& right, const std::string& dir)
{
    StereoPairs p;
    std::size_t li = 0, ri = 0;
    while (li < left.size() && ri < right.size())
    {
        if (left[li].t_ns < right[ri].t_ns)
        {
            ++li;
        }
        else if (right[ri].t_ns < left[li].t_ns)
        {
            ++ri;
        }
        else
        {
            p.stamps.push_back(left[li].t_ns);
            p.left.push_back(left[li++].file);
            p.right.push_back(right[ri++].file);
        }
    }
    if (p.stamps.empty())
    {
        THROW_EXCEPTION_FMT(
            "EuRoC folder '%s': no timestamp of cam0/data.csv appears in cam1/data.csv",
            dir.c_str());
    }
    std::error_code ec;
    for (std::size_t i = 0; i < p.stamps.size(); i++)
    {
        for (const auto* file : {&p.left[i], &p.right[i]})
        {
            if (!fs::is_regular_file(*file, ec))
            {
                THROW_EXCEPTION_FMT("EuRoC image '%s' is missing", file->c_str());
            }
        }
    }
    return p;
}

/** Per stamp, the pose of the nearest ground-truth row within max_dt_ns
 * (rows sorted by time), or none. */
std::vector<std::optional<mrpt::poses::CPose3D>> posesAtStamps(
    const std::vector<std::int64_t>& stamps,
    const std::vector<EurocSequence::GtRow>& rows,
    std::int64_t max_dt_ns)
{
    using GtRow = EurocSequence::GtRow;
    std::vector<std::optional<mrpt::poses::CPose3D>> gt(stamps.size());
    for (std::size_t i = 0; i < stamps.size(); i++)
    {
        const auto it = std::lower_bound(
            rows.begin(), rows.end(), stamps[i],
            [](const GtRow& r, std::int64_t t) { return r.t_ns < t; });
        const GtRow* best = nullptr;
        std::int64_t best_dt = 0;
        for (auto c : {it, it == rows.begin() ? rows.end() : std::prev(it)})
        {
            if (c == rows.end())
            {
                continue;
            }
            const std::int64_t dt = absDifferenceNs(c->t_ns, stamps[i]);
            if (best == nullptr || dt < best_dt)
            {
                best = &*c;
                best_dt = dt;
            }
        }
        if (best != nullptr && best_dt <= max_dt_ns)
        {
            gt[i] = best->pose;
        }
    }
    return gt;
}
}  // namespace

void EurocSequence::open(const std::string& mav0_dir, const std::string& gt_csv)
{
    m_dir.clear();
    m_stamps.clear();
    m_left_files.clear();
    m_right_files.clear();
    m_gt.clear();
    m_has_gt = false;
    m_unpaired = 0;

    const std::string dir = cameraFolder(mav0_dir);
    const auto left = readDataCsv(dir + "/cam0");
    const auto right = readDataCsv(dir + "/cam1");
    StereoPairs pairs = pairByStamp(left, right, dir);
    const std::vector<std::string>& lf = pairs.left;
    const std::vector<std::string>& rf = pairs.right;
    // An image the other camera has no image for is counted.
    m_unpaired = left.size() + right.size() - 2 * pairs.stamps.size();

    m_calib = loadEurocCalibration(dir + "/cam0/sensor.yaml", dir + "/cam1/sensor.yaml");
    // Sizes from the headers: a huge image is refused before it is decoded.
    const cv::Size l0 = imageFileSize(lf[0]);
    const cv::Size r0 = imageFileSize(rf[0]);
    if (l0 != r0)
    {
        THROW_EXCEPTION_FMT(
            "Left/right image size mismatch: '%s' is %dx%d but '%s' is %dx%d", lf[0].c_str(),
            l0.width, l0.height, rf[0].c_str(), r0.width, r0.height);
    }
    m_width = static_cast<unsigned int>(l0.width);
    m_height = static_cast<unsigned int>(l0.height);
    if (m_calib.leftCamera.ncols != m_width || m_calib.leftCamera.nrows != m_height ||
        m_calib.rightCamera.ncols != m_width || m_calib.rightCamera.nrows != m_height)
    {
        THROW_EXCEPTION_FMT(
            "Image size %ux%u of '%s' differs from the calibration's resolution %ux%u (left) / "
            "%ux%u (right) in '%s/cam*/sensor.yaml'",
            m_width, m_height, lf[0].c_str(), m_calib.leftCamera.ncols, m_calib.leftCamera.nrows,
            m_calib.rightCamera.ncols, m_calib.rightCamera.nrows, dir.c_str());
    }
    // The first pair must decode.
    loadImageFile(lf[0], l0, "its header");
    loadImageFile(rf[0], r0, "its header");

    std::vector<std::optional<mrpt::poses::CPose3D>> gt(pairs.stamps.size());
    if (!gt_csv.empty())
    {
        // Bounded so that the conversion to nanoseconds below cannot overflow.
        if (!(gt_max_dt >= 0.0 && gt_max_dt <= 1e9))
        {
            THROW_EXCEPTION_FMT("gt_max_dt = %g s: must be in [0, 1e9]", gt_max_dt);
        }
        gt = posesAtStamps(
            pairs.stamps, readGroundTruthCsv(gt_csv),
            static_cast<std::int64_t>(std::llround(gt_max_dt * 1e9)));
        m_has_gt = true;
    }

    m_stamps = std::move(pairs.stamps);
    m_left_files = std::move(pairs.left);
    m_right_files = std::move(pairs.right);
    m_gt = std::move(gt);
    m_dir = dir;
}

std::int64_t EurocSequence::timestampNs(std::size_t i) const
{
    ASSERT_LT_(i, m_stamps.size());
    return m_stamps[i];
}

std::optional<mrpt::poses::CPose3D> EurocSequence::groundTruth(std::size_t i) const
{
    ASSERT_LT_(i, m_gt.size());
    return m_gt[i];
}

std::size_t EurocSequence::framesWithoutGroundTruth() const
{
    return static_cast<std::size_t>(
        std::count_if(m_gt.begin(), m_gt.end(), [](const auto& g) { return !g.has_value(); }));
}

std::vector<std::string> EurocSequence::inputFiles() const
{
    std::vector<std::string> files{
        m_dir + "/cam0/data.csv", m_dir + "/cam1/data.csv", m_dir + "/cam0/sensor.yaml",
        m_dir + "/cam1/sensor.yaml"};
    files.insert(files.end(), m_left_files.begin(), m_left_files.end());
    files.insert(files.end(), m_right_files.begin(), m_right_files.end());
    return files;
}

std::string EurocSequence::leftImageFile(std::size_t i) const
{
    ASSERT_LT_(i, m_left_files.size());
    return m_left_files[i];
}

std::string EurocSequence::rightImageFile(std::size_t i) const
{
    ASSERT_LT_(i, m_right_files.size());
    return m_right_files[i];
}

EurocSequence::Frame EurocSequence::frame(std::size_t i) const
{
    ASSERTMSG_(isOpen(), "EurocSequence: open() a sequence first");
    ASSERT_LT_(i, m_stamps.size());
    Frame f;
    f.t = timestamp(i);
    f.obs = loadStereoPairObservation(m_left_files[i], m_right_files[i], m_calib, "calibration");
    f.obs->timestamp = fromNs(m_stamps[i]);
    f.obs->sensorLabel = sensor_label;
    f.ground_truth = m_gt[i];
    return f;
}

SequenceFrame EurocSequence::readFrame(std::size_t i) const
{
    Frame f = frame(i);
    return {std::move(f.obs), std::move(f.ground_truth), f.t};
}

}  // namespace emslam::io
