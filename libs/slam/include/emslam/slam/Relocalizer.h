// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/rectify/ActionCovariance.h>
#include <emslam/slam/PlaceRecognition.h>

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <optional>
#include <vector>

namespace emslam::slam
{
/** Where a frame is in a saved map, by its look alone (a run that starts
 * in a session it continues or is localized in, EntropySlam):
 * 1. the saved keyframes that look most like it (PlaceRecognition over their
 *    kept descriptions) are registered against it by the egomotion;
 * 2. where the registration of most inliers puts it, the saved keyframes
 *    near that pose and facing its way are registered too;
 * 3. the frame is placed by the registration of most inliers that another
 *    one agrees with (the same pose within their covariances, χ²(6) at
 *    99.73 %), and only if it beats the best registration of another place
 *    (beyond the loop closer's revisit gate, `max_distance`, `max_angle`)
 *    by more than three standard deviations of the counts (Poisson). Why
 *    the best and not the sum: in a periodic corridor consecutive keyframes
 *    are fooled alike, so their agreement is no independent evidence; the
 *    place truly seen again registers more of the frame's features than any
 *    look-alike.
 * A frame where a look-alike is as good is not placed, the next one may
 * tell them apart; unless a prior pose is given (a run that continues a
 * session most often starts where it stopped) and one of the places it
 * cannot tell apart is at the prior. \ingroup emslam_slam_grp \sa CMapSession */
class Relocalizer
{
public:
    /** A keyframe of the saved map. */
    struct Place
    {
        /** Its kept description (LoopCloser::Snapshot::Keyframe::kept). */
        emslam::egomotion::EgomotionEstimator::CompactDescription kept;
        mrpt::poses::CPose3D pose;  //!< world
        /** How well it sits among its neighbours: the egomotion's
         * covariance of the motion that placed it. */
        emslam::rectify::ActionCovariance covariance;
    };
    /** Where the frame is. */
    struct Fix
    {
        std::size_t place{0};                //!< the registration kept, as in the places given
        mrpt::poses::CPose3D T_world_frame;  //!< by that registration
        /** Of T_place_frame, the registration's (times the covariance scale). */
        emslam::rectify::ActionCovariance covariance;
        std::size_t matches{0};   //!< after LWO
        std::size_t agreeing{0};  //!< registrations that agree with it, itself included
        std::size_t tried{0};     //!< registrations made
    };

    /** How it searches. */
    struct TOptions
    {
        std::size_t candidates{8};  //!< keyframes registered by look, and near the fix
        /** The frame's registrations count their covariance times this (>=
         * 1: how much the egomotion understates its error,
         * LoopCloser::Stats::drift_scale). */
        double covariance_scale{1};
        double max_distance{2};    //!< [m] keyframes near a fix
        double max_angle{0.5236};  //!< [rad] and facing within this of it
    };
    /** Over `places` (the saved keyframes). */
    Relocalizer(std::vector<Place> places, const TOptions& options);

    /** The frame described by `frame` in the map, or nothing; `prior`:
     * where it most likely is (see the class comment). */
    std::optional<Fix> locate(
        const emslam::egomotion::EgomotionEstimator::Description& frame,
        const emslam::egomotion::EgomotionEstimator& estimator,
        const std::optional<mrpt::poses::CPose3D>& prior = std::nullopt) const;

    /** Places in the map. */
    std::size_t size() const { return m_places.size(); }

private:
    /** The frame registered against place `place`. */
    std::optional<Fix> registerAt(
        std::size_t place,
        const emslam::egomotion::EgomotionEstimator::Description& frame,
        const emslam::egomotion::EgomotionEstimator& estimator) const;
    /** The nearest places within max_distance of `pose`, facing within max_angle. */
    std::vector<std::size_t> placesNear(const mrpt::poses::CPose3D& pose) const;
    /** Whether two fixes put the frame at one pose within their covariances. */
    static bool agree(const Fix& a, const Fix& b);
    /** Whether two poses are within the revisit gate (max_distance, max_angle). */
    bool samePlace(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b) const;
    /** Whether `a` inliers are fewer than `b` beyond the counts' noise. */
    static bool significantlyFewer(std::size_t a, std::size_t b);
    /** The fix of most matches that another agrees with (near `near`, if given). */
    std::optional<Fix> strongestAgreed(
        const std::vector<Fix>& fixes, const mrpt::poses::CPose3D* near) const;
    /** Whether every fix of another place has significantly fewer matches. */
    bool clearlyBest(const Fix& best, const std::vector<Fix>& fixes) const;

    std::vector<Place> m_places;
    PlaceRecognition m_index;
    TOptions m_options;
};

}  // namespace emslam::slam
