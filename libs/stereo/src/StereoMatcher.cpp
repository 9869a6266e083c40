// SPDX-License-Identifier: BSD-3-Clause
#include "GrayImage.h"
#include "StereoKeyCheck.h"

#include <emslam/stereo/StereoCalibration.h>
#include <emslam/stereo/StereoMatcher.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>

#include <cmath>
#include <mutex>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace emslam::stereo
{
namespace
{
int roundUpTo16(int n)
{
    return ((n + 15) / 16) * 16;
}

/** Intrinsics after resizing an image by `s` (pixel centres stay aligned). */
mrpt::img::TCamera scaledCamera(const mrpt::img::TCamera& c, double s)
{
    mrpt::img::TCamera o = c;
    o.ncols = static_cast<uint32_t>(std::lround(c.ncols * s));
    o.nrows = static_cast<uint32_t>(std::lround(c.nrows * s));
    o.setIntrinsicParamsFromValues(
        c.fx() * s, c.fy() * s, (c.cx() + 0.5) * s - 0.5, (c.cy() + 0.5) * s - 0.5);
    return o;
}

/** OpenCV's SGBM mode of an `algorithm` name. MODE_SGBM and MODE_SGBM_3WAY
 * aggregate costs only along paths that come from the rows above (one pass),
 * so a surface whose disparity changes down the image (a floor, a ceiling) is
 * pulled towards the disparity of the rows above it; MODE_HH runs all 8 paths
 * (two passes) and is unbiased there. */
int sgbmMode(const std::string& algorithm)
{
    if (algorithm == "sgbm_hh")
    {
        return cv::StereoSGBM::MODE_HH;
    }
    if (algorithm == "sgbm_3way")
    {
        return cv::StereoSGBM::MODE_SGBM_3WAY;
    }
    return cv::StereoSGBM::MODE_SGBM;
}
}  // namespace

namespace
{
/** Every key of the section, once for load and save. */
void visit(StereoMatcher::TParameters& p, emslam::util::ConfigVisitor& v)
{
    v.field("algorithm", p.algorithm, "sgbm_hh | sgbm | sgbm_3way | bm");
    v.field("image_scale", p.image_scale, "Resize factor before matching, (0,1]");
    v.field("num_disparities", p.num_disparities, "Disparity range [px] at working scale");
    v.field("min_disparity", p.min_disparity, "Smallest disparity searched [px]");
    v.field("block_size", p.block_size, "Matching window side [px], odd");
    v.field("uniqueness_ratio", p.uniqueness_ratio, "Uniqueness margin [%]");
    v.field("speckle_window_size", p.speckle_window_size, "Speckle blob size removed [px]; 0: off");
    v.field("speckle_range", p.speckle_range, "Max disparity step inside a blob [px]");
    v.field("lr_max_diff", p.lr_max_diff, "Left-right check tolerance [px]; <0: off");
    v.field("texture_threshold", p.texture_threshold, "BM only: minimum texture");
    v.field("pre_filter_cap", p.pre_filter_cap, "Prefilter clip value");
    v.field("p1_per_pixel", p.p1_per_pixel, "SGBM: P1 = p1_per_pixel * block_size^2");
    v.field("p2_per_pixel", p.p2_per_pixel, "SGBM: P2 = p2_per_pixel * block_size^2");
    v.field("min_range", p.min_range, "Minimum depth kept [m]");
    v.field("max_range", p.max_range, "Maximum depth kept [m]");
    v.field(
        "sparse_at_features", p.sparse_at_features,
        "egomotion points by a row search at its features, full size");
    v.field("sparse_block_size", p.sparse_block_size, "that search's SAD window [px], odd, 3..15");
    v.field("subpixel", p.subpixel, "false: whole-pixel disparities (both matchers)");
}
}  // namespace

void StereoMatcher::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    validate();
}

void StereoMatcher::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void StereoMatcher::TParameters::validate() const
{
    requireStereo(
        algorithm == "sgbm_hh" || algorithm == "sgbm" || algorithm == "sgbm_3way" ||
            algorithm == "bm",
        "algorithm", "'" + algorithm + "'", "sgbm_hh, sgbm, sgbm_3way or bm");
    // Below 0.01 a 640x480 image has fewer pixels than one matching block.
    requireStereo(
        image_scale >= 0.01 && image_scale <= 1.0, "image_scale", image_scale, "in [0.01, 1]");
    // Ranges that keep OpenCV's fixed-point disparities (16 x disparity in a
    // short) and SGBM's penalties (p * block_size^2 in an int) from overflowing.
    requireStereo(
        num_disparities > 0 && num_disparities <= 1024, "num_disparities", num_disparities,
        "in [1, 1024]");
    requireStereo(
        min_disparity >= -1000 && min_disparity <= 1000, "min_disparity", min_disparity,
        "in [-1000, 1000]");
    requireStereo(
        block_size >= 1 && block_size <= 255 && block_size % 2 == 1, "block_size", block_size,
        "odd, in [1, 255]");
    requireStereo(lr_max_diff <= 1024, "lr_max_diff", lr_max_diff, "<= 1024 (< 0: off)");
    requireStereo(
        algorithm != "bm" || block_size >= 5, "block_size", block_size, "in [5, 255] for bm");
    requireStereo(
        uniqueness_ratio >= 0 && uniqueness_ratio <= 100, "uniqueness_ratio", uniqueness_ratio,
        "in [0, 100]");
    requireStereo(
        speckle_window_size >= 0 && speckle_window_size <= 100000000, "speckle_window_size",
        speckle_window_size, "in [0, 100000000]");
    // OpenCV scales it by 16 (fixed-point disparities) in an int.
    requireStereo(
        speckle_range >= 0 && speckle_range <= 1024, "speckle_range", speckle_range,
        "in [0, 1024]");
    requireStereo(
        texture_threshold >= 0 && texture_threshold <= 100000000, "texture_threshold",
        texture_threshold, "in [0, 100000000]");
    requireStereo(
        pre_filter_cap >= 1 && pre_filter_cap <= 63, "pre_filter_cap", pre_filter_cap,
        "in [1, 63]");
    requireStereo(
        p1_per_pixel >= 0 && p1_per_pixel <= 10000, "p1_per_pixel", p1_per_pixel, "in [0, 10000]");
    requireStereo(
        p2_per_pixel > p1_per_pixel && p2_per_pixel <= 10000, "p2_per_pixel", p2_per_pixel,
        "in (p1_per_pixel, 10000]");
    // Farther than 10 km no stereo rig resolves depth; the bound keeps map
    // cell indices (coordinate / cell size) far from int overflow.
    requireStereo(min_range >= 0 && min_range < 10000, "min_range", min_range, "in [0, 10000) m");
    requireStereo(
        max_range > min_range && max_range <= 10000, "max_range", max_range,
        "in (min_range, 10000] m");
    requireStereo(
        sparse_block_size >= 3 && sparse_block_size <= 15 && sparse_block_size % 2 == 1,
        "sparse_block_size", sparse_block_size, "odd, in [3, 15]");
}

struct StereoMatcher::Impl
{
    cv::Ptr<cv::StereoMatcher> matcher;
    // OpenCV's matchers keep working buffers in the object (the speckle
    // filter's among them): one compute at a time.
    std::mutex compute_mutex;
};

StereoMatcher::StereoMatcher() : StereoMatcher(TParameters()) {}
StereoMatcher::StereoMatcher(const TParameters& p) : m_impl(std::make_unique<Impl>())
{
    setParameters(p);
}
StereoMatcher::~StereoMatcher() = default;
StereoMatcher::StereoMatcher(StereoMatcher&&) noexcept = default;
StereoMatcher& StereoMatcher::operator=(StereoMatcher&&) noexcept = default;

void StereoMatcher::setParameters(const TParameters& p)
{
    p.validate();
    m_params = p;
    const int nd = roundUpTo16(p.num_disparities);
    const int lr = p.lr_max_diff < 0 ? -1 : p.lr_max_diff;
    if (p.algorithm == "bm")
    {
        auto bm = cv::StereoBM::create(nd, p.block_size);
        bm->setMinDisparity(p.min_disparity);
        bm->setUniquenessRatio(p.uniqueness_ratio);
        bm->setTextureThreshold(p.texture_threshold);
        bm->setPreFilterCap(p.pre_filter_cap);
        bm->setSpeckleWindowSize(p.speckle_window_size);
        bm->setSpeckleRange(p.speckle_range);
        bm->setDisp12MaxDiff(lr);
        m_impl->matcher = bm;
        return;
    }
    const int area = p.block_size * p.block_size;
    auto sgbm = cv::StereoSGBM::create(
        p.min_disparity, nd, p.block_size, p.p1_per_pixel * area, p.p2_per_pixel * area, lr,
        p.pre_filter_cap, p.uniqueness_ratio, p.speckle_window_size, p.speckle_range,
        sgbmMode(p.algorithm));
    m_impl->matcher = sgbm;
}

cv::Mat StereoMatcher::computeDisparity(const cv::Mat& left_gray, const cv::Mat& right_gray) const
{
    ASSERTMSG_(!left_gray.empty() && !right_gray.empty(), "Stereo: empty image");
    ASSERTMSG_(left_gray.size() == right_gray.size(), "Stereo: left/right image sizes differ");
    cv::Mat l = grayImage(left_gray), r = grayImage(right_gray);
    ASSERTMSG_(l.depth() == CV_8U, "Stereo: images must be 8-bit");
    if (m_params.image_scale != 1.0)
    {
        cv::resize(l, l, cv::Size(), m_params.image_scale, m_params.image_scale, cv::INTER_AREA);
        cv::resize(r, r, cv::Size(), m_params.image_scale, m_params.image_scale, cv::INTER_AREA);
    }
    cv::Mat disp16;
    {
        std::lock_guard<std::mutex> lock(m_impl->compute_mutex);
        m_impl->matcher->compute(l, r, disp16);
    }
    // OpenCV returns fixed point (x16) with min_disparity-1 marking invalid pixels.
    cv::Mat disp;
    if (m_params.subpixel)
    {
        disp16.convertTo(disp, CV_32F, 1.0 / 16.0);
    }
    else
    {
        // Nearest whole pixel: (d16 + 8) / 16, floored (min_disparity may be negative).
        disp16.convertTo(disp, CV_32F, 1.0 / 16.0, 0.5);
        disp.forEach<float>([](float& d, const int*) { d = std::floor(d); });
    }
    cv::Mat invalid = disp16 < static_cast<short>(m_params.min_disparity * 16);
    disp.setTo(0.0f, invalid);
    return disp;
}

StereoFrame StereoMatcher::compute(
    const cv::Mat& left, const cv::Mat& right, const mrpt::img::TStereoCamera& camera) const
{
    ASSERTMSG_(!left.empty() && !right.empty(), "Stereo: empty image");
    ASSERTMSG_(
        left.cols == static_cast<int>(camera.leftCamera.ncols) &&
            left.rows == static_cast<int>(camera.leftCamera.nrows),
        mrpt::format(
            "Stereo: image size %dx%d differs from the calibration's %ux%u", left.cols, left.rows,
            camera.leftCamera.ncols, camera.leftCamera.nrows));
    validateStereoCamera(camera, "stereo calibration");

    StereoFrame f;
    const double s = m_params.image_scale;
    f.camera = camera;
    f.camera.leftCamera = scaledCamera(camera.leftCamera, s);
    f.camera.rightCamera = scaledCamera(camera.rightCamera, s);

    f.disparity = computeDisparity(left, right);
    const cv::Mat gray = grayImage(left);
    if (s != 1.0)
    {
        cv::resize(gray, f.intensity, f.disparity.size(), 0, 0, cv::INTER_AREA);
    }
    else
    {
        f.intensity = gray.clone();
    }

    const auto& lc = f.camera.leftCamera;
    const double fx = lc.fx(), fy = lc.fy(), cx = lc.cx(), cy = lc.cy();
    // A rectified pair may keep different principal points (e.g. Middlebury):
    // the true disparity is then d + (cx_right - cx_left).
    const double doffs = f.camera.rightCamera.cx() - cx;
    const double fb = fx * baselineOf(camera);

    f.valid = cv::Mat::zeros(f.disparity.size(), CV_8UC1);
    f.points.reserve(f.disparity.total() / 2);
    f.pixels.reserve(f.disparity.total() / 2);
    for (int v = 0; v < f.disparity.rows; ++v)
    {
        float* drow = f.disparity.ptr<float>(v);
        uint8_t* mrow = f.valid.ptr<uint8_t>(v);
        for (int u = 0; u < f.disparity.cols; ++u)
        {
            if (drow[u] <= 0.0f)
            {
                continue;
            }
            const double d = drow[u] + doffs;
            const double z = d > 0.0 ? fb / d : -1.0;
            if (z < m_params.min_range || z > m_params.max_range)
            {
                drow[u] = 0.0f;  // keep `disparity` consistent with `valid`
                continue;
            }
            mrow[u] = 255;
            f.points.emplace_back(
                static_cast<float>((u - cx) * z / fx), static_cast<float>((v - cy) * z / fy),
                static_cast<float>(z));
            f.pixels.push_back({static_cast<uint16_t>(u), static_cast<uint16_t>(v)});
        }
    }
    return f;
}

}  // namespace emslam::stereo
