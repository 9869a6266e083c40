// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/rectify/ActionCovariance.h>
#include <emslam/rectify/PoseGraph.h>
#include <emslam/slam/PlaceRecognition.h>
#include <emslam/stereo/StereoFrame.h>
#include <emslam/stereo/VerticalFromPlanes.h>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose3D.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace emslam::slam
{
/** Loop closing beside the paper's rectification, online: each keyframe is
 * registered, as it arrives, against the few keyframes before it and against
 * the places it may be seeing again, by the egomotion itself, and the
 * keyframe poses are bent to agree (a pose graph,
 * emslam::rectify::PoseGraph).
 *
 * Why: the entropy of a drifting stereo map barely changes when a long loop
 * is closed (doc/rectify.md), while the egomotion registers a place seen
 * again to a centimetre. The rectifier keeps what it is good at (a map
 * consistent with itself, the Manhattan or flat-floor alignment); the loop
 * closer moves every keyframe, including those the compressed trajectory
 * holds rigid.
 *
 * Threads: addKeyframe() and observeVertical() come from the producer (the
 * mapper's frame loop); update() runs on a background thread and does the
 * work of the keyframes added since its last call; currentPoses() may be
 * read from any thread; close() ends the run once update() is no longer
 * called.
 *
 * update(), per new keyframe j (the work is bounded: a fixed number of
 * registrations, a spatial index instead of all pairs):
 * 1. Node: j is placed by the egomotion's motion since the previous
 *    keyframe, with that motion's covariance as an odometry edge.
 * 2. Local edges (`local_edges` > 0): j is registered against the few
 *    keyframes before it; an edge whose Mahalanobis distance to the
 *    egomotion's chain (its composed covariance plus the edge's own) is
 *    within the 99.73 % bulk of a χ²(6) joins the graph.
 * 3. Candidates, two ways. By their look (`place_candidates` > 0): the
 *    keyframes PlaceRecognition finds most like j (an inverted index of the
 *    kept descriptors), whatever the drift. By proximity: keyframes whose
 *    cameras look within `max_angle_deg` plus three standard deviations of
 *    the chain's rotation drift of j's, and whose estimated distance is
 *    within `max_distance` plus three standard deviations of the chain's
 *    drift between them (translations, and rotations times their lever
 *    arm, shortened by the loops already closed); a grid over the keyframe
 *    positions finds them. Both only at least `min_path_length` of path
 *    before j.
 *    The drift is the egomotion's covariances, except where they are known
 *    to understate it: a step the egomotion predicted because it failed
 *    counts as off by up to the largest step it measured (one missed turn
 *    on the spot is tens of degrees), and the whole chain is scaled by the
 *    median Mahalanobis² of the local registrations to it over that of a
 *    χ²(6) when larger (Drift).
 * 4. Registration: the look-alikes first, then the `max_candidates`
 *    nearest, by EgomotionEstimator::estimate() against the kept compact
 *    descriptions (`kept_features`); kept if it succeeds and its correction
 *    of the chain is within three standard deviations of that drift.
 * 5. Consensus: a repetitive world registers look-alike places too, each
 *    with its own correction. The registrations of the last
 *    `consensus_window` keyframes are grouped by the world correction they
 *    ask for, two agreeing when their corrections differ by less than three
 *    standard deviations of the drift between them; of the groups with at
 *    least two members (loop edges accepted in the window count as
 *    members), the one of the largest support × exp(−n/2) wins, n the
 *    normalised correction of its seed: the drift's prior on the correction
 *    times the registrations that found it on their own. A new loop (none
 *    accepted in the window) is decided only when the path has gone past
 *    its oldest registration by that registration's correction, so that a
 *    look-alike seen first competes with the place truly revisited.
 * 6. Solve: when a new loop edge disagrees with the graph beyond its χ²
 *    bulk, the graph is solved from where it is (a few Levenberg–Marquardt
 *    iterations). The χ² gates count the egomotion's covariances as the
 *    data show them (times the drift scale: on real images registrations
 *    of one true loop disagree beyond their stated noise). A group the
 *    solved graph cannot agree with loses the member it disagrees with most
 *    and is solved again, while the rest are still the group's majority;
 *    else it is refused and the graph restored. A loop edge the solved
 *    graph still disagrees with beyond that bulk is dropped and the graph
 *    solved again.
 * 7. Contradictions: a loop edge dropped, or a group refused while asking
 *    for another correction than the loop edges accepted in the window (a
 *    group agreeing with them is the same loop, beyond its noise), is the
 *    solved graph contradicting registrations the consensus let through; a
 *    group counts once per consensus window of keyframes it spans. A true
 *    edge fails its χ² test by chance once in 370, and one look-alike place
 *    may fool the consensus twice (in and out); more contradictions than
 *    that (and than the 99.73 % bulk of the Poisson count of chance
 *    failures) mean a world of look-alikes the registrations cannot tell
 *    apart (a periodic texture, identical floors): the run's loop closing
 *    is unreliable (Stats::unreliable), its loop edges are withdrawn, the
 *    keyframes placed again along the odometry edges and the graph solved
 *    from there (from the bent graph, a few iterations stay bent), no
 *    further loop closes and close() does not polish.
 *
 * Levelling (`vertical_prior`) is online too: the up each keyframe saw in
 * its dense cloud is gated once, at the first rectification after it came,
 * and joins the graph as a prior on its tilt (relevelFloors()); every solve
 * from then on, local or not, counts the priors. Only when the world up and
 * the camera's bias moved beyond their noise are all ups gated again and
 * the graph solved whole.
 *
 * close() polishes: the odometry edges take the rectified relative poses,
 * the ups of the last keyframes join, the graph is solved once more from
 * the first keyframe that changed, inconsistent loop edges dropped.
 * \ingroup emslam_slam_grp \sa EntropySlam */
class LoopCloser
{
public:
    /** `[LoopCloser]` */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws std::invalid_argument naming the key of a bad value. */
        void validate() const;

        /** Close loops beside the rectification (false: the paper's result
         * alone). (Default: true) */
        bool enabled{true};
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
        /** Keyframes that look most like the new one (PlaceRecognition, an
         * inverted index of the kept descriptors), registered before the
         * nearest by the estimate: they are proposed whatever the drift. 0:
         * proximity alone. (Default: 4) */
        int place_candidates{4};
        /** Each keyframe is also registered directly against this many
         * keyframes before it, and those registrations join the pose graph:
         * one registration in place of a chain of frame-to-frame steps, so
         * the chain's errors average out along the whole path, loop or not.
         * 0: off. A few ms per registration. (Default: 3) */
        int local_edges{3};
        /** Level the floors: each keyframe's dense cloud says where up is
         * (emslam::stereo::VerticalFromPlanes), and those that agree join
         * the pose graph as priors on its tilt, online (relevelFloors()). For
         * buildings (floors, ceilings, stair treads are level); not for
         * open terrain. (Default: false) */
        bool vertical_prior{false};
        /** [deg] the largest tilt of the camera's own bias in the ups it
         * sees (levelFloors()): solved only once the keyframes' orientations
         * tell it from the world up, and never beyond this. (Default: 3) */
        double vertical_max_bias_deg{3.0};
        /** Features kept per keyframe for registering it again later (the
         * strongest of each image cell, 8-bit descriptors; about 150 bytes
         * each): what bounds the memory of a long run. 0: every feature at
         * full precision. (Default: 200) */
        int kept_features{200};
        /** Keyframes whose registrations may agree with each other
         * (consensus, step 5). (Default: 10) */
        int consensus_window{10};
        /** Keyframes the background loop closing may lag behind the frames
         * before the mapper waits for it: bounds the work left at the end
         * of a run and how old the online estimate may be. (Default: 20) */
        int max_lag{20};
        /** [ms] Work the background loop closing may have left before the
         * mapper waits for it: the keyframes waiting times its recent time
         * per keyframe. Bounds the time after the last frame and the age of
         * the online estimate in time, on any machine. 0: max_lag only.
         * (Default: 100) */
        double max_lag_ms{100};
        /** The up measurement: section `[VerticalFromPlanes]`, loaded by
         * EntropySlam::TParameters (not by this struct's load / save). */
        emslam::stereo::VerticalFromPlanes::TParameters vertical;
    };

    /** What close() did. */
    struct Stats
    {
        std::size_t candidates{0};         //!< pairs within the gates of step 1
        std::size_t place_candidates{0};   //!< proposed by their look (place_candidates)
        std::size_t place_index_bytes{0};  //!< of the PlaceRecognition index
        double place_ms{0};                //!< its queries and insertions, all keyframes
        std::size_t place_visited_max{0};  //!< index entries a query visited, at most
        /** The egomotion's variances times this are its drift (calibrated
         * by the local registrations' misclosures; 1: as it says). */
        double drift_scale{1};
        std::size_t registrations{0};        //!< egomotion registrations tried
        std::size_t registered{0};           //!< of them: succeeded and within the gate
        std::size_t loop_edges{0};           //!< accepted into the pose graph
        std::size_t local_registrations{0};  //!< of `local_edges`, tried
        std::size_t local_edges{0};          //!< of them: within the gate, in the graph
        std::size_t verticals_measured{0};   //!< keyframes whose up was measured
        std::size_t verticals_used{0};       //!< of them: agreed, in the graph
        double vertical_drift_deg{0};        //!< tilt spread before levelling
        /** The camera's own tilt of what it sees [deg]; NaN while not
         * observable (see levelFloors()). */
        double vertical_bias_deg{std::numeric_limits<double>::quiet_NaN()};
        double vertical_correlation_time{1};  //!< keyframes that share one error
        /** Solves of every keyframe because the levelling's world up and
         * bias moved beyond their noise (relevelFloors()). */
        std::size_t level_resolves{0};
        int rounds{0};                //!< solves of the graph
        std::size_t local_solves{0};  //!< of them: the recent keyframes only
        /** From a keyframe's addKeyframe() to its loop edges in the
         * current poses [ms], over the keyframes that closed a loop. */
        ///@{
        double latency_ms_mean{0}, latency_ms_max{0};
        ///@}
        std::size_t latency_count{0};  //!< keyframes the mean is over
        /** New loops (none accepted in the consensus window before): from
         * the first keyframe that registered the place seen again to the
         * loop in the current poses, in wall time [ms] and in path [m]. The
         * path is the wait of step 5 (a look-alike seen first must compete
         * with the place truly revisited); it is what a frame rate turns
         * into sensor time. */
        ///@{
        double new_loop_latency_ms_mean{0}, new_loop_latency_ms_max{0};
        double new_loop_wait_m_mean{0}, new_loop_wait_m_max{0};
        ///@}
        std::size_t new_loops{0};       //!< loops closed where none was in the window
        std::size_t dropped_edges{0};   //!< loop edges the solved graph disagreed with
        std::size_t refused_groups{0};  //!< consensus groups the solved graph refused
        /** Of those, the groups asking for another correction than the loop
         * followed, their registrations and the keyframes they registered. */
        ///@{
        std::size_t contradicting_groups{0}, contradicting_edges{0}, contradicting_keyframes{0};
        ///@}
        std::size_t kept_bytes{0};  //!< kept descriptions, all keyframes
        /** Cost of the pose graph at the first and the last solve. */
        ///@{
        double initial_cost{0}, final_cost{0};
        ///@}
        double ms{0};         //!< update() and close(), all of it
        double polish_ms{0};  //!< close() alone
        /** Of polish_ms: the solve, the levelling. */
        ///@{
        double polish_solve_ms{0}, polish_level_ms{0};
        ///@}
        std::size_t refused_edges{0};  //!< loop edges of the refused groups
        /** Empty, or why the loop closing is not to be trusted: the solved
         * graph contradicted the registrations (dropped edges, refused
         * groups) more often than chance and one look-alike place explain
         * (step 7 of the class comment). From then on no
         * loop closes, and the loop edges accepted so far are withdrawn
         * (counted in `withdrawn_edges`, not in `loop_edges`). */
        std::string unreliable;
        std::size_t withdrawn_edges{0};  //!< loop edges withdrawn as unreliable
    };

    /** A keyframe's pose in the current estimate. */
    struct KeyframePose
    {
        std::size_t frame_index{0};  //!< as given to addKeyframe()
        mrpt::poses::CPose3D pose;   //!< world
    };

    /** The last keyframe in the graph at its current pose (any thread). */
    std::optional<KeyframePose> lastPose() const;

    /** An accepted loop edge, for reports. */
    struct LoopEdge
    {
        /** Frame indices (as given to addKeyframe()). */
        ///@{
        std::size_t frame_from{0}, frame_to{0};
        ///@}
        mrpt::poses::CPose3D measurement;  //!< pose of `frame_to` in `frame_from`
        std::size_t matches{0};            //!< after LWO
    };

    /** What a later run needs to go on with this graph (a saved session,
     * CMapSession): the keyframes, the pose graph and the drift's
     * calibration. */
    struct Snapshot
    {
        /** A keyframe, as addKeyframe() gave it, with its kept description. */
        struct Keyframe
        {
            std::size_t frame_index{0};  //!< as given to addKeyframe()
            /** Its description for registering it again. */
            emslam::egomotion::EgomotionEstimator::CompactDescription kept;
            /** Of the motion since the previous keyframe. */
            emslam::rectify::ActionCovariance covariance;
            std::optional<mrpt::poses::CPose3D> motion;  //!< since the previous keyframe
            bool predicted{false};                       //!< the motion holds a predicted step
            std::optional<emslam::stereo::VerticalMeasurement> vertical;  //!< the up it saw
        };
        std::vector<Keyframe> keyframes;  //!< in the order added
        /** Keyframe poses in the graph's world (the first keyframe's). */
        std::vector<mrpt::poses::CPose3D> nodes;
        /** Every edge (odometry, local, loop); a loop edge's tag minus
         * `loop_tag` indexes `loop_edges`. */
        std::vector<emslam::rectify::PoseGraph::Edge> edges;
        std::vector<LoopEdge> loop_edges;       //!< of the loop edges in `edges`
        std::size_t loop_tag{0};                //!< see `edges`
        std::vector<double> local_misclosures;  //!< see Stats::drift_scale
        /** The largest keyframe motion measured [m], [rad]. */
        ///@{
        double largest_step_t{0}, largest_step_r{0};
        ///@}
    };
    /** The graph after close() (world: its first keyframe). */
    Snapshot snapshot() const;
    /** Before the first addKeyframe(): the graph starts as `s` left it, its
     * keyframes numbered `frame_offset` + their frame index; the next
     * keyframe added is placed from the last of them. Their registrations
     * are not made again; they are candidates for the new keyframes, by
     * their look and by proximity. `hold_fixed`: no solve moves them (a run
     * localized in a saved map). Throws std::logic_error after
     * addKeyframe(), std::invalid_argument on an inconsistent snapshot. */
    void seed(const Snapshot& s, std::size_t frame_offset, bool hold_fixed);

    /** A loop closer with the parameters `p` (validated); the graph is empty. */
    explicit LoopCloser(const TParameters& p);
    ~LoopCloser();
    LoopCloser(const LoopCloser&) = delete;
    LoopCloser& operator=(const LoopCloser&) = delete;

    /** The parameters it runs with. */
    const TParameters& parameters() const { return m_p; }

    /** Adds the next keyframe (producer thread): its frame index, its
     * description (may be null: never registered), the egomotion's
     * covariance of its motion since the previous keyframe and that motion
     * (both ignored for the first), and whether that motion holds a step
     * the egomotion predicted because it failed (the drift then counts it
     * as off by up to the largest step measured). update() takes only
     * keyframes with a motion; close() places the others by the poses it is
     * given. */
    void addKeyframe(
        std::size_t frame_index,
        emslam::egomotion::EgomotionEstimator::Description description,
        const emslam::rectify::ActionCovariance& step_covariance,
        const std::optional<mrpt::poses::CPose3D>& step_motion = std::nullopt,
        bool step_predicted = false);
    /** Measures the up that keyframe `frame_index` (already added) sees in
     * its dense cloud `frame`, near where `pose` (world, the egomotion's)
     * says it is; nothing unless `vertical_prior`. Producer thread. */
    void observeVertical(
        std::size_t frame_index,
        const emslam::stereo::StereoFrame& frame,
        const mrpt::poses::CPose3D& pose);
    /** The rectifier's current keyframe poses (producer thread; world):
     * the next update() makes their relative poses the odometry edges of
     * the keyframes it holds and solves the graph, so that the online
     * estimate has the rectification as well as the loops. Only the latest
     * set waits. */
    void setRectifiedPoses(std::vector<KeyframePose> poses);
    /** Before close() (any thread): forgets the rectified poses still
     * waiting and cuts short a solve for them after its current iteration,
     * since close() takes the final ones: solving for them first would be
     * work done twice after the last frame. */
    void prepareToClose();
    /** Keyframes added so far (any thread). */
    std::size_t keyframeCount() const;
    /** Keyframes in the graph so far (any thread). */
    std::size_t processedCount() const;
    /** [ms] The time the keyframes added but not yet in the graph will
     * take, at the recent time per keyframe (any thread). */
    double backlogMs() const;

    /** Background thread: the work of every keyframe added since the last
     * call (see the class comment), in order; while `stop` returns true the
     * keyframes only get their nodes. Returns how many were taken. */
    std::size_t update(
        const emslam::egomotion::EgomotionEstimator& estimator,
        const std::function<bool()>& stop = {});
    /** The keyframes in the graph at their current poses (any thread; world
     * = the first keyframe). */
    std::vector<KeyframePose> currentPoses() const;
    /** The loop edges in the current estimate (any thread): the frame
     * indices of their ends, as given to addKeyframe(), oldest first. */
    std::vector<std::pair<std::size_t, std::size_t>> currentLoops() const;

    /** The keyframe poses (world, one per addKeyframe(), in order) with the
     * loops closed, starting from `poses` (the rectified trajectory): the
     * keyframes update() did not take are taken first, then the graph is
     * polished (see the class comment); with `stop` true, no more
     * registrations and no polish (the online estimate, moved to `poses`'
     * first pose). Call once update() is no longer called. Throws
     * std::invalid_argument if `poses` has another size. */
    std::vector<mrpt::poses::CPose3D> close(
        const std::vector<mrpt::poses::CPose3D>& poses,
        const emslam::egomotion::EgomotionEstimator& estimator,
        const std::function<bool()>& stop = {});

    /** After close(), or from the thread that calls update(). */
    const Stats& stats() const { return m_stats; }
    /** Stats::unreliable as it stands (any thread). */
    std::string unreliable() const;
    /** The accepted loop edges, in the order accepted (after close(), or from the thread that calls
     * update()). */
    const std::vector<LoopEdge>& loopEdges() const { return m_edges; }

private:
    struct Keyframe
    {
        std::size_t frame_index{0};
        /** Full while local edges may still register against it. */
        emslam::egomotion::EgomotionEstimator::Description description;
        emslam::egomotion::EgomotionEstimator::CompactDescription kept;
        emslam::rectify::ActionCovariance covariance;
        std::optional<mrpt::poses::CPose3D> motion;
        bool predicted{false};  //!< the motion holds a predicted step
        std::optional<emslam::stereo::VerticalMeasurement> vertical;
        std::chrono::steady_clock::time_point added;  //!< by addKeyframe()
    };
    struct Registration;
    class Drift;
    class Grid;

    /** Steps 1-6 for the next keyframe, `T_prev_cur` placing it. */
    void integrate(
        Keyframe k,
        const mrpt::poses::CPose3D& T_prev_cur,
        const emslam::egomotion::EgomotionEstimator& estimator,
        bool work);
    void addLocalEdges(std::size_t j, const emslam::egomotion::EgomotionEstimator& estimator);
    /** Step 4: registers keyframe j with its candidates; those within the
     * drift of the chain join the pool. */
    void registerCandidates(std::size_t j, const emslam::egomotion::EgomotionEstimator& estimator);
    /** The keyframes near enough to j, by the drift, facing its way: the
     * nearest max_candidates (distance, keyframe), nearest first. */
    std::vector<std::pair<double, std::size_t>> nearCandidates(std::size_t j);
    /** The order to register j's candidates in: those that look like it
     * (place recognition), then the near ones. */
    std::vector<std::size_t> candidateOrder(
        std::size_t j, const std::vector<std::pair<double, std::size_t>>& near);
    /** A local registration's Mahalanobis² to the chain: calibrates the
     * drift (Drift::setScale()). */
    void recordLocalMisclosure(double d2);
    /** The drift scale from the local misclosures recorded. */
    void updateDriftScale();
    /** Step 5 on the pool: the winning group, taken out of it (or none);
     * a new loop waits for the window to end unless `last_call`. */
    std::vector<std::unique_ptr<Registration>> takeConsensusGroup(std::size_t j, bool last_call);
    /** A registration's normalised correction and correction, at the
     * current poses. */
    void measure(Registration& r) const;
    /** Whether the path at keyframe j went far enough past r to decide on it. */
    bool readyToDecide(const Registration& r, std::size_t j) const;
    /** The pool's indices of the group with the largest support x
     * exp(-n/2) (empty: no consensus). */
    std::vector<std::size_t> bestConsensusGroup() const;
    /** Step 6 for a group: its edges join the graph, solved if it disagrees;
     * a group the solved graph refuses (it, or the loop edges accepted in
     * the window) is taken out again. Returns true if the graph was solved
     * and kept. */
    bool tryAccept(std::vector<std::unique_ptr<Registration>> group);
    /** The group's edges join the graph, tagged from `first_tag` on, each
     * registration keeping its misclosure before the solve. */
    void addGroupEdges(std::vector<std::unique_ptr<Registration>>& group, std::size_t first_tag);
    /** The first keyframe a solve for the group may move. */
    std::size_t firstFreeKeyframe(const std::vector<std::unique_ptr<Registration>>& group) const;
    /** After a solve of the keyframes from `first_free` on: if it stopped
     * at `max_iterations` rather than converging, the next solve frees
     * them too. */
    void leaveUnconverged(
        const emslam::rectify::PoseGraph::Result& solved,
        int max_iterations,
        std::size_t first_free);
    /** Solves with the keyframes from `free_from` on free; keeps the
     * solution if it satisfies (within `gate`) every edge from `first_tag`
     * on and every loop edge accepted in the window, else puts the graph
     * back and lists the edges it could not satisfy (tag, cost). */
    bool solveConsistently(
        std::size_t free_from,
        std::size_t first_tag,
        double gate,
        std::vector<std::pair<std::size_t, double>>& offenders);
    /** Takes the group's worst offender out and solves again while the rest
     * are a consensus; true once the solution is consistent. */
    bool dropDisagreeingMembers(
        std::vector<std::unique_ptr<Registration>>& group,
        std::size_t first_tag,
        double gate,
        std::vector<std::pair<std::size_t, double>>& offenders);
    /** The refused group's edges leave the graph and it is counted (a
     * contradiction unless it continues the loop accepted); returns
     * checkContradictions()'s answer, or false. */
    bool refuseGroup(
        const std::vector<std::unique_ptr<Registration>>& group, std::size_t first_tag);
    /** Wall time since keyframe k was added [ms]. */
    double msSinceAdded(std::size_t k) const;
    /** Time from keyframe j's arrival to its loop edges' acceptance. */
    void recordLatency(std::size_t j);
    /** Every keyframe placed by the odometry edges from the first. */
    void placeAlongOdometry();
    /** New-loop latency (Stats::new_loops) of a group about to be accepted. */
    void recordNewLoop(const std::vector<std::unique_ptr<Registration>>& group);
    /** The group's registrations become loop edges (and drift shortcuts). */
    void acceptGroup(std::vector<std::unique_ptr<Registration>>& group);
    /** The χ² gate a loop edge's cost (times 2) must pass in the solved
     * graph, scaled by the drift scale. */
    double loopEdgeGate() const;
    /** Whether two registrations' corrections (at the current poses) agree
     * within the drift between them and their covariances (3σ). */
    bool correctionsAgree(const Registration& a, const Registration& b) const;
    /** Whether each member of a refused group agrees with most loop edges
     * accepted in the window: the loop followed, not a contradiction. */
    bool continuesAcceptedLoop(const std::vector<std::unique_ptr<Registration>>& group) const;
    /** The polish: solve (the keyframes from `first_free` on), drop loop edges the
     * solution refuses, solve again. */
    void solve(int max_iterations, std::size_t first_free = 1);
    /** The online levelling (relevelFloors()) with the keyframes' ups so
     * far: the next solve counts them. Returns the first keyframe whose
     * prior came or went (keyframeCount(): none). */
    std::size_t relevel();
    /** After the solved graph contradicted loop edges: if more of them
     * than chance explains (Stats::unreliable), withdraws every loop edge
     * and solves the graph without them. Returns true if it did. */
    bool checkContradictions();
    emslam::egomotion::EgomotionEstimator::Description descriptionOf(std::size_t k) const;
    /** Takes the keyframes added since the last call (producer's lock). */
    std::vector<Keyframe> takeIncoming();
    void publishPoses(bool all);
    /** The odometry edges take these poses' relative poses (where both ends
     * are there); returns the first keyframe whose edge changed beyond a
     * small fraction of its noise (keyframeCount(): none). */
    std::size_t applyRectified(const std::vector<KeyframePose>& poses);

    TParameters m_p;
    // Producer side.
    emslam::stereo::VerticalFromPlanes m_vertical;  // with m_p.vertical
    mrpt::math::TVector3D m_up_sum{0, 0, 0};        // ups seen (world), weighted by information
    mutable std::mutex m_in_mutex;                  // guards the three below
    std::vector<Keyframe> m_incoming;
    std::vector<std::pair<std::size_t, emslam::stereo::VerticalMeasurement>> m_incoming_verticals;
    std::size_t m_added{0};
    std::optional<std::vector<KeyframePose>> m_incoming_rectified;
    std::atomic<bool> m_closing{false};  // prepareToClose() was called
    // Background side.
    std::vector<Keyframe> m_keyframes;
    std::size_t m_seeded{0};  // keyframes of a saved session, first (seed())
    std::map<std::size_t, std::size_t> m_keyframe_of_frame;
    emslam::rectify::PoseGraph m_graph;
    std::unique_ptr<Drift> m_drift;
    std::unique_ptr<Grid> m_grid;
    PlaceRecognition m_places;              // with place_candidates
    PlaceRecognition::Words m_place_words;  // of the keyframe being integrated
    /** Mahalanobis² of the recent local registrations to the egomotion's
     * chain (ring): how far the egomotion's covariance understates its error. */
    std::vector<double> m_local_misclosures;
    /** Contradicting groups, each counted once per consensus window of
     * keyframes it spans. */
    std::size_t m_contradicting_windows{0};
    std::size_t m_local_misclosure_next{0};
    std::vector<double> m_path;  // along the chain, per keyframe
    /** The largest keyframe motion measured so far [m, rad]. */
    double m_largest_step_t{0}, m_largest_step_r{0};
    /** The first keyframe a local edge added since the last solve that
     * covered it reaches (max: none). */
    std::size_t m_unsolved_from{static_cast<std::size_t>(-1)};
    /** Keyframes before it were free in a solve since they were added. */
    std::size_t m_solved_upto{0};
    /** The levelling the keyframes were last solved with, all of them. */
    emslam::rectify::PoseGraph::DirectionFrame m_levelled_for;
    /** Keyframes at the last relevel(); of them, the first whose up came
     * since. */
    std::size_t m_gated_upto{0};
    std::size_t m_ungated_from{static_cast<std::size_t>(-1)};
    std::vector<std::unique_ptr<Registration>> m_pool;      // gated, waiting for consensus
    std::vector<std::unique_ptr<Registration>> m_accepted;  // recent loop edges, for consensus
    Stats m_stats;
    std::vector<LoopEdge> m_edges;  // every accepted one; those dropped out at close()
    std::vector<bool> m_dropped;    // per m_edges
    // Published.
    mutable std::mutex m_out_mutex;
    std::vector<KeyframePose> m_published;
    double m_ms_per_keyframe{0};  // recent, of update()
    std::vector<std::pair<std::size_t, std::size_t>> m_published_loops;
    std::string m_published_unreliable;
};

}  // namespace emslam::slam
