// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/DppPoseEstimator.h>
#include <emslam/egomotion/Feature.h>
#include <emslam/egomotion/FeatureMatcher.h>
#include <emslam/egomotion/GlmFeatureExtractor.h>
#include <emslam/egomotion/LogPolarDescriptor.h>
#include <emslam/stereo/StereoFrame.h>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace emslam::egomotion
{
/** What one egomotion step found. \ingroup emslam_egomotion_grp */
struct EgomotionResult
{
    /** Shared pointer to a result. */
    using Ptr = std::shared_ptr<EgomotionResult>;

    /** Pose of the current camera in the previous camera frame (the action). */
    mrpt::poses::CPose3D T_prev_cur;
    /** False when the step is not trustworthy (too few matches after LWO, or
     * no features); T_prev_cur is then identity and must not be used. */
    bool ok{false};
    std::string failure_reason;  //!< empty when ok

    /** Features found in the previous and the current frame. */
    ///@{
    std::size_t features_prev{0}, features_cur{0};
    ///@}
    std::size_t initial_matches{0};  //!< after mutual consistency
    std::size_t final_matches{0};    //!< after LWO
    int lwo_iterations{0};           //!< LWO rounds run
    double energy{0};                //!< final sum of Dpp
    /** Covariance of T_prev_cur (DppPoseEstimator::Result::covariance);
     * valid only if has_covariance. */
    mrpt::math::CMatrixDouble66 covariance;
    bool has_covariance{false};  //!< false: `covariance` is not valid

    /** Matched near the constant-velocity prediction (guided_matching), and
     * that was enough; guided_fallback: it was not, and the full search gave
     * this result. */
    ///@{
    bool guided{false}, guided_fallback{false};
    ///@}
    /** Too few distinct matches (experimental_match_distinctiveness): this result is the
     * paper's matching's. */
    bool distinct_fallback{false};

    /** Time per stage [ms]: features, descriptors, matching, LWO, pose, all. */
    ///@{
    double ms_features{0}, ms_descriptors{0}, ms_matching{0}, ms_lwo{0}, ms_pose{0}, ms_total{0};
    ///@}
};

/** Var(x) / Var(x | |x| < c) for a Gaussian x, with c such that
 * P(|x| < c) = q: how much the spread of the central fraction q of a
 * Gaussian sample underestimates its variance. 1 at q = 1; about 1.9 / q²
 * for small q. Throws unless 0 < q <= 1. \ingroup emslam_egomotion_grp */
double lwoTruncationVarianceFactor(double q);

/** The four stages of §2.1 between two StereoFrames, plus failure detection.
 * Frames are given in sequence with process(); features and descriptors of
 * the previous frame are kept, so each frame is described once.
 *
 * INI section `[EgomotionEstimator]`:
 * \code
 * [EgomotionEstimator]
 * window_size       = 8      ; |W|, GLM non-maximum window [px], 3..128
 * min_gradient      = 0      ; gradient magnitude floor for features
 * similarity_min    = 0.8    ; S_min
 * lwo_sigma_min     = 0.005  ; sigma_min
 * min_final_matches = 12     ; fewer matches after LWO -> the step failed
 * lp_num_rings      = 8      ; log-polar descriptor, 2..64
 * lp_num_angles     = 16     ; 4..256
 * lp_radius         = 8      ; [px], (1, 256]
 * euclidean_init    = true   ; closed-form start before the Dpp conjugate gradient
 * joint_refinement  = false  ; Levenberg-Marquardt on all six parameters after it
 * reprojection_refinement = false ; then polish by the stereo reprojection error
 * max_lwo_matches   = 2000   ; most similar matches kept for LWO (O(M^2) memory/time)
 * guided_matching   = false  ; match near the constant-velocity prediction first
 * guided_radius     = 0.1    ; its search radius, fraction of the image width, (0, 1]
 * experimental_covariance_lwo_truncation = false ; widen the covariance for what LWO cut off
 * experimental_match_distinctiveness = 1 ; runner-up's Pearson distance / the best's, at least (1:
 * off) \endcode Guided matching (not in the paper; process() only): the last step's motion predicts
 * where each previous feature appears, and only current features within guided_radius of that are
 * compared, which costs O(N k) instead of O(N^2) and keeps far look-alikes out. If that step fails
 * (a stop, a sudden turn), the paper's full search runs on the same frames. Distinctiveness (not in
 * the paper; every matching, loop registrations too): with experimental_match_distinctiveness > 1 a
 * mutual best is kept only if it stands clear of the best candidate elsewhere in the image
 * (emslam::egomotion::Distinctiveness, candidates beyond lp_radius of it):
 * on a periodic texture the look-alikes a period away are refused instead
 * of left to the noise. A sequential step (process(), and estimate() of two
 * frames) that then has too few matches is matched again the paper's way,
 * so no step is lost to it; a registration of two descriptions (a loop) is
 * not: it fails instead.
 * \ingroup emslam_egomotion_grp */
class EgomotionEstimator
{
public:
    /** `[EgomotionEstimator]` parameters (the INI section of this estimator). */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;

        /** Throws std::exception naming the key when a value is out of range. */
        void validate() const;

        /** Side |W| of the GLM non-maximum window [px], >= 3. (Default: 8) */
        int window_size{8};
        /** Gradient magnitude floor for features (Sobel units), >= 0. (Default: 0) */
        double min_gradient{0};
        /** S_min, the appearance similarity threshold, in (0, 1]. (Default: 0.8) */
        double similarity_min{0.8};
        /** sigma_min, LWO stops when the std. dev. of the D_i is below it, > 0. (Default: 0.005) */
        double lwo_sigma_min{0.005};
        /** A step with fewer matches after LWO failed, >= 3. (Default: 12) */
        int min_final_matches{12};
        /** Log-polar descriptor rings, >= 2. (Default: 8) */
        int lp_num_rings{8};
        /** Log-polar descriptor angles, >= 4. (Default: 16) */
        int lp_num_angles{16};
        /** Log-polar window radius [px], > 1. (Default: 8) */
        double lp_radius{8};
        /** Closed-form Euclidean start of the Dpp minimisation. (Default: true) */
        bool euclidean_init{true};
        /** Joint Levenberg-Marquardt polish of the Dpp minimum after the
         * paper's alternating conjugate gradient
         * (DppPoseEstimator::TParameters::joint_refinement). (Default: false) */
        bool joint_refinement{false};
        /** Polish the pose by the stereo reprojection error in both frames
         * (StereoReprojectionRefinement), after the Dpp minimisation; the
         * covariance is the Dpp's at the polished pose. Not in the paper; a
         * stereo pair only (no effect with a zero baseline). (Default: false) */
        bool reprojection_refinement{false};
        /** Upper bound on the matches given to LWO (the most similar are kept),
         * bounding its O(M^2) matrix; >= min_final_matches. (Default: 2000) */
        int max_lwo_matches{2000};
        /** Guided matching first (see above). (Default: false, the paper's full search) */
        bool guided_matching{false};
        /** Guided search radius as a fraction of the image width, in (0, 1]. (Default: 0.1) */
        double guided_radius{0.1};
        /** The pose covariance's residual scale comes from the matches LWO
         * kept, the best fraction q of them: read as a Gaussian truncated to
         * its central q, it is multiplied by lwoTruncationVarianceFactor(q).
         * Experimental: on KITTI 06 it puts the prior's minimum near the
         * truth (0.54 -> 0.07 nats there), but the one-grid search then
         * drifts (pseudo-loop end error 0.22-0.33 -> 0.47-1.49 m;
         * doc/notes/2026-12-02-lwo-truncation-coarse-levels-validation.md).
         * (Default: false: the kept residuals as they are) */
        bool experimental_covariance_lwo_truncation{false};
        /** Distinctiveness::ratio: a match's runner-up elsewhere in the
         * image (beyond lp_radius of it) must have at least this times its
         * Pearson distance 1 - S, in [1, 100]. Experimental: with 2 the
         * periodic world's egomotion barely changed (lookalike_periodic seed
         * 62: ATE 0.86 -> 0.85 m) and the hall's end error grew 0.14 -> 0.37 m
         * (doc/apps/emslam-odometry.md, "Distinctiveness").
         * (Default: 1, off: the paper) */
        double experimental_match_distinctiveness{1};
    };

    EgomotionEstimator() = default;
    /** An estimator with the parameters `p`. */
    explicit EgomotionEstimator(const TParameters& p);
    /** The parameters it runs with. */
    const TParameters& parameters() const { return m_params; }

    /** Estimates the action between the two frames (stateless). */
    EgomotionResult estimate(
        const emslam::stereo::StereoFrame& prev, const emslam::stereo::StereoFrame& cur) const;

    /** Sequential use: the action from the previously processed frame to
     * `cur`. The first call returns ok=false with reason "first frame". */
    EgomotionResult process(const emslam::stereo::StereoFrame& cur);

    /** The pixels of a rectified 8-bit image that would be features if they
     * had a 3D point (GlmFeatureExtractor::locate with these parameters):
     * the pixel selector of a sparse StereoFrontEnd. The gradient maps are
     * kept until the next describe (process(), estimate()) reads them again
     * for the same image: not to be called from two threads at once. */
    std::vector<emslam::stereo::PixelCoord> locateFeatures(const cv::Mat& intensity) const;

    /** Forget the previous frame (e.g. after a failure, to restart). */
    void reset();

    /** A frame's features, their 3D points and descriptors, as process()
     * computed them: what registering the frame again needs, without its
     * images or its cloud. */
    struct Described;
    /** Shared, immutable handle to a Described frame. */
    using Description = std::shared_ptr<const Described>;
    /** The description of the frame the last process() call took (null
     * before the first): keep it to register that frame again later. */
    Description lastDescription() const { return m_prev; }
    /** The motion between two described frames, by the same stages as
     * process() (matching, LWO, Dpp and the optional refinements) but with no
     * prediction and no fallback from distinct matching: e.g. a place seen
     * again after a loop. Throws
     * std::invalid_argument on a null description. */
    EgomotionResult estimate(const Description& prev, const Description& cur) const;

    /** A description kept for registering its frame much later (a loop) in
     * little memory: at most a given number of features, the strongest
     * gradients of each image cell first so that they cover the image, with
     * 8-bit descriptors (one scale per row). bytes() is what it holds. */
    struct CompactDescription
    {
        FeatureList features;  //!< the kept features, strongest gradient of each image cell first
        int dim{0};            //!< values per descriptor
        std::vector<std::int8_t> codes;  //!< features.size() x dim
        std::vector<float> scales;       //!< per feature: value = code * scale
        mrpt::img::TCamera camera;       //!< of the intensity image
        double baseline{0};              //!< stereo baseline [m]
        /** Bytes it holds: the struct itself, its features, codes and scales. */
        std::size_t bytes() const;
    };
    /** The compact form of `d` with at most `max_features` features (0: all
     * of them); a null `d` gives an empty one. */
    static CompactDescription compact(const Description& d, std::size_t max_features);
    /** A description to give estimate() again (descriptors re-normalised, so
     * Pearson's rho is still a dot product); null if `c` has no feature. */
    static Description expand(const CompactDescription& c);

private:
    Described describe(const emslam::stereo::StereoFrame& f) const;
    /** estimateMatching(), distinct if experimental_match_distinctiveness is on; if that
     * fails and `fall_back_to_paper`, again with the paper's matching. */
    EgomotionResult estimateDescribed(
        const Described& prev,
        const Described& cur,
        const mrpt::poses::CPose3D* prediction,
        bool fall_back_to_paper) const;
    /** Guided if `prediction` (T_prev_cur) is given and guided_matching is
     * on; with Distinctiveness if `distinct`. */
    EgomotionResult estimateMatching(
        const Described& prev,
        const Described& cur,
        const mrpt::poses::CPose3D* prediction,
        bool distinct) const;
    /** How far stage 4 goes: the paper's Dpp minimisation, or only its
     * closed-form (Euclidean) start, enough for a prediction. */
    enum class PoseStage
    {
        Dpp,
        ClosedFormOnly
    };
    EgomotionResult estimateWithMatches(
        const Described& prev,
        const Described& cur,
        const std::function<MatchList()>& match,
        PoseStage stage = PoseStage::Dpp) const;
    /** Guided matching around where T_prev_cur puts the previous features,
     * within radius_factor * guided_radius. */
    MatchList guidedMatches(
        const Described& prev,
        const Described& cur,
        const mrpt::poses::CPose3D& T_prev_cur,
        double radius_factor,
        bool distinct) const;

    /** The Distinctiveness of matching `prev` to `cur` (off unless
     * experimental_match_distinctiveness > 1). */
    Distinctiveness distinctiveness(const Described& prev, const Described& cur) const;

    TParameters m_params;
    std::shared_ptr<const Described> m_prev;
    /** The gradient maps of the image locateFeatures() saw last, for the
     * describe of that image's frame (GlmFeatureExtractor::extract checks
     * that it is the same image). */
    mutable std::shared_ptr<const GlmFeatureExtractor::Gradients> m_located;
    /** The last successful step's action: the constant-velocity prediction. */
    std::optional<mrpt::poses::CPose3D> m_velocity;
};

}  // namespace emslam::egomotion
