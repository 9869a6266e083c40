// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/Feature.h>

#include <opencv2/core.hpp>
#include <vector>

namespace emslam::egomotion
{
/** Log-polar descriptors of a feature list, one row per feature, already
 * zero-mean and unit-norm so that Pearson's rho of two descriptors is their
 * dot product. A row of a feature whose window is flat (or leaves the image)
 * is all zeros: it matches nothing.
 * \ingroup emslam_egomotion_grp */
struct Descriptors
{
    int dim{0};               //!< values per descriptor (rings x angles)
    std::vector<float> data;  //!< row-major, size() x dim
    /** Number of descriptors (rows). */
    std::size_t size() const { return dim > 0 ? data.size() / dim : 0; }
    /** The `i`-th descriptor, `dim` values. */
    const float* row(std::size_t i) const { return data.data() + i * dim; }
};

/** Stage 2a of §2.1: the log-polar transform of the window around each
 * feature, rotated so that the feature's gradient points along the image's
 * +x axis (a cyclic shift of the angle axis in log-polar space).
 *
 * Sample (k, j), stored at k * num_angles + j, is the bilinear interpolation
 * of the image at radius r_k = min_radius * (radius/min_radius)^(k/(num_rings-1))
 * and angle gradient_angle + 2 pi j / num_angles around the feature pixel:
 * the grid turns by the exact gradient angle (a continuous, not a
 * whole-sample, shift). A feature whose disc of `radius` leaves the image, or
 * whose samples are flat (RMS < 1e-3 grey levels), gets a zero row.
 * \ingroup emslam_egomotion_grp \sa GlmFeatureExtractor, matchMutual */
class LogPolarDescriptorExtractor
{
public:
    /** Shape of the log-polar window. */
    struct TParameters
    {
        int num_rings{8};        //!< samples along log(radius)
        int num_angles{16};      //!< samples along the angle
        float radius{8.0f};      //!< outer radius of the window [px]
        float min_radius{1.0f};  //!< inner radius [px]
    };

    LogPolarDescriptorExtractor() = default;
    /** An extractor with the options `p`. */
    explicit LogPolarDescriptorExtractor(const TParameters& p) : m_params(p) {}
    /** The options it runs with. */
    const TParameters& parameters() const { return m_params; }

    /** `image` is the 8-bit reference image the features come from; one row
     * per feature, in order. Throws on invalid parameters or a non-CV_8UC1 image. */
    Descriptors compute(const cv::Mat& image, const FeatureList& features) const;

private:
    TParameters m_params;
};

}  // namespace emslam::egomotion
