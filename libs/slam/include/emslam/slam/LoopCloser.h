// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/rectify/ActionCovariance.h>
#include <emslam/rectify/PoseGraph.h>
#include <emslam/stereo/StereoFrame.h>
#include <emslam/stereo/VerticalFromPlanes.h>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace emslam::slam
{
/** Loop closing beside the paper's rectification: the places a path comes
 * back to are registered by the egomotion itself, and the keyframe poses are
 * bent to agree with them (a pose graph, emslam::rectify::PoseGraph).
 *
 * Why: the entropy of a drifting stereo map barely changes when a long loop
 * is closed (doc/rectify.md), while the egomotion registers a place seen
 * again to a centimetre. The rectifier keeps what it is good at (a map
 * consistent with itself, the Manhattan or flat-floor alignment); the loop
 * closer moves every keyframe, including those the compressed trajectory
 * holds rigid.
 *
 * close() runs once the trajectory is final:
 * 1. Candidates: keyframe pairs (i, j) whose path in between is at least
 *    `min_path_length`, whose cameras look within `max_angle_deg` of each
 *    other, and whose estimated distance is within `max_distance` plus three
 *    standard deviations of the chain's drift between them (from the
 *    egomotion's own covariances: translations, and rotations times their
 *    lever arm).
 * 2. Registration: the `max_candidates` nearest of them per keyframe j, by
 *    EgomotionEstimator::estimate() on the kept descriptions (GLM features,
 *    log-polar matching, LWO, Dpp); kept if it succeeds and its correction
 *    of the chain is within three standard deviations.
 * 3. Consensus: a repetitive world (a wallpaper, a row of doors) registers
 *    look-alike places too, each with its own correction. The registrations
 *    are grouped by the world correction they ask for, two agreeing when
 *    their corrections differ by less than three standard deviations of the
 *    drift between them; the group of the registration with the smallest
 *    normalised correction wins if it has at least two members.
 * 4. The winners join the pose graph as edges (their Dpp covariances), which
 *    is solved; steps 1–4 repeat on the corrected poses until no group wins.
 *
 * Before step 1, with `local_edges` > 0, each keyframe is registered
 * against the few keyframes before it and those edges (kept if their
 * Mahalanobis distance to the chain, under the chain's composed covariance
 * plus their own, is within the 99.73 % bulk of a χ²(6))
 * join the graph, which is solved once: this bends the path where no loop
 * does.
 *
 * After the last round, with `vertical_prior`, the up each keyframe saw in
 * its dense cloud (observeVertical()) levels the graph (levelFloors()).
 *
 * The odometry edges are the relative poses of the keyframes as given (the
 * rectified trajectory) with the egomotion's covariances.
 * \ingroup emslam_slam_grp \sa EntropySlam */
class LoopCloser
{
public:
    /** `[LoopCloser]` */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws std::invalid_argument naming the key of a bad value. */
        void validate() const;

        /** Close loops after the rectification. (Default: false, the paper) */
        bool enabled{false};
        /** [m] path between two keyframes before they may close a loop:
         * shorter detours are the egomotion's. (Default: 10) */
        double min_path_length{10.0};
        /** [m] how far apart two keyframes may see the same place, beyond
         * their drift. (Default: 2) */
        double max_distance{2.0};
        /** [deg] how far apart the viewing directions of two keyframes may
         * be and still register. (Default: 30) */
        double max_angle_deg{30.0};
        /** Registrations tried per keyframe, nearest first: with a drift of
         * metres the nearest by the estimate are often not the place seen
         * again. A registration costs a few ms at 320×240. (Default: 8) */
        int max_candidates{8};
        /** Rounds of detection and solving. (Default: 4) */
        int max_rounds{4};
        /** Each keyframe is also registered directly against this many
         * keyframes before it, and those registrations join the pose graph:
         * one registration in place of a chain of frame-to-frame steps, so
         * the chain's errors average out along the whole path, loop or not.
         * 0: off. A few ms per registration. (Default: 0) */
        int local_edges{0};
        /** Level the floors: each keyframe's dense cloud says where up is
         * (emslam::stereo::VerticalFromPlanes), and those that agree join
         * the pose graph as priors on its tilt (levelFloors()). For
         * buildings (floors, ceilings, stair treads are level); not for
         * open terrain. (Default: false) */
        bool vertical_prior{false};
        /** The `vertical_*` keys of the measurement. */
        emslam::stereo::VerticalFromPlanes::TParameters vertical;
    };

    /** What close() did. */
    struct Stats
    {
        std::size_t candidates{0};            //!< pairs within the gates of step 1
        std::size_t registrations{0};         //!< egomotion registrations tried
        std::size_t registered{0};            //!< of them: succeeded and within the gate
        std::size_t loop_edges{0};            //!< accepted into the pose graph
        std::size_t local_registrations{0};   //!< of `local_edges`, tried
        std::size_t local_edges{0};           //!< of them: within the gate, in the graph
        std::size_t verticals_measured{0};    //!< keyframes whose up was measured
        std::size_t verticals_used{0};        //!< of them: agreed, in the graph
        double vertical_drift_deg{0};         //!< tilt spread before levelling
        double vertical_bias_deg{0};          //!< the camera's own tilt of what it sees
        double vertical_correlation_time{1};  //!< keyframes that share one error
        int rounds{0};
        double initial_cost{0}, final_cost{0};  //!< of the pose graph, first and last solve
        double ms{0};
    };

    /** An accepted loop edge, for reports. */
    struct LoopEdge
    {
        std::size_t frame_from{0}, frame_to{0};  //!< frame indices (as given to addKeyframe())
        mrpt::poses::CPose3D measurement;        //!< pose of `frame_to` in `frame_from`
        std::size_t matches{0};                  //!< after LWO
    };

    explicit LoopCloser(const TParameters& p);

    const TParameters& parameters() const { return m_p; }

    /** Adds the next keyframe: its frame index, its description (may be
     * null: never registered), the egomotion's covariance of its motion
     * since the previous keyframe and, if known, that motion itself (both
     * ignored for the first). The local edges are checked against the
     * egomotion's own chain of these motions, so that a registration can
     * undo what the rectifier did wrong; without them, against the poses
     * given to close(). */
    void addKeyframe(
        std::size_t frame_index,
        emslam::egomotion::EgomotionEstimator::Description description,
        const emslam::rectify::ActionCovariance& step_covariance,
        const std::optional<mrpt::poses::CPose3D>& step_motion = std::nullopt);
    /** Measures the up that keyframe `frame_index` (already added) sees in
     * its dense cloud `frame`, near where `pose` (world, the egomotion's)
     * says it is; nothing unless `vertical_prior`. */
    void observeVertical(
        std::size_t frame_index,
        const emslam::stereo::StereoFrame& frame,
        const mrpt::poses::CPose3D& pose);
    std::size_t keyframeCount() const { return m_keyframes.size(); }

    /** The keyframe poses (world, one per addKeyframe(), in order) with the
     * loops closed; `poses` unchanged if none was found. Throws
     * std::invalid_argument if `poses` has another size. */
    std::vector<mrpt::poses::CPose3D> close(
        const std::vector<mrpt::poses::CPose3D>& poses,
        const emslam::egomotion::EgomotionEstimator& estimator);

    const Stats& stats() const { return m_stats; }
    const std::vector<LoopEdge>& loopEdges() const { return m_edges; }

private:
    /** The `local_edges` registrations into `graph`, which is then solved. */
    void addLocalEdges(
        emslam::rectify::PoseGraph& graph,
        const std::vector<emslam::rectify::ActionCovariance>& steps,
        const emslam::rectify::ActionCovariance& mean_step,
        const emslam::egomotion::EgomotionEstimator& estimator);

    struct Keyframe
    {
        std::size_t frame_index{0};
        emslam::egomotion::EgomotionEstimator::Description description;
        emslam::rectify::ActionCovariance covariance;
        std::optional<mrpt::poses::CPose3D> motion;
        std::optional<emslam::stereo::VerticalMeasurement> vertical;
    };
    TParameters m_p;
    emslam::stereo::VerticalFromPlanes m_vertical;  // with m_p.vertical
    mrpt::math::TVector3D m_up_sum{0, 0, 0};        // ups seen (world), weighted by information
    std::vector<Keyframe> m_keyframes;
    Stats m_stats;
    std::vector<LoopEdge> m_edges;
};

}  // namespace emslam::slam
