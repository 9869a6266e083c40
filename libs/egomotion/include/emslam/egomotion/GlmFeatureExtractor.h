// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/Feature.h>
#include <emslam/stereo/StereoFrame.h>

#include <memory>

namespace emslam::egomotion
{
/** Stage 1 of §2.1: the reduced observation. Keeps the pixels whose |grad I|
 * is a *strict* local maximum within a `window_size` x `window_size` window
 * (no plateau pixel survives) and that have a valid stereo 3D point.
 *
 * Details: |grad I| is the 3x3 Sobel magnitude of `intensity`. The window of
 * pixel (u, v) spans offsets -W/2 .. W-1-W/2 (integer division) on each axis:
 * centred for odd W, one pixel more towards -u/-v for even W; it is clipped
 * at the image border. A feature must be strictly greater than every other
 * pixel of its window, > 0 and >= `min_gradient`, lie off the outermost
 * 1-pixel border (where Sobel sees a mirrored image) and be valid in
 * `frame.valid`. Features come in the order of `frame.points`.
 * \ingroup emslam_egomotion_grp \sa LogPolarDescriptorExtractor */
class GlmFeatureExtractor
{
public:
    /** Options of the feature search. */
    struct TParameters
    {
        /** Side |W| of the non-maximum window [px]; the paper uses 8. */
        int window_size{8};
        /** Gradient magnitudes below this are never features (Sobel units, 0: off). */
        float min_gradient{0.0f};
    };

    GlmFeatureExtractor() = default;
    /** An extractor with the options `p`. */
    explicit GlmFeatureExtractor(const TParameters& p) : m_params(p) {}
    /** The options it runs with. */
    const TParameters& parameters() const { return m_params; }

    /** Features of `frame` (its `intensity`, `valid`, points/pixels).
     * Throws if window_size < 1, min_gradient < 0, `intensity` is not
     * CV_8UC1, or `valid`/`pixels` disagree in size with the image/points. */
    FeatureList extract(const emslam::stereo::StereoFrame& frame) const;

    /** The gradient maps of one image (Sobel, |grad I|^2, its window maximum)
     * that both locate() and extract() read: with a sparse front-end they see
     * the same image, and computing the maps once saves ~1 ms per KITTI frame. */
    class Gradients;

    /** extract(), reading `gradients` when they are those of
     * `frame.intensity` (same pixels, window and gradient floor; checked) and
     * computing them otherwise: the result is extract(frame)'s either way. */
    FeatureList extract(const emslam::stereo::StereoFrame& frame, const Gradients* gradients) const;

    /** Every pixel of `intensity` (CV_8UC1) that passes the feature tests
     * other than having a 3D point, in raster order: where a sparse stereo
     * front-end must find points (StereoFrontEnd::setPixelSelector). extract()
     * of a frame with points at these pixels gives back the same pixels. */
    std::vector<emslam::stereo::PixelCoord> locate(const cv::Mat& intensity) const;

    /** locate(), also handing out the gradient maps it computed (with a
     * copy of `intensity`, to tell later whether an image is the same). */
    std::vector<emslam::stereo::PixelCoord> locate(
        const cv::Mat& intensity, std::shared_ptr<const Gradients>& gradients) const;

private:
    TParameters m_params;
};

}  // namespace emslam::egomotion
