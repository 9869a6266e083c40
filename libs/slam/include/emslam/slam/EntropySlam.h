// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/maps/CEntropyVoxelMap.h>
#include <emslam/rectify/ActionCovariance.h>
#include <emslam/rectify/RectificationRunner.h>
#include <emslam/rectify/RectifierOptions.h>
#include <emslam/rectify/SpaceSampler.h>
#include <emslam/slam/BackgroundWorker.h>
#include <emslam/slam/CMapSession.h>
#include <emslam/slam/FrameRecord.h>
#include <emslam/slam/FusedPointCloud.h>
#include <emslam/slam/IntensityCloud.h>
#include <emslam/slam/KeyframeClouds.h>
#include <emslam/slam/LoopCloser.h>
#include <emslam/slam/OccupancyGridBuilder.h>
#include <emslam/slam/OctoMapBuilder.h>
#include <emslam/slam/Relocalizer.h>
#include <emslam/slam/StereoOdometry.h>
#include <emslam/stereo/StereoFrontEnd.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <deque>
#include <functional>
#include <future>
#include <limits>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace emslam::slam
{
/** The whole SLAM pipeline of the paper, one frame at a time (the data flow
 * of the design): stereo front-end → egomotion (§2.1) → space sampling
 * (§2.2.4) → trajectory with global rectification, serial or AnyTime, and
 * compression (§2.2.3-2.2.4). MapperApp feeds it from a rawlog and writes its
 * results.
 *
 * Frames whose egomotion fails keep the previous pose (the action is taken
 * as the identity) and are counted; the next step is measured from them.
 *
 * Every frame gets a SLAM pose: the frames space sampling accepts (the
 * keyframes) are rectified; any other frame is placed by its egomotion relative
 * to the keyframe it was measured from: T_world_frame = T_world_keyframe
 * (rectified) ⊕ T_keyframe_frame (the egomotion steps since that keyframe). A
 * frame whose egomotion failed therefore sits where the frame before it sits.
 * \ingroup emslam_slam_grp \sa MapperApp */
class EntropySlam
{
public:
    /** `[EntropySlam]`: what EntropySlam keeps besides the paper's parameters. */
    struct TOptions : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws std::invalid_argument naming the key of a bad value. */
        void validate() const;

        /** Egomotion and space sampling only; the entropy map is still built
         * (energy of the egomotion map) but never rectified. (Default: false) */
        bool egomotion_only{false};
        /** Cell size of the map.ply / map.3Dscene cloud [m]: each accepted
         * frame keeps one point per cell, so does each trajectory element
         * once compression has fused frames into it, and so does the final
         * map (≤ 0: every point, and memory grows with the sequence).
         * (Default: 0.1) */
        double map_cell_size{0.1};
        /** Ceiling cut of map.3Dscene and map_top.png [m]: cloud points
         * higher than this above the first camera (along its −y, the
         * world's up) are left out, so the floor plan shows from above.
         * E.g. a camera 1.2 m above the floor under a 3 m ceiling: 1.5.
         * `inf` (or absent): no cut. map.ply always keeps every point.
         * (Default: inf) */
        double export_max_height{std::numeric_limits<double>::infinity()};
        /** Disparity noise σ_d [px] of the stereo points: a point at depth z
         * has σ_z = z² σ_d / (f b) along its ray (DepthNoiseModel).
         * (Default: 0.2) */
        double depth_sigma_px{0.2};
        /** σ_z = k z² of RGB-D points (no baseline) [1/m]. (Default: 0.0015) */
        double rgbd_depth_sigma{0.0015};
        /** Cell of the fused map [m]: the keyframes' points are fused into
         * one point per cell weighted by 1/σ² (FusedPointCloud). map.ply,
         * map.3Dscene, map_top.png, the grid and map.bt use it. (Default: 0.1) */
        double fused_voxel_size{0.1};
        /** [m] fused points whose σ is above this are left out of the map
         * (inf: none). (Default: 0.05) */
        double max_point_sigma{0.05};
        /** [m] points whose own σ is above this are not fused at all (inf:
         * all). (Default: 0.5) */
        double max_observation_sigma{0.5};
        /** Points join the strongest voxel along their own ray within ±2σ
         * (FusedPointCloud). (Default: true) */
        bool fuse_along_rays{true};
        /** [MB] memory of the keyframes' clouds kept for the final map
         * (KeyframeClouds): past it, only every 2nd, 4th, ... keyframe keeps
         * its cloud (0: no limit). (Default: 64) */
        double max_map_clouds_mb{64};

        /** The fusion's options from these keys. */
        FusedPointCloud::TOptions fusionOptions() const;
        /** max_map_clouds_mb in bytes (0: no limit). */
        std::size_t mapCloudsBytes() const;
    };

    /** Every parameter the mapper uses, one INI section each. */
    struct TParameters
    {
        emslam::stereo::StereoMatcher::TParameters stereo;             //!< [StereoMatcher]
        emslam::egomotion::EgomotionEstimator::TParameters egomotion;  //!< [EgomotionEstimator]
        emslam::CEntropyVoxelMap::TCreationOptions map;                //!< [EntropyVoxelMap]
        emslam::CEntropyVoxelMap::TInsertionOptions insertion;         //!< [EntropyVoxelMap]
        emslam::rectify::SpaceSampler::TParameters sampling;           //!< [SpaceSampler]
        emslam::rectify::TRectifierOptions rectifier;                  //!< [Rectifier]
        TOptions mapper;                                               //!< [EntropySlam]
        LoopCloser::TParameters loop_closer;                           //!< [LoopCloser]
        OccupancyGridBuilder::TParameters occupancy_grid;              //!< [OccupancyGridBuilder]
        OctoMapBuilder::TParameters octomap;                           //!< [OctoMapBuilder]

        /** Loads every section (missing keys keep their defaults) and
         * validates; throws std::invalid_argument naming the section and key
         * of a bad value. */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& c);
        /** Saves every section, every key. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& c) const;
    };

    /** A mapper with the parameters `p`. */
    explicit EntropySlam(const TParameters& p);
    ~EntropySlam();
    EntropySlam(const EntropySlam&) = delete;
    EntropySlam& operator=(const EntropySlam&) = delete;

    /** What process() throws for an observation the stereo front-end
     * cannot use (no right image, images of different sizes, missing or
     * invalid calibration, ...): the mapper is left as it was, so the caller
     * may skip the observation and go on. */
    class UnusableObservation : public std::runtime_error
    {
    public:
        using std::runtime_error::runtime_error;
    };

    /** Processes one observation. Returns false (and does nothing) if it is
     * neither stereo nor RGB-D. Throws UnusableObservation (and changes
     * nothing) on one the front-end cannot use; any other exception leaves
     * the mapper fit only for finish(). */
    bool process(const mrpt::obs::CObservation& obs);

    /** Ends the run: syncs the rectifier, runs the final rectification and
     * builds the outputs. Idempotent; process() throws afterwards. */
    void finish();

    /** How a run uses a saved session (continueSession()). */
    enum class SessionUse
    {
        /** The run goes on with the session: its frames come first in every
         * result, the new keyframes join its pose graph, loops close across
         * both, and session() saves the whole. */
        Continue,
        /** The run is tracked in the session's map, which no solve moves;
         * the results hold the run's frames only, in the session's world. */
        Localize
    };
    /** Before the first process(): the run starts in `session` (saved by
     * session() of an earlier run). Its first frames are located in the
     * saved map by their look (Relocalizer); frames before the first one
     * located are placed from it by the egomotion, and their clouds are left
     * out of the map. Needs loop closing ([LoopCloser] enabled) and
     * rectification; throws std::invalid_argument otherwise, and
     * std::logic_error after process(). */
    void continueSession(std::shared_ptr<const CMapSession> session, SessionUse use);
    /** After finish(): the run as a session to save (with the session it
     * continued, if any). Throws std::logic_error before finish(), in
     * Localize use, without loop closing or without a keyframe. */
    CMapSession::Ptr session() const;
    /** Where the run was located in its session: the frame (as in frames())
     * and the fix (none yet, or no session). */
    struct Relocalization
    {
        std::size_t frame_index{0};    //!< as in frames()
        std::size_t frames_before{0};  //!< frames of the run processed before it
        Relocalizer::Fix fix;          //!< the registration that placed it
    };
    /** See Relocalization. */
    const std::optional<Relocalization>& relocalization() const { return m_relocalization; }
    /** Frames of the continued session at the start of frames() (0 unless
     * SessionUse::Continue). */
    std::size_t sessionFrames() const { return m_session_frames; }

    /** What says "stop soon" (e.g. a signal): while it returns true, the
     * background loop closing only places the keyframes and finish() skips
     * the loop closer's polish, so an interrupted run ends within a second.
     * Called from the loop-closing thread too; set it before the first
     * process(). */
    void setStopCheck(std::function<bool()> stop) { m_stop_check = std::move(stop); }

    /** The parameters it runs with. */
    const TParameters& parameters() const { return m_p; }

    /** Frames in frames(): those processed (stereo or RGB-D observations)
     * and, continuing a session, the session's before them. */
    std::size_t frameCount() const { return m_records.size(); }
    /** Frames this run processed (frameCount() without the session's). */
    std::size_t runFrameCount() const { return m_records.size() - m_session_frames; }
    /** Frames accepted into the trajectory. */
    std::size_t acceptedCount() const { return m_sampler.accepted(); }
    /** Steps whose egomotion failed. */
    std::size_t egomotionFailures() const { return m_odometry.failures(); }
    /** Why the estimate is not to be trusted so far (empty: no reason
     * known): the loop closing's contradictions (LoopCloser::unreliable()),
     * or more than 2 % of the egomotion's steps failed, i.e. guessed at
     * constant velocity: the drift of that share of the path is not
     * measured. Producer thread. */
    std::vector<std::string> unreliableReasons() const;
    /** Successful steps matched near the constant-velocity prediction, and
     * steps whose guided attempt fell back to the full search
     * ([EgomotionEstimator] guided_matching; both 0 without it). */
    ///@{
    std::size_t guidedSteps() const { return m_odometry.guidedSteps(); }
    std::size_t guidedFallbacks() const { return m_odometry.guidedFallbacks(); }
    ///@}
    /** One record per processed frame. */
    const std::vector<FrameRecord>& frames() const { return m_records; }
    /** Energy of the map after the last rectification (or of the unrectified
     * map in egomotion-only mode); 0 before any (see hasEnergy()). */
    double currentEnergy() const { return m_energy; }
    /** True once currentEnergy() holds an energy (after the first
     * rectification, or finish()). */
    bool hasEnergy() const { return m_has_energy; }

    /** Size of the frames as processed (after any stereo scaling) [px]; 0 before the first. */
    ///@{
    int imageWidth() const { return m_image_width; }
    int imageHeight() const { return m_image_height; }
    ///@}

    /** Egomotion pose of every processed frame (T_world_cam, world = first camera). */
    const std::vector<emslam::rectify::TimedPose>& egomotionPoses() const { return m_egomotion; }

    /** @name Live state, for viewers (valid until the next process())
     * @{ */
    /** Reference (left) image of the last processed frame (shares its
     * pixels; empty before the first frame). */
    const cv::Mat& lastImage() const { return m_last_image; }
    /** A keyframe's map cloud, in its own camera frame. */
    struct AddedCloud
    {
        std::size_t frame_index{0};  //!< as in frames()
        IntensityCloud cloud;        //!< in the keyframe's camera frame
    };
    /** The map clouds of the keyframes the last process() (or finish())
     * added to the map, oldest first (often none or one): the frame just
     * processed, or with a sparse front-end ([StereoMatcher]
     * sparse_at_features) keyframes before it, whose dense clouds were
     * computed meanwhile on another thread. */
    const std::vector<AddedCloud>& addedClouds() const { return m_added_clouds; }
    /** World poses of the keyframes in the current estimate (a copy): with
     * loop closing, every loop closed so far (keyframes the background has
     * not reached yet left out); without, as rectified so far (AnyTime:
     * buffered frames not yet included). */
    std::vector<emslam::rectify::TimedPose> currentSlamPoses() const;
    /** The loops closed in the current estimate (a copy): for each, the
     * frame indices (as in frames()) of the two keyframes it joins; empty
     * without loop closing. */
    std::vector<std::pair<std::size_t, std::size_t>> currentLoops() const
    {
        return m_loops.currentLoops();
    }
    /** For each processed frame, the pose the system had for it when it
     * was processed (causal): the latest keyframe of the current estimate
     * and the egomotion since. */
    const std::vector<emslam::rectify::TimedPose>& onlinePoses() const { return m_online; }
    /** @} */

    /** @name Results, valid after finish()
     * @{ */
    /** Every processed frame, in order: keyframes at their rectified poses,
     * the other frames placed from their keyframe by the egomotion (see the
     * class comment). */
    const std::vector<emslam::rectify::TimedPose>& slamPoses() const { return m_slam; }
    /** The keyframes (accepted frames) only, at their rectified poses. */
    const std::vector<emslam::rectify::TimedPose>& keyframePoses() const { return m_keyframe_slam; }
    /** Frame indices (as in frames()) of the keyframes, increasing. */
    const std::vector<std::size_t>& keyframes() const { return m_keyframes; }
    /** Every rectification run. */
    const std::vector<emslam::rectify::RectificationStats>& rectifications() const
    {
        return m_rectifications;
    }
    /** The entropy map of the final trajectory. */
    const emslam::CEntropyVoxelMap& entropyMap() const;
    /** The final (compressed) trajectory: actions, elements and their frames. */
    const emslam::rectify::Trajectory& trajectory() const;
    /** The map cloud (with grey levels) at the final poses, world frame: the
     * accepted frames' points fused per `fused_voxel_size` cell weighted by
     * their depth uncertainty, and gated by `max_point_sigma`
     * (FusedPointCloud); each point's sigma is its fused σ. Kept per
     * keyframe during the run (KeyframeClouds), so that each keyframe's
     * points land at its own final pose. */
    const IntensityCloud& mapCloud() const { return m_map_cloud; }
    /** The clouds mapCloud() was made of, each in the camera frame of its
     * keyframe, with the sigma of each point, before fusion (points above
     * `max_observation_sigma` are not kept). */
    const std::vector<KeyframeScan>& keyframeScans() const { return m_keyframe_scans; }
    /** keyframeScans() with each point moved to the fused point it joined
     * and the points of gated voxels left out (scansOnFusedSurfaces()):
     * scans to insert from keyframePoses() (map.bt, OctoMapBuilder). */
    const std::vector<KeyframeScan>& fusedKeyframeScans() const { return m_fused_scans; }
    /** 1, or the keyframes per cloud kept for the map once
     * `max_map_clouds_mb` thinned them (KeyframeClouds::stride()). */
    std::size_t mapCloudsStride() const { return m_map_clouds_stride; }
    /** What the map's fusion counted. */
    const FusedPointCloud::Stats& fusionStats() const { return m_fusion_stats; }
    /** Final energy (recomputed from scratch): the entropy plus the odometry
     * prior's cost, if `[Rectifier] prior_weight` > 0. */
    double finalEnergy() const { return m_energy; }
    /** The entropy part of finalEnergy() (the paper's energy; what
     * entropyMap().energy() gives). */
    double finalEntropy() const { return m_entropy; }
    /** The loop closer ([LoopCloser]): its statistics and accepted edges
     * after finish() (none unless enabled). */
    const LoopCloser& loopCloser() const { return m_loops; }
    /** Elements N and trajectory compressions at the end. */
    std::size_t trajectoryElements() const;
    std::size_t compressions() const;
    /** @} */

private:
    /** A keyframe whose map cloud is being computed on another thread. */
    /** What the map takes of a keyframe's cloud: the points the entropy map
     * weighs and the downsampled cloud of the map outputs. Pure functions of
     * the cloud, so the sparse front-end's map task computes them on its own
     * thread, beside the frame loop. */
    struct MapClouds
    {
        emslam::maps::WeightedPointCloud weighted;
        IntensityCloud downsampled;
    };
    MapClouds mapClouds(const emslam::stereo::StereoFrame& f) const;
    /** A keyframe's dense cloud with its map clouds (from the map task). */
    struct DenseKeyframe
    {
        emslam::stereo::StereoFrame frame;
        MapClouds clouds;
    };
    struct PendingKeyframe
    {
        std::size_t index{0};
        double timestamp{0};
        mrpt::poses::CPose3D action;  //!< since the previous keyframe
        emslam::rectify::ActionCovariance covariance;
        std::future<DenseKeyframe> cloud;
    };
    /** Adds the pending keyframes' clouds in order: those ready, and while
     * more than `keep` are pending, waits for the oldest. Their times go to
     * `record` (if given). */
    void completePendingKeyframe(FrameRecord* record, std::size_t keep = 0);
    /** The front-end's step; false: no frame yet. Throws UnusableObservation
     * for what the front-end cannot use. */
    bool runOdometry(const mrpt::obs::CObservation& obs, StereoOdometry::Step& step);
    /** The step's matches, success and sigmas go to `r` (a predicted step
     * marks the keyframe interval); returns the step's covariance (the
     * prior's, a failed step's wide one, or the Dpp's). */
    emslam::rectify::ActionCovariance recordStep(const StereoOdometry::Step& step, FrameRecord& r);
    /** Frame `r` was accepted: to the loop closer, then to the map (now, or
     * when the front-end's map task ends). */
    void addKeyframe(
        const emslam::stereo::StereoFrame& f,
        const emslam::rectify::ActionCovariance& cov_since_keyframe,
        const mrpt::poses::CPose3D& motion_since_keyframe,
        FrameRecord& r);
    void addAccepted(
        const emslam::stereo::StereoFrame& f, MapClouds clouds, const PendingKeyframe& k);
    bool loopClosing() const { return m_loop_worker != nullptr; }
    /** With a session not yet located: tries frame `r` (its egomotion pose
     * is the last); true once the run is located, at this frame or before. */
    bool relocalize(FrameRecord& r);
    /** The keyframe poses for LoopCloser::close(): the session's, then the
     * run's rectified `poses` moved into the session's world. */
    std::vector<emslam::rectify::TimedPose> withSessionKeyframes(
        const std::vector<emslam::rectify::TimedPose>& poses) const;
    /** Whether loop-closer frame `index` is a frame of this run. */
    bool ofThisRun(std::size_t index) const
    {
        return index >= m_session_frames && index < m_records.size();
    }
    /** The online pose of frame `index` (see onlinePoses()). */
    mrpt::poses::CPose3D onlinePose(std::size_t index);

    TParameters m_p;
    StereoOdometry m_odometry;
    emslam::rectify::SpaceSampler m_sampler;
    std::unique_ptr<emslam::rectify::RectificationRunner> m_runner;
    LoopCloser m_loops;
    /** The loop closer's own: estimate() of two descriptions only reads it. */
    emslam::egomotion::EgomotionEstimator m_loop_estimator;
    std::function<bool()> m_stop_check;
    /** Runs m_loops.update() beside the frames; after m_loops, so it stops first. */
    std::unique_ptr<BackgroundWorker> m_loop_worker;
    std::vector<emslam::rectify::TimedPose> m_online;
    /** Without loop closing: the last rectified keyframe, and how many
     * rectifications it is from. */
    std::optional<emslam::rectify::TimedPose> m_rectified_anchor;
    std::size_t m_anchor_rectifications{0};
    /** Rectifications whose poses the loop closer was given. */
    std::size_t m_rectifications_sent{0};
    std::vector<emslam::rectify::TimedPose> m_egomotion, m_slam, m_keyframe_slam;
    /** Where a frame is measured from: its keyframe and the egomotion since. */
    struct KeyframeLink
    {
        std::size_t keyframe{0};
        mrpt::poses::CPose3D T_keyframe_frame;
    };
    std::vector<KeyframeLink> m_links;  //!< one per processed frame
    mrpt::poses::CPose3D m_T_keyframe_cur;
    /** The egomotion's covariance of m_T_keyframe_cur (zero at a keyframe). */
    emslam::rectify::ActionCovariance m_cov_keyframe_cur;
    /** A step since the last keyframe was predicted (the egomotion failed). */
    bool m_predicted_since_keyframe{false};
    std::size_t m_last_keyframe{0};
    std::vector<std::size_t> m_keyframes;
    std::vector<FrameRecord> m_records;
    double m_energy{0.0};
    bool m_has_energy{false};
    double m_entropy{0.0};
    /** The map clouds of the keyframes, kept apart until the end. */
    KeyframeClouds m_clouds;
    std::size_t m_map_clouds_stride{1};
    std::vector<KeyframeScan> m_keyframe_scans, m_fused_scans;
    FusedPointCloud::Stats m_fusion_stats;
    std::vector<AddedCloud> m_added_clouds;  //!< by the last process() or finish()
    std::deque<PendingKeyframe> m_pending;   //!< oldest first
    IntensityCloud m_map_cloud;
    std::vector<emslam::rectify::RectificationStats> m_rectifications;
    int m_image_width{0}, m_image_height{0};
    cv::Mat m_last_image;
    bool m_finished{false};
    // A session the run continues or is localized in.
    std::shared_ptr<const CMapSession> m_session;
    SessionUse m_session_use{SessionUse::Continue};
    std::size_t m_session_frames{0};  //!< its frames in m_records (Continue)
    /** Added to the session's frame indices in the loop closer (Localize:
     * beyond any frame of the run). */
    std::size_t m_session_offset{0};
    std::unique_ptr<Relocalizer> m_relocalizer;  //!< until the run is located
    std::optional<Relocalization> m_relocalization;
    std::vector<std::size_t> m_unlocated;  //!< frames of the run before it
    /** Session world from the run's egomotion world (identity without a session). */
    mrpt::poses::CPose3D m_T_session_run;
    /** The first keyframe's motion from the session's last, and its covariance. */
    std::optional<std::pair<mrpt::poses::CPose3D, emslam::rectify::ActionCovariance>> m_junction;
};

}  // namespace emslam::slam
