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
    std::size_t size() const { return dim > 0 ? data.size() / dim : 0; }
    const float* row(std::size_t i) const { return data.data() + i * dim; }
};

/** Stage 2a of §2.1: the log-polar transform of the window around each
 * feature, rotated so that the feature's gradient points along the image's
 * +x axis (a cyclic shift of the angle axis in log-polar space).
 * \ingroup emslam_egomotion_grp */
class LogPolarDescriptorExtractor
{
public:
    struct TParameters
    {
        int num_rings{8};        //!< samples along log(radius)
        int num_angles{16};      //!< samples along the angle
        float radius{8.0f};      //!< outer radius of the window [px]
        float min_radius{1.0f};  //!< inner radius [px]
    };

    LogPolarDescriptorExtractor() = default;
    explicit LogPolarDescriptorExtractor(const TParameters& p) : m_params(p) {}
    const TParameters& parameters() const { return m_params; }

    /** `image` is the 8-bit reference image the features come from. */
    Descriptors compute(const cv::Mat& image, const FeatureList& features) const;

private:
    TParameters m_params;
};

}  // namespace emslam::egomotion
