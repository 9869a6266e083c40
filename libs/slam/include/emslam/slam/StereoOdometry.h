// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/stereo/StereoFrame.h>
#include <emslam/stereo/StereoFrontEnd.h>

#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>

namespace emslam::slam
{
/** Visual odometry, the first half of EntropySlam: stereo front-end →
 * egomotion (§2.1) → the pose chained step by step. A step whose egomotion
 * fails repeats the previous step (constant velocity); the first frame is
 * the world origin. With `[StereoMatcher] sparse_at_features` the front-end
 * matches only the egomotion's feature pixels. emslam-odometry runs it
 * alone; EntropySlam adds space sampling and rectification.
 * \ingroup emslam_slam_grp \sa EntropySlam */
class StereoOdometry
{
public:
    /** What process() did with one frame. */
    struct Step
    {
        emslam::stereo::StereoFrame frame;  //!< the front-end's output
        emslam::egomotion::EgomotionResult
            egomotion;  //!< the egomotion's result for the step (not ok after a failure)
        /** The motion from the previous frame: the egomotion's, or after a
         * failure the previous step again; the identity for the first frame. */
        mrpt::poses::CPose3D action;
        bool first{false};      //!< the first frame: no step measured
        bool predicted{false};  //!< the egomotion failed: `action` is a prediction
        double ms_stereo{0.0};  //!< the front-end's time [ms]
    };

    /** A front-end with `stereo` and an egomotion with `egomotion`. */
    StereoOdometry(
        const emslam::stereo::StereoMatcher::TParameters& stereo,
        const emslam::egomotion::EgomotionEstimator::TParameters& egomotion);
    StereoOdometry(const StereoOdometry&) = delete;
    StereoOdometry& operator=(const StereoOdometry&) = delete;

    /** Processes one observation into `step`. Returns false (and changes
     * nothing) if it is neither stereo nor RGB-D; what the front-end throws
     * for an unusable observation passes on, with nothing changed either. */
    bool process(const mrpt::obs::CObservation& obs, Step& step);

    /** T_world_cam of the last processed frame (world = the first camera). */
    const mrpt::poses::CPose3D& pose() const { return m_T_world_cur; }
    /** Frames processed, and steps whose egomotion failed. */
    ///@{
    std::size_t frameCount() const { return m_frames; }
    std::size_t failures() const { return m_failures; }
    ///@}
    /** Steps matched near the constant-velocity prediction, and guided
     * attempts that fell back to the full search ([EgomotionEstimator] guided_matching). */
    ///@{
    std::size_t guidedSteps() const { return m_guided_steps; }
    std::size_t guidedFallbacks() const { return m_guided_fallbacks; }
    ///@}

    /** The stereo front-end. */
    const emslam::stereo::StereoFrontEnd& frontEnd() const { return m_front; }
    /** The egomotion estimator. */
    const emslam::egomotion::EgomotionEstimator& estimator() const { return m_estimator; }

private:
    emslam::stereo::StereoFrontEnd m_front;
    emslam::egomotion::EgomotionEstimator m_estimator;
    mrpt::poses::CPose3D m_T_world_cur;
    /** The last step the egomotion estimated: a failed step repeats it. */
    mrpt::poses::CPose3D m_velocity;
    std::size_t m_frames{0}, m_failures{0};
    std::size_t m_guided_steps{0}, m_guided_fallbacks{0};
};

}  // namespace emslam::slam
