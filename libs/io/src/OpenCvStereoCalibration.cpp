// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/OpenCvStereoCalibration.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/core/format.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>
#include <mrpt/system/string_utils.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <optional>
#include <stdexcept>
#include <vector>

namespace emslam::io
{
namespace
{
[[noreturn]] void fail(const std::string& file, const std::string& problem)
{
    throw std::runtime_error("OpenCV calibration '" + file + "': " + problem);
}

/** Brackets and YAML indentation at most MAX_OPENCV_CALIBRATION_NESTING deep. */
void requireShallowNesting(const std::string& text, const std::string& file)
{
    int depth = 0;
    std::size_t line = 1;
    bool line_start = true;
    int indent = 0;
    for (const char ch : text)
    {
        if (line_start && ch == ' ')
        {
            // YAML nests by indentation: count levels of two spaces.
            if (++indent / 2 > MAX_OPENCV_CALIBRATION_NESTING)
            {
                fail(file, "line " + std::to_string(line) + ": indented too deeply");
            }
            continue;
        }
        line_start = false;
        if (ch == '\n')
        {
            ++line;
            line_start = true;
            indent = 0;
        }
        else if (ch == '[' || ch == '{' || ch == '<')
        {
            if (++depth > MAX_OPENCV_CALIBRATION_NESTING)
            {
                fail(file, "line " + std::to_string(line) + ": nested too deeply");
            }
        }
        else if ((ch == ']' || ch == '}' || ch == '>') && depth > 0)
        {
            --depth;
        }
    }
}

/** Size, NUL bytes and nesting depth: what OpenCV's parser must never see. */
void precheck(const std::string& file)
{
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
    {
        fail(file, "file not found");
    }
    const auto bytes = std::filesystem::file_size(file, ec);
    if (ec || bytes > MAX_OPENCV_CALIBRATION_BYTES)
    {
        fail(
            file, "larger than " + std::to_string(MAX_OPENCV_CALIBRATION_BYTES) +
                      " bytes: not a calibration file");
    }
    std::ifstream in(file, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.find('\0') != std::string::npos)
    {
        fail(file, "contains NUL bytes: not a text file");
    }
    requireShallowNesting(text, file);
}

/** Most numbers a calibration key holds (a 3x3 matrix: 9; distortion: 8). */
constexpr std::size_t MAX_NUMBERS = 64;

/** The numbers of a flat sequence, each a number node. */
std::vector<double> sequenceNumbers(
    const cv::FileNode& seq, const std::string& file, const std::string& name)
{
    if (seq.size() > MAX_NUMBERS)
    {
        fail(file, name + " has " + std::to_string(seq.size()) + " elements: not a calibration");
    }
    std::vector<double> v;
    for (const auto& e : seq)
    {
        if (!e.isReal() && !e.isInt())
        {
            fail(file, name + ": an element is not a number");
        }
        v.push_back(static_cast<double>(e));
    }
    return v;
}

/** The numbers of a key: a number, a flat sequence, or an `opencv-matrix`
 * map (rows, cols, dt, data) read without cv::Mat, whose reader allocates
 * rows x cols before it looks at the data (a file of a few bytes could ask
 * for gigabytes). */
std::vector<double> flatNumbers(
    const cv::FileNode& n, const std::string& file, const std::string& name)
{
    if (n.isReal() || n.isInt())
    {
        return {static_cast<double>(n)};
    }
    if (n.isSeq())
    {
        return sequenceNumbers(n, file, name);
    }
    if (!n.isMap())
    {
        fail(file, name + " is neither a number, a list nor a matrix");
    }
    const cv::FileNode rows = n["rows"], cols = n["cols"], dt = n["dt"], data = n["data"];
    if (!rows.isInt() || !cols.isInt() || !data.isSeq())
    {
        fail(file, name + ": a matrix needs whole-number rows and cols and a data list");
    }
    const int r = static_cast<int>(rows), c = static_cast<int>(cols);
    if (r < 0 || c < 0 || r > 16 || c > 16)
    {
        fail(file, mrpt::format("%s: a %dx%d matrix is not a calibration", name.c_str(), r, c));
    }
    if (!dt.isString() || std::string(dt).size() != 1)
    {
        fail(file, name + ": dt must be one element type (d, f, i, ...), one channel");
    }
    auto v = sequenceNumbers(data, file, name);
    if (v.size() != static_cast<std::size_t>(r * c))
    {
        fail(
            file,
            mrpt::format("%s: %zu data values for a %dx%d matrix", name.c_str(), v.size(), r, c));
    }
    return v;
}

/** The files' nodes, searched in order: a key comes from the first file that has it. */
class CalibrationNodes
{
public:
    void open(const std::string& file)
    {
        precheck(file);
        cv::FileStorage fs;
        try
        {
            fs.open(file, cv::FileStorage::READ);
        }
        catch (const cv::Exception& e)
        {
            fail(file, "does not parse: " + emslam::util::shortExceptionMessage(e));
        }
        if (!fs.isOpened())
        {
            fail(file, "does not parse as YAML, XML or JSON (cv::FileStorage)");
        }
        m_files.push_back(file);
        m_storages.push_back(std::move(fs));
    }

    /** The first file holding one of `keys`, and that key's node. */
    std::optional<std::pair<std::size_t, cv::FileNode>> find(
        std::initializer_list<const char*> keys) const
    {
        for (std::size_t i = 0; i < m_storages.size(); ++i)
        {
            for (const char* k : keys)
            {
                cv::FileNode n = m_storages[i][k];
                if (!n.empty() && !n.isNone())
                {
                    return std::make_pair(i, n);
                }
            }
        }
        return std::nullopt;
    }

    /** The numbers of a matrix (`!!opencv-matrix`) or a flat sequence. */
    std::vector<double> numbers(
        std::initializer_list<const char*> keys,
        const std::vector<std::size_t>& allowed_sizes,
        bool optional = false) const
    {
        const std::string name = nameOf(keys);
        const auto found = find(keys);
        if (!found)
        {
            if (optional)
            {
                return {};
            }
            fail(m_files.front(), "missing key " + name);
        }
        const std::string& file = m_files[found->first];
        const cv::FileNode& n = found->second;
        std::vector<double> v;
        try
        {
            v = flatNumbers(n, file, name);
        }
        catch (const cv::Exception& e)
        {
            fail(file, name + ": " + emslam::util::shortExceptionMessage(e));
        }
        if (std::find(allowed_sizes.begin(), allowed_sizes.end(), v.size()) == allowed_sizes.end())
        {
            std::string sizes;
            for (const auto s : allowed_sizes)
            {
                sizes += (sizes.empty() ? "" : " or ") + std::to_string(s);
            }
            fail(file, name + " has " + std::to_string(v.size()) + " numbers, expected " + sizes);
        }
        for (const double x : v)
        {
            if (!std::isfinite(x))
            {
                fail(file, name + ": non-finite number");
            }
        }
        return v;
    }

private:
    /** "M1/K1". */
    static std::string nameOf(std::initializer_list<const char*> keys)
    {
        std::string s;
        for (const char* k : keys)
        {
            s += (s.empty() ? "" : "/") + std::string(k);
        }
        return s;
    }

    std::vector<std::string> m_files;
    std::vector<cv::FileStorage> m_storages;
};

mrpt::img::TCamera cameraFrom(const std::vector<double>& K, const std::vector<double>& D)
{
    mrpt::img::TCamera c;
    c.setIntrinsicParamsFromValues(K[0], K[4], K[2], K[5]);
    c.dist.fill(0.0);
    c.distortion =
        D.empty() ? mrpt::img::DistortionModel::none : mrpt::img::DistortionModel::plumb_bob;
    std::copy(D.begin(), D.end(), c.dist.begin());
    return c;
}

/** Throws unless `k` (9 numbers, row-major) is [fx 0 cx; 0 fy cy; 0 0 1]. */
void requirePinholeMatrix(
    const std::vector<double>& k, const std::string& name, const std::string& file)
{
    if (k[1] != 0 || k[3] != 0 || k[6] != 0 || k[7] != 0 || k[8] != 1)
    {
        fail(
            file,
            "camera matrix " + name + " is not [fx 0 cx; 0 fy cy; 0 0 1] (skew is not supported)");
    }
}

/** R from 9 numbers (row-major) or 3 (a Rodrigues vector); throws unless a rotation. */
cv::Mat rotationFrom(const std::vector<double>& r, const std::string& file)
{
    cv::Mat R(3, 3, CV_64F);
    if (r.size() == 3)
    {
        cv::Rodrigues(cv::Mat(r).reshape(1, 3), R);
    }
    else
    {
        R = cv::Mat(r, true).reshape(1, 3);
    }
    // Orthonormal with determinant +1 (to 1e-3: printed files round).
    const cv::Mat RtR = R.t() * R;
    if (cv::norm(RtR - cv::Mat::eye(3, 3, CV_64F), cv::NORM_INF) > 1e-3 ||
        std::abs(cv::determinant(R) - 1.0) > 1e-3)
    {
        fail(file, "R is not a rotation matrix (R^T R = I, det R = 1, to 1e-3)");
    }
    return R;
}

/** [w, h] from image_width / image_height or image_size / imageSize; 0x0 if absent. */
std::pair<unsigned, unsigned> imageSizeOf(const CalibrationNodes& nodes, const std::string& file)
{
    std::vector<double> wh = nodes.numbers({"image_size", "imageSize"}, {0, 2}, true);
    if (wh.empty())
    {
        const auto w = nodes.numbers({"image_width"}, {0, 1}, true);
        const auto h = nodes.numbers({"image_height"}, {0, 1}, true);
        if (w.size() != h.size())
        {
            fail(file, "image_width and image_height must be given together");
        }
        if (w.empty())
        {
            return {0U, 0U};
        }
        wh = {w[0], h[0]};
    }
    for (const double v : wh)
    {
        if (!(v >= 1 && v <= 100000 && v == std::floor(v)))
        {
            fail(file, mrpt::format("image size %g: must be a whole number in [1, 100000]", v));
        }
    }
    return {static_cast<unsigned>(wh[0]), static_cast<unsigned>(wh[1])};
}
cv::Mat cameraMatrixOf(const mrpt::img::TCamera& c)
{
    return (cv::Mat_<double>(3, 3) << c.fx(), 0, c.cx(), 0, c.fy(), c.cy(), 0, 0, 1);
}

/** k1 k2 p1 p2 k3 (and k4 k5 k6 if any is not 0): OpenCV's order, MRPT's too. */
cv::Mat distortionOf(const mrpt::img::TCamera& c)
{
    if (c.distortion == mrpt::img::DistortionModel::none)
    {
        return cv::Mat::zeros(1, 5, CV_64F);
    }
    const bool rational = c.dist[5] != 0 || c.dist[6] != 0 || c.dist[7] != 0;
    cv::Mat d(1, rational ? 8 : 5, CV_64F);
    for (int i = 0; i < d.cols; ++i)
    {
        d.at<double>(0, i) = c.dist[static_cast<std::size_t>(i)];
    }
    return d;
}

/** OpenCV's R, T (X_right = R X_left + T) of `cam`'s T_left_right:
 * R = R_lr^T, T = -R_lr^T t_lr. */
void openCvExtrinsics(const mrpt::img::TStereoCamera& cam, cv::Mat& R, cv::Mat& T)
{
    const mrpt::poses::CPose3D T_left_right(mrpt::poses::CPose3DQuat(cam.rightCameraPose));
    const auto R_lr = T_left_right.getRotationMatrix();
    R.create(3, 3, CV_64F);
    T.create(3, 1, CV_64F);
    for (int i = 0; i < 3; ++i)
    {
        double t = 0;
        for (int j = 0; j < 3; ++j)
        {
            R.at<double>(i, j) = R_lr(j, i);
            t -= R_lr(j, i) * T_left_right.m_coords[static_cast<std::size_t>(j)];
        }
        T.at<double>(i, 0) = t;
    }
}
}  // namespace

bool isOpenCvStorageFile(const std::string& file)
{
    const std::string ext =
        mrpt::system::lowerCase(std::filesystem::path(file).extension().string());
    return ext == ".yml" || ext == ".yaml" || ext == ".xml" || ext == ".json";
}

mrpt::img::TStereoCamera loadOpenCvStereoCalibration(
    const std::string& file, const std::string& extrinsics_file, double translation_scale)
{
    if (!(translation_scale > 0 && translation_scale <= 1e6))
    {
        fail(file, mrpt::format("translation scale %g must be in (0, 1e6]", translation_scale));
    }
    CalibrationNodes nodes;
    nodes.open(file);
    if (!extrinsics_file.empty())
    {
        nodes.open(extrinsics_file);
    }
    const auto K1 = nodes.numbers({"M1", "K1"}, {9});
    const auto K2 = nodes.numbers({"M2", "K2"}, {9});
    requirePinholeMatrix(K1, "M1/K1", file);
    requirePinholeMatrix(K2, "M2/K2", file);
    mrpt::img::TStereoCamera cam;
    cam.leftCamera = cameraFrom(K1, nodes.numbers({"D1"}, {0, 4, 5, 8}, true));
    cam.rightCamera = cameraFrom(K2, nodes.numbers({"D2"}, {0, 4, 5, 8}, true));
    const auto [w, h] = imageSizeOf(nodes, file);
    for (auto* c : {&cam.leftCamera, &cam.rightCamera})
    {
        c->ncols = w;
        c->nrows = h;
    }
    const cv::Mat R = rotationFrom(nodes.numbers({"R"}, {3, 9}), file);
    const auto T = nodes.numbers({"T"}, {3});
    // T_left_right: rotation R^T, position -R^T T (OpenCV maps left points into the right frame).
    mrpt::math::CMatrixDouble33 R_lr;
    mrpt::math::CVectorFixedDouble<3> t_lr;
    for (int i = 0; i < 3; ++i)
    {
        double p = 0;
        for (int j = 0; j < 3; ++j)
        {
            R_lr(i, j) = R.at<double>(j, i);
            p -= R.at<double>(j, i) * T[static_cast<std::size_t>(j)];
        }
        t_lr[i] = p * translation_scale;
    }
    cam.rightCameraPose = mrpt::poses::CPose3DQuat(mrpt::poses::CPose3D(R_lr, t_lr)).asTPose();
    return cam;
}

void saveOpenCvStereoCalibration(const std::string& file, const mrpt::img::TStereoCamera& cam)
{
    cv::FileStorage fs;
    try
    {
        fs.open(file, cv::FileStorage::WRITE);
    }
    catch (const cv::Exception& e)
    {
        fail(file, "cannot be written: " + emslam::util::shortExceptionMessage(e));
    }
    if (!fs.isOpened())
    {
        fail(file, "cannot be written");
    }
    cv::Mat R, T;
    openCvExtrinsics(cam, R, T);
    fs << "image_width" << static_cast<int>(cam.leftCamera.ncols);
    fs << "image_height" << static_cast<int>(cam.leftCamera.nrows);
    fs << "M1" << cameraMatrixOf(cam.leftCamera) << "D1" << distortionOf(cam.leftCamera);
    fs << "M2" << cameraMatrixOf(cam.rightCamera) << "D2" << distortionOf(cam.rightCamera);
    fs << "R" << R << "T" << T;
    fs.release();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
    {
        fail(file, "was not written");
    }
}

}  // namespace emslam::io
