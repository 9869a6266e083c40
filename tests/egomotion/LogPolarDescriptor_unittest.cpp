// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/egomotion/LogPolarDescriptor.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>

using emslam::egomotion::Descriptors;
using emslam::egomotion::Feature;
using emslam::egomotion::FeatureList;
using emslam::egomotion::LogPolarDescriptorExtractor;

namespace
{
/** Seeded noise blurred to a smooth texture, grey levels in [lo, hi]. */
cv::Mat smoothTexture(int w, int h, unsigned seed, double sigma, double lo, double hi)
{
    cv::Mat noise(h, w, CV_32F);
    cv::RNG rng(seed);
    rng.fill(noise, cv::RNG::UNIFORM, 0.0, 1.0);
    cv::GaussianBlur(noise, noise, cv::Size(), sigma);
    cv::normalize(noise, noise, lo, hi, cv::NORM_MINMAX);
    cv::Mat out;
    noise.convertTo(out, CV_8U);
    return out;
}

/** A feature at (u, v) oriented by the image's Sobel gradient there. */
Feature orientedFeature(const cv::Mat& img, int u, int v)
{
    cv::Mat gx, gy;
    cv::Sobel(img, gx, CV_32F, 1, 0, 3);
    cv::Sobel(img, gy, CV_32F, 0, 1, 3);
    Feature f;
    f.u = static_cast<std::uint16_t>(u);
    f.v = static_cast<std::uint16_t>(v);
    f.gradient_angle = std::atan2(gy.at<float>(v, u), gx.at<float>(v, u));
    f.gradient_magnitude = std::hypot(gx.at<float>(v, u), gy.at<float>(v, u));
    return f;
}

float dot(const Descriptors& a, std::size_t i, const Descriptors& b, std::size_t j)
{
    return std::inner_product(a.row(i), a.row(i) + a.dim, b.row(j), 0.0f);
}

float norm(const Descriptors& d, std::size_t i)
{
    return std::sqrt(dot(d, i, d, i));
}
}  // namespace

TEST(LogPolarDescriptor, rowsAreZeroMeanUnitNorm)
{
    const cv::Mat img = smoothTexture(64, 64, 1, 2.0, 30, 220);
    const FeatureList feats{orientedFeature(img, 20, 20), orientedFeature(img, 40, 33)};
    const LogPolarDescriptorExtractor ex;
    const auto d = ex.compute(img, feats);
    ASSERT_EQ(d.dim, ex.parameters().num_rings * ex.parameters().num_angles);
    ASSERT_EQ(d.size(), feats.size());
    for (std::size_t i = 0; i < d.size(); ++i)
    {
        EXPECT_NEAR(std::accumulate(d.row(i), d.row(i) + d.dim, 0.0f), 0.0f, 1e-4f);
        EXPECT_NEAR(norm(d, i), 1.0f, 1e-5f);
    }
}

TEST(LogPolarDescriptor, rotatedPatchMatchesAfterOrientationNormalisation)
{
    // Texture of ~2 px grain: Sobel and resampling commute with rotation up
    // to small errors.
    const cv::Mat img = smoothTexture(121, 121, 42, 1.5, 20, 235);
    // The feature: the strongest gradient near the centre.
    cv::Mat gx, gy, mag;
    cv::Sobel(img, gx, CV_32F, 1, 0, 3);
    cv::Sobel(img, gy, CV_32F, 0, 1, 3);
    cv::magnitude(gx, gy, mag);
    cv::Point c;
    cv::minMaxLoc(mag(cv::Rect(55, 55, 11, 11)), nullptr, nullptr, nullptr, &c);
    c += cv::Point(55, 55);

    const LogPolarDescriptorExtractor ex;
    const Feature f0 = orientedFeature(img, c.x, c.y);
    const auto d0 = ex.compute(img, {f0});
    for (int deg = 0; deg <= 180; deg += 15)
    {
        cv::Mat rotated;
        cv::warpAffine(
            img, rotated, cv::getRotationMatrix2D(cv::Point2f(c), deg, 1.0), img.size(),
            cv::INTER_CUBIC, cv::BORDER_REFLECT);
        const Feature f1 = orientedFeature(rotated, c.x, c.y);
        // getRotationMatrix2D turns counter-clockwise on screen (y down):
        // image angles decrease by deg.
        const double expected = f0.gradient_angle - deg * M_PI / 180.0;
        EXPECT_NEAR(std::remainder(f1.gradient_angle - expected, 2 * M_PI), 0.0, 0.1)
            << deg << " deg";
        const auto d1 = ex.compute(rotated, {f1});
        EXPECT_GT(std::abs(dot(d0, 0, d1, 0)), 0.9f) << deg << " deg";
        if (deg == 90)
        {
            // Control: without re-orienting, the same patches do not match.
            Feature f1_unoriented = f1;
            f1_unoriented.gradient_angle = f0.gradient_angle;
            const auto d1u = ex.compute(rotated, {f1_unoriented});
            EXPECT_LT(std::abs(dot(d0, 0, d1u, 0)), 0.5f);
        }
    }
}

TEST(LogPolarDescriptor, linearIlluminationChangeKeepsAbsoluteCorrelationOne)
{
    // Grey levels in [40, 100]: a*I+b below stays inside [0, 255] exactly.
    const cv::Mat img = smoothTexture(80, 80, 7, 2.0, 40, 100);
    FeatureList feats;
    for (int v = 15; v <= 65; v += 10)
    {
        for (int u = 15; u <= 65; u += 10)
        {
            feats.push_back(orientedFeature(img, u, v));
        }
    }
    const LogPolarDescriptorExtractor ex;
    const auto d0 = ex.compute(img, feats);
    for (const auto& [a, b] :
         std::vector<std::pair<int, int>>{{2, 10}, {1, 100}, {-1, 250}, {-2, 250}})
    {
        cv::Mat changed;
        img.convertTo(changed, CV_8U, a, b);
        FeatureList feats1 = feats;
        if (a > 0)
        {
            // a > 0 keeps the gradient direction: re-orient from the new image.
            for (auto& f : feats1)
            {
                f = orientedFeature(changed, f.u, f.v);
            }
        }
        // (a < 0 flips the gradient by pi; Pearson's rho is checked on the
        // same sampling grid, where it must be exactly -1.)
        const auto d1 = ex.compute(changed, feats1);
        for (std::size_t i = 0; i < feats.size(); ++i)
        {
            const float rho = dot(d0, i, d1, i);
            EXPECT_NEAR(rho, a > 0 ? 1.0f : -1.0f, 1e-4f) << "a=" << a << " b=" << b;
        }
    }
}

TEST(LogPolarDescriptor, flatPatchAndImageBorderGiveZeroRows)
{
    cv::Mat img = smoothTexture(60, 60, 3, 2.0, 30, 220);
    img(cv::Rect(0, 0, 30, 30)).setTo(77);
    Feature flat;
    flat.u = 14;
    flat.v = 14;
    flat.gradient_angle = 0.7f;
    Feature border = orientedFeature(img, 55, 40);  // radius 8 leaves the image
    Feature ok = orientedFeature(img, 45, 45);
    const auto d = LogPolarDescriptorExtractor().compute(img, {flat, border, ok});
    ASSERT_EQ(d.size(), 3U);
    EXPECT_EQ(norm(d, 0), 0.0f);
    EXPECT_EQ(norm(d, 1), 0.0f);
    EXPECT_NEAR(norm(d, 2), 1.0f, 1e-5f);
}

TEST(LogPolarDescriptor, emptyFeatureListAndBadParameters)
{
    const cv::Mat img(20, 20, CV_8UC1, cv::Scalar(0));
    const auto d = LogPolarDescriptorExtractor().compute(img, {});
    EXPECT_EQ(d.size(), 0U);
    LogPolarDescriptorExtractor::TParameters p;
    p.min_radius = 0;
    EXPECT_ANY_THROW(LogPolarDescriptorExtractor(p).compute(img, {}));
    p = {};
    p.radius = 0.5f;  // below min_radius
    EXPECT_ANY_THROW(LogPolarDescriptorExtractor(p).compute(img, {}));
}
