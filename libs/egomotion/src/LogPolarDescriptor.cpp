// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/egomotion/LogPolarDescriptor.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace emslam::egomotion
{
namespace
{
/** A descriptor whose samples vary less than this (RMS, grey levels) is
 * flat: its correlation would only measure interpolation noise. */
constexpr float FLAT_RMS = 1e-3f;
}  // namespace

Descriptors LogPolarDescriptorExtractor::compute(
    const cv::Mat& image, const FeatureList& features) const
{
    const auto& p = m_params;
    ASSERT_GE_(p.num_rings, 1);
    ASSERT_GE_(p.num_angles, 1);
    ASSERT_GT_(p.min_radius, 0.0f);
    ASSERT_GE_(p.radius, p.min_radius);
    ASSERT_(image.type() == CV_8UC1);

    Descriptors d;
    d.dim = p.num_rings * p.num_angles;
    d.data.assign(features.size() * static_cast<std::size_t>(d.dim), 0.0f);

    // Offset table, in the feature's rotated frame (gradient along +x):
    // rings log-spaced from min_radius to radius, angles uniform. Row layout
    // is ring-major, so a rotation is a shift along the angle axis.
    std::vector<float> ox(d.dim), oy(d.dim);
    const double ratio =
        p.num_rings > 1 ? std::log(static_cast<double>(p.radius) / p.min_radius) / (p.num_rings - 1)
                        : 0.0;
    for (int k = 0; k < p.num_rings; ++k)
    {
        const double r = p.min_radius * std::exp(ratio * k);
        for (int j = 0; j < p.num_angles; ++j)
        {
            const double th = 2.0 * M_PI * j / p.num_angles;
            ox[k * p.num_angles + j] = static_cast<float>(r * std::cos(th));
            oy[k * p.num_angles + j] = static_cast<float>(r * std::sin(th));
        }
    }

    const float x_max = static_cast<float>(image.cols - 1);
    const float y_max = static_cast<float>(image.rows - 1);
    const float flat_sq = FLAT_RMS * FLAT_RMS * static_cast<float>(d.dim);
    const std::size_t step = image.step1();
    for (std::size_t i = 0; i < features.size(); ++i)
    {
        const Feature& f = features[i];
        const float px = f.u, py = f.v;
        // Any rotation of the disc stays in the image iff its bounding box does.
        if (px - p.radius < 0 || py - p.radius < 0 || px + p.radius > x_max ||
            py + p.radius > y_max)
        {
            continue;  // zero row
        }
        // Rotating the sampling grid by the gradient angle is the continuous
        // form of the paper's cyclic shift of the log-polar angle axis.
        const float c = std::cos(f.gradient_angle), s = std::sin(f.gradient_angle);
        float* out = d.data.data() + i * d.dim;
        float sum = 0;
        for (int k = 0; k < d.dim; ++k)
        {
            const float x = px + c * ox[k] - s * oy[k];
            const float y = py + s * ox[k] + c * oy[k];
            // x <= cols-1: clamp the cell so that x0+1 stays inside.
            const int x0 = std::min(static_cast<int>(x), image.cols - 2);
            const int y0 = std::min(static_cast<int>(y), image.rows - 2);
            const float fx = x - x0, fy = y - y0;
            const uint8_t* a = image.data + y0 * step + x0;
            const uint8_t* b = a + step;
            const float top = a[0] + fx * (a[1] - a[0]);
            const float bot = b[0] + fx * (b[1] - b[0]);
            out[k] = top + fy * (bot - top);
            sum += out[k];
        }
        // Pearson's rho of two rows becomes their dot product.
        const float mean = sum / d.dim;
        float sq = 0;
        for (int k = 0; k < d.dim; ++k)
        {
            out[k] -= mean;
            sq += out[k] * out[k];
        }
        if (!(sq > flat_sq))
        {
            std::fill(out, out + d.dim, 0.0f);
            continue;
        }
        const float inv = 1.0f / std::sqrt(sq);
        for (int k = 0; k < d.dim; ++k)
        {
            out[k] *= inv;
        }
    }
    return d;
}

}  // namespace emslam::egomotion
