// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/stereo/StereoFrame.h>
#include <emslam/stereo/StereoMatcher.h>

#include <mrpt/img/TStereoCamera.h>

#include <opencv2/core.hpp>
#include <vector>

namespace emslam::stereo
{
/** Disparity at chosen pixels only (the egomotion's features), at full
 * resolution: a search along the row of the right image of a **rectified**
 * pair, instead of a dense disparity image.
 *
 * Both images are first filtered as OpenCV's SGBM does (horizontal Sobel,
 * clipped to ±31), which makes the costs blind to a brightness offset between
 * the cameras. For each pixel the cost of a disparity d is the sum of absolute
 * differences over a `block_size` square; the best d must beat every d more
 * than 1 px away by `uniqueness_ratio` %, must not lie at an end of the
 * searched range (the true minimum may be beyond it), must survive the
 * left-right check (the right pixel's own best match lies within
 * `lr_max_diff` of the left pixel). Its sub-pixel value starts from a
 * parabola through the three costs around the best and is then refined by
 * Gauss-Newton on the zero-mean squared differences of the raw intensities
 * (the right image linearly interpolated), which removes the pull of a cost
 * fit towards whole pixels: on the KITTI 06 excerpt drift 0.94 -> 0.87 %,
 * exact disparities on synthetic planes. A point is kept if its depth lies
 * in [min_range, max_range].
 *
 * Parameters come from `[StereoMatcher]` (fromStereo()): the search range is that
 * of the dense matcher at `image_scale`, brought to full resolution, so both
 * see the same depths.
 * \ingroup emslam_stereo_grp \sa StereoMatcher, StereoFrontEnd */
class SparseStereoMatcher
{
public:
    /** Options of the row search (the `[StereoMatcher]` keys they come from: fromStereo()). */
    struct TParameters
    {
        /** Disparities searched at full resolution [px], >= 3. (Default: 128) */
        int num_disparities{128};
        /** Smallest disparity searched [px]. (Default: 0) */
        int min_disparity{0};
        /** Side of the SAD window [px], odd, in [3, 15]. (Default: 9) */
        int block_size{9};
        /** Uniqueness margin [%], in [0, 100). (Default: 10) */
        int uniqueness_ratio{10};
        /** Left-right tolerance [px]; negative: no check. (Default: 1) */
        int lr_max_diff{1};
        /** Depth window of the points kept [m]. (Default: 0.3, 12) */
        ///@{
        double min_range{0.3}, max_range{12.0};
        ///@}
        /** Sub-pixel disparities (parabola, then Gauss-Newton); false: the
         * best whole pixel, as a correlation stereo head without
         * interpolation gives. (Default: true) */
        bool subpixel{true};

        /** Throws std::invalid_argument naming the `[StereoMatcher]` key of a bad value. */
        void validate() const;
    };

    /** The sparse parameters of a dense configuration: the disparity range
     * divided by its `image_scale`, `sparse_block_size`, and the same
     * uniqueness, left-right and depth limits. */
    static TParameters fromStereo(const StereoMatcher::TParameters& p);

    SparseStereoMatcher() = default;
    /** A matcher with the options `p` (validated). */
    explicit SparseStereoMatcher(const TParameters& p);
    /** The options it runs with. */
    const TParameters& parameters() const { return m_params; }

    /** The frame of `left_gray` (8-bit, 1 channel, rectified, the size of
     * `camera`) with a 3D point at each of `pixels` whose disparity passes
     * every test, in the order of `pixels`. `disparity` stays empty; `valid`
     * marks the points. Throws on empty or mismatched images. */
    StereoFrame compute(
        const cv::Mat& left_gray,
        const cv::Mat& right_gray,
        const mrpt::img::TStereoCamera& camera,
        const std::vector<PixelCoord>& pixels) const;

    /** Disparity at (u, v) of two prefiltered images (see prefilter()),
     * with the parabola's sub-pixel value, or a negative value if a test
     * rejects it. */
    double disparityAt(
        const cv::Mat& left_filtered, const cv::Mat& right_filtered, int u, int v) const;

    /** SGBM's prefilter: horizontal Sobel clipped to [-31, 31], plus 31 (CV_8UC1). */
    static cv::Mat prefilter(const cv::Mat& gray);

private:
    TParameters m_params;
};

}  // namespace emslam::stereo
