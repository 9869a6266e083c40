// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/sim/World.h>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/img/TStereoCamera.h>
#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <opencv2/core.hpp>

namespace emslam::sim
{
/** Exact pinhole stereo renderer: ray casting of a World's planes, boxes and
 * height field with bilinear texture sampling, optional n x n supersampling,
 * exposure gain and Gaussian photometric noise. Both cameras share the
 * intrinsics; the right camera sits `baseline` metres along the left camera's
 * +x axis (a rectified pair, no distortion). Pixel centres are at integer
 * coordinates (OpenCV convention).
 *
 * \code
 * [Camera]
 * width = 320           ; [px]
 * height = 240          ; [px]
 * focal_px = 200        ; [px] fx = fy
 * cx = -1               ; [px] principal point; < 0: (width - 1) / 2
 * cy = -1               ; [px] < 0: (height - 1) / 2
 * baseline = 0.10       ; [m] > 0
 * supersampling = 1     ; n x n rays per pixel (1..4)
 * noise_sigma = 1.0     ; [grey levels] Gaussian photometric noise
 * max_range = 60        ; [m] nothing is seen farther
 * \endcode
 * \ingroup emslam_sim_grp \sa World, StereoSimulator */
class StereoRenderer
{
public:
    /** [Camera] parameters. */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws std::invalid_argument naming the [Camera] key of a bad value. */
        void validate() const;

        int width{320};           //!< [px] (Default: 320)
        int height{240};          //!< [px] (Default: 240)
        double focal_px{200.0};   //!< [px] (Default: 200)
        double cx{-1.0};          //!< [px]; < 0: image centre (Default: -1)
        double cy{-1.0};          //!< [px]; < 0: image centre (Default: -1)
        double baseline{0.10};    //!< [m] (Default: 0.10)
        int supersampling{1};     //!< rays per pixel per axis, 1..4 (Default: 1)
        double noise_sigma{1.0};  //!< [grey levels] (Default: 1.0)
        double max_range{60.0};   //!< [m] (Default: 60)
    };

    /** One rendered stereo pair. */
    struct Output
    {
        cv::Mat left;   //!< CV_8UC1
        cv::Mat right;  //!< CV_8UC1
        /** Left-camera depth (z) at each pixel centre [m], CV_32FC1, 0 where
         * nothing is hit; empty unless requested. */
        cv::Mat depth;
    };

    StereoRenderer() = default;
    /** A renderer with the camera `p` (validated). */
    explicit StereoRenderer(const TParameters& p) { setParameters(p); }

    /** Sets (and validates) the camera. */
    void setParameters(const TParameters& p);
    /** The camera it renders with. */
    const TParameters& params() const { return m_p; }

    /** The calibration of the rendered pair (rectified, no distortion;
     * rightCameraPose = baseline along +x). */
    mrpt::img::TStereoCamera stereoCamera() const;

    /** Renders the pair seen from `T_scene_left` at time `t` [s] (moving
     * elements), with exposure `gain` and noise seeded by `noise_seed`.
     * Deterministic: same inputs, same bytes. */
    Output render(
        const World& world,
        const mrpt::poses::CPose3D& T_scene_left,
        double t,
        double gain,
        std::uint64_t noise_seed,
        bool want_depth = false) const;

    /** Renders one noise-free view as float intensities (CV_32FC1) and,
     * optionally, the exact depth of each pixel centre. */
    void renderView(
        const World& world,
        const mrpt::poses::CPose3D& T_scene_cam,
        double t,
        cv::Mat& intensity,
        cv::Mat* depth) const;

private:
    TParameters m_p;
};

}  // namespace emslam::sim
