// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/DppPoseEstimator.h>
#include <emslam/egomotion/Feature.h>
#include <emslam/egomotion/GlmFeatureExtractor.h>
#include <emslam/egomotion/LogPolarDescriptor.h>
#include <emslam/stereo/StereoFrame.h>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose3D.h>

#include <memory>
#include <string>

namespace emslam::egomotion
{
/** What one egomotion step found. \ingroup emslam_egomotion_grp */
struct EgomotionResult
{
    using Ptr = std::shared_ptr<EgomotionResult>;

    /** Pose of the current camera in the previous camera frame (the action). */
    mrpt::poses::CPose3D T_prev_cur;
    /** False when the step is not trustworthy (too few matches after LWO, or
     * no features); T_prev_cur is then identity and must not be used. */
    bool ok{false};
    std::string failure_reason;  //!< empty when ok

    std::size_t features_prev{0}, features_cur{0};
    std::size_t initial_matches{0};  //!< after mutual consistency
    std::size_t final_matches{0};    //!< after LWO
    int lwo_iterations{0};
    double energy{0};  //!< final sum of Dpp

    // Time per stage [ms]
    double ms_features{0}, ms_descriptors{0}, ms_matching{0}, ms_lwo{0}, ms_pose{0}, ms_total{0};
};

/** The four stages of §2.1 between two StereoFrames, plus failure detection.
 * Frames are given in sequence with process(); features and descriptors of
 * the previous frame are kept, so each frame is described once.
 *
 * INI section `[Egomotion]`:
 * \code
 * [Egomotion]
 * window_size       = 8      ; |W|, GLM non-maximum window [px]
 * min_gradient      = 0      ; gradient magnitude floor for features
 * similarity_min    = 0.8    ; S_min
 * lwo_sigma_min     = 0.005  ; sigma_min
 * min_final_matches = 12     ; fewer matches after LWO -> the step failed
 * lp_num_rings      = 8      ; log-polar descriptor
 * lp_num_angles     = 16
 * lp_radius         = 8
 * euclidean_init    = true   ; closed-form start before the Dpp conjugate gradient
 * \endcode
 * \ingroup emslam_egomotion_grp */
class EgomotionEstimator
{
public:
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;

        int window_size{8};
        double min_gradient{0};
        double similarity_min{0.8};
        double lwo_sigma_min{0.005};
        int min_final_matches{12};
        int lp_num_rings{8};
        int lp_num_angles{16};
        double lp_radius{8};
        bool euclidean_init{true};
    };

    EgomotionEstimator() = default;
    explicit EgomotionEstimator(const TParameters& p);
    const TParameters& parameters() const { return m_params; }

    /** Estimates the action between the two frames (stateless). */
    EgomotionResult estimate(
        const emslam::stereo::StereoFrame& prev, const emslam::stereo::StereoFrame& cur) const;

    /** Sequential use: the action from the previously processed frame to
     * `cur`. The first call returns ok=false with reason "first frame". */
    EgomotionResult process(const emslam::stereo::StereoFrame& cur);

    /** Forget the previous frame (e.g. after a failure, to restart). */
    void reset();

private:
    struct Described;
    Described describe(const emslam::stereo::StereoFrame& f) const;
    EgomotionResult estimateDescribed(const Described& prev, const Described& cur) const;

    TParameters m_params;
    std::shared_ptr<const Described> m_prev;
};

}  // namespace emslam::egomotion
