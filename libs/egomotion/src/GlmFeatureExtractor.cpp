// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/egomotion/GlmFeatureExtractor.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <optional>

namespace emslam::egomotion
{
namespace
{
/** True when no pixel of the window around (u, v), other than (u, v) itself,
 * has the value `value`. The caller already knows `value` is the window
 * maximum, so this is the "strict" part of the test. */
bool isUniqueInWindow(const cv::Mat& sq, int u, int v, int lo, int hi, float value)
{
    const int r0 = std::max(v + lo, 0), r1 = std::min(v + hi, sq.rows - 1);
    const int c0 = std::max(u + lo, 0), c1 = std::min(u + hi, sq.cols - 1);
    for (int r = r0; r <= r1; ++r)
    {
        const float* row = sq.ptr<float>(r);
        for (int c = c0; c <= c1; ++c)
        {
            if (row[c] == value && (r != v || c != u))
            {
                return false;
            }
        }
    }
    return true;
}

}  // namespace

/** |grad I| (squared), its direction and its window maximum: what the GLM
 * tests read. */
class GlmFeatureExtractor::Gradients
{
public:
    cv::Mat image;  //!< a copy of the image they are of (its buffer may be reused)
    cv::Mat gx, gy, sq, local_max;
    int window{0};
    float min_gradient{0};
    int lo{0}, hi{0};  //!< window offsets
    float min_sq{0};

    Gradients(const cv::Mat& img, int w, float min_gradient_)
        : image(img.clone()), window(w), min_gradient(min_gradient_)
    {
        cv::Sobel(img, gx, CV_32F, 1, 0, 3);
        cv::Sobel(img, gy, CV_32F, 0, 1, 3);
        // Squared magnitude: Sobel of an 8-bit image gives integer gx, gy, so
        // |grad|^2 is an exact integer in float and the "strictly greater" test
        // is free of rounding ties; the square root is monotonic.
        cv::multiply(gx, gx, sq);
        cv::Mat gy2;
        cv::multiply(gy, gy, gy2);
        sq += gy2;
        // Window offsets lo..hi, i.e. -W/2 .. W-1-W/2: centred for odd W, one
        // pixel more on the negative side for even W. The dilate anchor at W/2
        // realises exactly these offsets; the outside of the image never wins.
        lo = -(w / 2);
        hi = w - 1 - w / 2;
        cv::dilate(
            sq, local_max, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(w, w)),
            cv::Point(w / 2, w / 2), 1, cv::BORDER_CONSTANT, cv::morphologyDefaultBorderValue());
        // Cheap pre-filter on the square, slightly loose so that rounding never
        // drops a pixel; the exact test is on |grad I| in isFeature().
        min_sq = 0.999f * min_gradient * min_gradient;
    }

    /** Whether these are the maps of `img` with these parameters: its
     * pixels compared, since a caller may copy the image or reuse a buffer. */
    bool areOf(const cv::Mat& img, int w, float min_gradient_) const
    {
        if (w != window || min_gradient_ != min_gradient || img.size() != image.size() ||
            img.type() != image.type())
        {
            return false;
        }
        const std::size_t row_bytes = static_cast<std::size_t>(img.cols) * img.elemSize();
        for (int r = 0; r < img.rows; ++r)
        {
            if (std::memcmp(img.ptr(r), image.ptr(r), row_bytes) != 0)
            {
                return false;
            }
        }
        return true;
    }

    /** Every test but the 3D point's; `mag` gets |grad I| when true. */
    bool isFeature(int u, int v, float floor, float& mag) const
    {
        // The Sobel response on the outermost pixels sees a mirrored image:
        // not a real gradient, so never a feature.
        if (u < 1 || v < 1 || u >= sq.cols - 1 || v >= sq.rows - 1)
        {
            return false;
        }
        const float m2 = sq.at<float>(v, u);
        if (m2 <= 0.0f || m2 < min_sq || m2 != local_max.at<float>(v, u))
        {
            return false;
        }
        if (!isUniqueInWindow(sq, u, v, lo, hi, m2))
        {
            return false;
        }
        mag = std::sqrt(m2);
        return mag >= floor;
    }
};

FeatureList GlmFeatureExtractor::extract(const emslam::stereo::StereoFrame& frame) const
{
    return extract(frame, nullptr);
}

FeatureList GlmFeatureExtractor::extract(
    const emslam::stereo::StereoFrame& frame, const Gradients* gradients) const
{
    ASSERT_GE_(m_params.window_size, 1);
    ASSERT_GE_(m_params.min_gradient, 0.0f);
    const cv::Mat& img = frame.intensity;
    ASSERT_(img.type() == CV_8UC1);
    const bool has_mask = !frame.valid.empty();
    if (has_mask)
    {
        ASSERT_(frame.valid.type() == CV_8UC1 && frame.valid.size() == img.size());
    }
    ASSERT_EQUAL_(frame.points.size(), frame.pixels.size());

    FeatureList out;
    if (img.rows < 3 || img.cols < 3 || frame.pixels.empty())
    {
        return out;
    }
    std::optional<Gradients> computed;
    if (gradients == nullptr || !gradients->areOf(img, m_params.window_size, m_params.min_gradient))
    {
        gradients = &computed.emplace(img, m_params.window_size, m_params.min_gradient);
    }
    const Gradients& g = *gradients;
    const int w = m_params.window_size;
    out.reserve(frame.pixels.size() / static_cast<std::size_t>(std::max(1, w * w / 4)) + 16);
    // Visiting the 3D points (instead of all pixels) looks the point up for
    // free; it is the pixel->point map read in the other direction.
    for (std::size_t i = 0; i < frame.pixels.size(); ++i)
    {
        const int u = frame.pixels[i].u, v = frame.pixels[i].v;
        float mag = 0;
        if (u >= img.cols || v >= img.rows || (has_mask && frame.valid.at<uint8_t>(v, u) == 0) ||
            !g.isFeature(u, v, m_params.min_gradient, mag))
        {
            continue;
        }
        Feature f;
        f.u = static_cast<std::uint16_t>(u);
        f.v = static_cast<std::uint16_t>(v);
        f.point = frame.points[i];
        float angle = std::atan2(g.gy.at<float>(v, u), g.gx.at<float>(v, u));
        if (angle <= -static_cast<float>(M_PI))
        {
            angle = static_cast<float>(M_PI);  // keep the documented (-pi, pi]
        }
        f.gradient_angle = angle;
        f.gradient_magnitude = mag;
        out.push_back(f);
    }
    return out;
}

std::vector<emslam::stereo::PixelCoord> GlmFeatureExtractor::locate(const cv::Mat& img) const
{
    std::shared_ptr<const Gradients> unused;
    return locate(img, unused);
}

std::vector<emslam::stereo::PixelCoord> GlmFeatureExtractor::locate(
    const cv::Mat& img, std::shared_ptr<const Gradients>& gradients) const
{
    ASSERT_GE_(m_params.window_size, 1);
    ASSERT_GE_(m_params.min_gradient, 0.0f);
    ASSERT_(img.type() == CV_8UC1);
    std::vector<emslam::stereo::PixelCoord> out;
    gradients.reset();
    if (img.rows < 3 || img.cols < 3)
    {
        return out;
    }
    auto maps = std::make_shared<const Gradients>(img, m_params.window_size, m_params.min_gradient);
    const Gradients& g = *maps;
    gradients = maps;
    for (int v = 1; v < img.rows - 1; ++v)
    {
        const float* sq = g.sq.ptr<float>(v);
        const float* mx = g.local_max.ptr<float>(v);
        for (int u = 1; u < img.cols - 1; ++u)
        {
            float mag = 0;
            // The row test first: most pixels are not their window's maximum.
            if (sq[u] == mx[u] && g.isFeature(u, v, m_params.min_gradient, mag))
            {
                out.push_back({static_cast<std::uint16_t>(u), static_cast<std::uint16_t>(v)});
            }
        }
    }
    return out;
}

}  // namespace emslam::egomotion
