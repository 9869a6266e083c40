// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/stereo/StereoFrame.h>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/img/TStereoCamera.h>

#include <memory>
#include <opencv2/core.hpp>
#include <string>

namespace emslam::stereo
{
/** Dense disparity of a **rectified** stereo pair, filtered to a semi-dense
 * set of trustworthy pixels, and its reconstruction into a StereoFrame.
 *
 * Runs OpenCV's StereoSGBM (or StereoBM) at `image_scale` of the input size,
 * then keeps a pixel only if it passes the uniqueness test, is not part of a
 * small speckle, agrees with the right-to-left disparity within
 * `lr_max_diff`, and reconstructs within [min_range, max_range].
 *
 * INI section (default `[StereoMatcher]`), every key optional:
 * \code
 * [StereoMatcher]
 * algorithm          = sgbm_hh ; sgbm_hh | sgbm | sgbm_3way | bm
 * image_scale        = 1.0    ; resize factor applied before matching (0.5: 640x480 -> 320x240)
 * num_disparities    = 64     ; [px] search range at working scale, 1..1024 (rounded up to 16)
 * min_disparity      = 0      ; [px], -1000..1000
 * block_size         = 5      ; matching window side [px], odd, 1..255 (bm: 5..255)
 * uniqueness_ratio   = 10     ; [%] best cost must beat the second best by this margin
 * speckle_window_size = 100   ; [px] connected blobs smaller than this are removed (0: off)
 * speckle_range      = 2      ; [px] max disparity step inside one blob
 * lr_max_diff        = 1      ; [px] left-right consistency tolerance (<0: off), <= 1024
 * texture_threshold  = 10     ; BM only: minimum local texture
 * pre_filter_cap     = 31     ; clip of the prefiltered image
 * p1_per_pixel       = 8      ; SGBM: P1 = p1_per_pixel * block_size^2, 0..10000
 * p2_per_pixel       = 32     ; SGBM: P2 = p2_per_pixel * block_size^2, > p1, <= 10000
 * min_range          = 0.3    ; [m] closer points are dropped
 * max_range          = 12.0   ; [m] farther points are dropped (paper: 12 m)
 * sparse_at_features = true   ; egomotion points by a row search at its features (full size)
 * sparse_block_size  = 9      ; that search's SAD window [px], odd, 3..15
 * subpixel           = true   ; false: whole-pixel disparities (both matchers)
 * \endcode
 * With `sparse_at_features`, StereoFrontEnd gives the egomotion the points of
 * SparseStereoMatcher at its features, at full resolution, and computes this
 * dense cloud (at `image_scale`) only for the frames the map takes.
 * \ingroup emslam_stereo_grp */
class StereoMatcher
{
public:
    /** `[StereoMatcher]` parameters: the keys of the INI block above. */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws std::exception with a message naming the key when a value is out of range. */
        void validate() const;

        /** "sgbm_hh" (SGBM with all 8 aggregation paths, OpenCV MODE_HH),
         * "sgbm" (single pass, 5 paths all coming from the rows above),
         * "sgbm_3way" or "bm". The single-pass variants bias the disparity
         * of surfaces slanted down the image (floors: -0.3 px at 320x240),
         * sgbm_hh does not; it costs 1.4x (320x240) to 2.4x (KITTI) the
         * time of sgbm and keeps a W x H x num_disparities cost volume
         * (~20 MB at 320x240 x 64, ~200 MB at 1241x376 x 128).
         * (Default: sgbm_hh) */
        std::string algorithm{"sgbm_hh"};
        /** Resize factor before matching, (0, 1]. (Default: 1.0) */
        double image_scale{1.0};
        /** Disparity range at the working scale [px], rounded up to a multiple of 16. (Default: 64)
         */
        int num_disparities{64};
        /** Smallest disparity searched [px]. (Default: 0) */
        int min_disparity{0};
        /** Matching window side [px], odd, >= 1 (>= 5 for BM). (Default: 5) */
        int block_size{5};
        /** Uniqueness margin [%]. (Default: 10) */
        int uniqueness_ratio{10};
        /** Speckle filter: maximum blob size to remove [px]; 0 disables. (Default: 100) */
        int speckle_window_size{100};
        /** Speckle filter: max disparity variation within a blob [px]. (Default: 2) */
        int speckle_range{2};
        /** Left-right consistency tolerance [px]; negative disables. (Default: 1) */
        int lr_max_diff{1};
        /** BM only: texture threshold. (Default: 10) */
        int texture_threshold{10};
        /** Prefilter clip value. (Default: 31) */
        int pre_filter_cap{31};
        /** SGBM penalty for a 1 px disparity change between neighbours, per
         * pixel of the block (P1 = p1_per_pixel * block_size^2). (Default: 8) */
        int p1_per_pixel{8};
        /** SGBM penalty for larger disparity jumps, per pixel of the block
         * (P2 = p2_per_pixel * block_size^2, must exceed p1). (Default: 32) */
        int p2_per_pixel{32};
        /** Minimum depth kept [m]. (Default: 0.3) */
        double min_range{0.3};
        /** Maximum depth kept [m]; the paper uses 12 m. (Default: 12.0) */
        double max_range{12.0};
        /** The egomotion's points come from SparseStereoMatcher at its
         * features, at full resolution; the dense cloud only for the frames
         * the map takes (StereoFrontEnd). Not in the paper (false): the
         * shipped tuning, 165 -> 34 ms per KITTI frame. (Default: true) */
        bool sparse_at_features{true};
        /** SparseStereoMatcher's SAD window side [px], odd, in [3, 15]. (Default: 9) */
        int sparse_block_size{9};
        /** Sub-pixel disparities; false rounds both matchers' disparities to
         * whole pixels, as the paper's Digiclops head gave them without
         * interpolation: depth steps of z^2 / (f b) (the paper's regime,
         * config/experiments/paper-regime.ini). (Default: true) */
        bool subpixel{true};
    };

    StereoMatcher();
    /** A matcher with the parameters `p` (validated). */
    explicit StereoMatcher(const TParameters& p);
    ~StereoMatcher();
    /** Moves the matcher and its OpenCV state. */
    StereoMatcher(StereoMatcher&&) noexcept;
    /** Moves the matcher and its OpenCV state. */
    StereoMatcher& operator=(StereoMatcher&&) noexcept;

    /** The parameters it runs with. */
    const TParameters& parameters() const { return m_params; }
    /** Validates and applies new parameters. */
    void setParameters(const TParameters& p);

    /** Computes the semi-dense frame of a rectified pair (8-bit gray or BGR,
     * same size). `camera` is the rectified calibration of the inputs at their
     * full size; the frame carries it scaled by `image_scale`.
     * Throws on empty or mismatched images or an unusable calibration.
     * Thread-safe: concurrent calls take turns on the OpenCV matcher, whose
     * buffers are shared between calls. */
    StereoFrame compute(
        const cv::Mat& left, const cv::Mat& right, const mrpt::img::TStereoCamera& camera) const;

    /** Disparity [px] of a rectified pair at the working scale, CV_32F, with
     * every filter applied; invalid pixels are 0. Inputs as in compute();
     * thread-safe as it. */
    cv::Mat computeDisparity(const cv::Mat& left_gray, const cv::Mat& right_gray) const;

private:
    TParameters m_params;
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace emslam::stereo
