// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/Feature.h>
#include <emslam/stereo/StereoFrame.h>

namespace emslam::egomotion
{
/** Stage 1 of §2.1: the reduced observation. Keeps the pixels whose |grad I|
 * is a *strict* local maximum within a `window_size` x `window_size` window
 * (no plateau pixel survives) and that have a valid stereo 3D point.
 * \ingroup emslam_egomotion_grp */
class GlmFeatureExtractor
{
public:
    struct TParameters
    {
        /** Side |W| of the non-maximum window [px]; the paper uses 8. */
        int window_size{8};
        /** Gradient magnitudes below this are never features (Sobel units, 0: off). */
        float min_gradient{0.0f};
    };

    GlmFeatureExtractor() = default;
    explicit GlmFeatureExtractor(const TParameters& p) : m_params(p) {}
    const TParameters& parameters() const { return m_params; }

    /** Features of `frame` (its `intensity`, `valid`, points/pixels). */
    FeatureList extract(const emslam::stereo::StereoFrame& frame) const;

private:
    TParameters m_params;
};

}  // namespace emslam::egomotion
