// SPDX-License-Identifier: BSD-3-Clause
// A drifting square loop whose last keyframes see the first keyframes' places
// again, and a look-alike place just before them.
#include "PoseLoops.h"
#include "SyntheticStereo.h"
#include "TestData.h"

#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/rectify/ActionCovariance.h>
#include <emslam/sim/StereoSimulator.h>
#include <emslam/slam/LoopCloser.h>
#include <emslam/stereo/StereoFrontEnd.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <vector>

using emslam::egomotion::EgomotionEstimator;
using emslam::rectify::ActionCovariance;
using emslam::rectify::diagonalCovariance;
using emslam::slam::LoopCloser;
using emslam::test::distance;
using emslam::test::positionRmse;
using mrpt::poses::CPose3D;

namespace
{
/** Loop closing by proximity alone, without local edges: what these tests
 * measure unless they say otherwise (the defaults add both). */
LoopCloser::TParameters proximityOnly()
{
    LoopCloser::TParameters p;
    p.local_edges = 0;
    p.place_candidates = 0;
    return p;
}

/** The description of a frame showing texture `seed` (a tilted plane). */
EgomotionEstimator::Description describe(EgomotionEstimator& e, unsigned seed)
{
    auto f = emslam::test::frameWithImage(emslam::test::noiseImage(160, 120, seed));
    for (std::size_t i = 0; i < f.points.size(); ++i)
    {
        f.points[i].z = 3.0f + 0.01f * f.pixels[i].u;
    }
    e.reset();
    e.process(f);
    return e.lastDescription();
}

struct LoopRun
{
    std::vector<CPose3D> truth, drifted, closed;
};

/** Keyframes round the loop (`steps` steps, 40 a lap) with `textures[k]`
 * seen from keyframe k (0: no description), odometry turning 0.15° too far
 * per step (6° a lap, within the three sigmas of its covariance). */
LoopRun runLoop(LoopCloser& closer, const std::map<std::size_t, unsigned>& textures, int steps = 43)
{
    LoopRun run;
    run.truth = emslam::test::squareLoop(steps);
    EgomotionEstimator e;
    const ActionCovariance step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(1.0));
    run.drifted.push_back(CPose3D());
    for (std::size_t k = 0; k < run.truth.size(); ++k)
    {
        if (k > 0)
        {
            run.drifted.push_back(
                run.drifted.back() + (run.truth[k] - run.truth[k - 1]) +
                CPose3D(0, 0, 0, 0, mrpt::DEG2RAD(0.15), 0));
        }
        const auto it = textures.find(k);
        closer.addKeyframe(k, it == textures.end() ? nullptr : describe(e, it->second), step_cov);
    }
    run.closed = closer.close(run.drifted, e);
    return run;
}
}  // namespace

TEST(LoopCloser, closesTheLoopWhereTheFirstPlacesAreSeenAgain)
{
    LoopCloser::TParameters p = proximityOnly();
    p.enabled = true;
    LoopCloser closer(p);
    // Keyframes 0 and 40 see one place, 1 and 41 another; every other
    // keyframe sees a texture of its own.
    std::map<std::size_t, unsigned> textures;
    for (std::size_t k = 0; k < 44; ++k)
    {
        textures[k] = static_cast<unsigned>(100 + k);
    }
    textures[40] = 100;
    textures[41] = 101;
    const LoopRun run = runLoop(closer, textures);
    const double gap_before = distance(run.drifted[40], run.drifted[0]);
    const double gap_after = distance(run.closed[40], run.closed[0]);
    const double rmse_before = positionRmse(run.drifted, run.truth);
    const double rmse_after = positionRmse(run.closed, run.truth);
    const auto& s = closer.stats();
    std::printf(
        "loop: gap %.3f -> %.3f m, RMSE %.3f -> %.3f m; %zu candidates, %zu registrations, %zu "
        "loop edges, %.0f ms\n",
        gap_before, gap_after, rmse_before, rmse_after, s.candidates, s.registrations, s.loop_edges,
        s.ms);
    ASSERT_GT(gap_before, 0.5);
    EXPECT_LT(gap_after, 0.05);
    EXPECT_LT(rmse_after, 0.25 * rmse_before);
    ASSERT_EQ(closer.loopEdges().size(), 2u);
    for (const auto& e : closer.loopEdges())
    {
        EXPECT_EQ(e.frame_to - e.frame_from, 40u);
        EXPECT_LT(e.measurement.norm(), 1e-3);  // the same view: identity
    }
    EXPECT_TRUE(s.unreliable.empty()) << s.unreliable;
}

TEST(LoopCloser, refusesALookAlikePlaceThatDisagreesWithTheRealRevisit)
{
    LoopCloser::TParameters p = proximityOnly();
    p.enabled = true;
    p.max_candidates = 6;  // so that the look-alikes are registered too
    LoopCloser closer(p);
    std::map<std::size_t, unsigned> textures;
    for (std::size_t k = 0; k < 40; ++k)
    {
        textures[k] = static_cast<unsigned>(100 + k);
    }
    // Keyframes 40 and 41 see the places of 0 and 1 again; 42 and 43, two
    // metres further, look exactly like them too (a repeated wallpaper):
    // registered, they would pull the loop's end two metres back.
    textures[40] = 100;
    textures[41] = 101;
    textures[42] = 100;
    textures[43] = 101;
    const LoopRun run = runLoop(closer, textures);
    // The look-alikes are registered too, but either disagree with the
    // revisits (whose correction is the smaller) or, once the revisits
    // closed the loop, fall outside the drift left.
    EXPECT_GE(closer.stats().registrations, 4u);
    for (const auto& e : closer.loopEdges())
    {
        EXPECT_EQ(e.frame_to - e.frame_from, 40u) << e.frame_from << " -> " << e.frame_to;
    }
    EXPECT_GE(closer.loopEdges().size(), 2u);
    EXPECT_LT(distance(run.closed[40], run.closed[0]), 0.05);
    EXPECT_TRUE(closer.stats().unreliable.empty()) << closer.stats().unreliable;
}

// A world of one wallpaper, two laps: keyframe k sees texture k mod 3, and a
// lap is 40 keyframes, so the place truly seen again shows another texture
// and every registration is of a look-alike 1 or 2 m away. Consensus groups
// of look-alikes get through; the solved graph contradicts them more often
// than chance and one look-alike place explain (measured: 3 groups refused
// of 25 loop edges): the loop closing says it is unreliable and keeps no
// loop edge.
TEST(LoopCloser, aPeriodicWorldIsUnreliableAndClosesNoLoop)
{
    LoopCloser::TParameters p = proximityOnly();
    p.enabled = true;
    p.max_candidates = 6;
    LoopCloser closer(p);
    constexpr std::size_t PERIOD = 3;
    constexpr int STEPS = 83;
    std::map<std::size_t, unsigned> textures;
    for (std::size_t k = 0; k <= STEPS; ++k)
    {
        textures[k] = static_cast<unsigned>(100 + k % PERIOD);
    }
    const LoopRun run = runLoop(closer, textures, STEPS);
    const auto& s = closer.stats();
    std::printf(
        "periodic: %zu registrations, %zu loop edges, %zu dropped, %zu groups refused (%zu "
        "contradicting, %zu keyframes), %zu withdrawn: %s\n",
        s.registrations, s.loop_edges, s.dropped_edges, s.refused_groups, s.contradicting_groups,
        s.contradicting_keyframes, s.withdrawn_edges, s.unreliable.c_str());
    EXPECT_FALSE(s.unreliable.empty());
    EXPECT_EQ(closer.unreliable(), s.unreliable);
    EXPECT_TRUE(closer.loopEdges().empty());
    EXPECT_EQ(s.loop_edges, 0u);
    // Without loop edges, the poses are the odometry's.
    EXPECT_LT(positionRmse(run.closed, run.drifted), 1e-3);
}

TEST(LoopCloser, withoutRevisitsThePosesStay)
{
    LoopCloser::TParameters p = proximityOnly();
    p.enabled = true;
    LoopCloser closer(p);
    std::map<std::size_t, unsigned> textures;
    for (std::size_t k = 0; k < 44; ++k)
    {
        textures[k] = static_cast<unsigned>(100 + k);
    }
    const LoopRun run = runLoop(closer, textures);
    EXPECT_EQ(closer.stats().loop_edges, 0u);
    for (std::size_t k = 0; k < run.closed.size(); ++k)
    {
        EXPECT_LT(distance(run.closed[k], run.drifted[k]), 1e-12);
    }
    EXPECT_THROW(closer.close({CPose3D()}, EgomotionEstimator()), std::invalid_argument);
}

namespace
{
/** Every second rendered frame of the corridor world (no loop) as a
 * keyframe: its true pose and its description. */
struct CorridorKeyframes
{
    std::vector<CPose3D> truth;
    std::vector<EgomotionEstimator::Description> descriptions;
};

CorridorKeyframes renderCorridorKeyframes(EgomotionEstimator& e, std::size_t count)
{
    emslam::sim::StereoSimulator sim;
    sim.loadFile(emslam::test::sourceDir() + "/config/sim/three_corridors.ini");
    emslam::stereo::StereoFrontEnd front_end;
    CorridorKeyframes out;
    for (std::size_t k = 0; k < count; ++k)
    {
        const auto f = sim.renderFrame(2 * k);
        e.reset();
        e.process(front_end.process(*f.obs));
        out.truth.push_back(f.T_first_left);
        out.descriptions.push_back(e.lastDescription());
    }
    return out;
}

/** The true poses with step `bent` (into keyframe `bent`) 0.3 m and 4 deg off. */
std::vector<CPose3D> withOneBentStep(const std::vector<CPose3D>& truth, std::size_t bent)
{
    const CPose3D error(0.05, 0.0, 0.3, mrpt::DEG2RAD(4.0), 0, 0);
    std::vector<CPose3D> poses{truth.front()};
    for (std::size_t k = 1; k < truth.size(); ++k)
    {
        const CPose3D step = truth[k] - truth[k - 1];
        poses.push_back(poses.back() + (k == bent ? step + error : step));
    }
    return poses;
}
}  // namespace

TEST(LoopCloser, localEdgesRepairABadStepOfAnOpenPath)
{
    // Rendered frames of a corridor world (no loop): every second frame is a
    // keyframe. The odometry between keyframes 5 and 6 is 0.3 m and 4 deg
    // off, with the wide covariance of a failed egomotion step; the direct
    // registrations of the keyframes around it (local_edges) put it right.
    EgomotionEstimator e;
    constexpr std::size_t KEYFRAMES = 12;
    const CorridorKeyframes kf = renderCorridorKeyframes(e, KEYFRAMES);
    const std::vector<CPose3D> odometry = withOneBentStep(kf.truth, 6);
    const ActionCovariance good = diagonalCovariance(0.01, mrpt::DEG2RAD(0.3));
    const ActionCovariance failed = diagonalCovariance(0.5, mrpt::DEG2RAD(10.0));
    for (auto local : {0, 2})
    {
        LoopCloser::TParameters p = proximityOnly();
        p.enabled = true;
        p.local_edges = local;
        LoopCloser closer(p);
        for (std::size_t k = 0; k < KEYFRAMES; ++k)
        {
            closer.addKeyframe(2 * k, kf.descriptions[k], k == 6 ? failed : good);
        }
        const std::vector<CPose3D> closed = closer.close(odometry, e);
        const double before = positionRmse(odometry, kf.truth);
        const double after = positionRmse(closed, kf.truth);
        std::printf(
            "local_edges %d: RMSE %.3f -> %.3f m, %zu of %zu registrations in the graph\n", local,
            before, after, closer.stats().local_edges, closer.stats().local_registrations);
        ASSERT_GT(before, 0.2);
        if (local == 0)
        {
            EXPECT_EQ(closer.stats().local_registrations, 0u);
            EXPECT_LT(std::abs(after - before), 1e-9);
            continue;
        }
        EXPECT_EQ(closer.stats().local_registrations, 2 * KEYFRAMES - 3);
        EXPECT_GE(closer.stats().local_edges, KEYFRAMES);
        EXPECT_LT(after, 0.03);
        EXPECT_LT(distance(closed[6], kf.truth[6]), 0.05);
    }
}

TEST(LoopCloser, localEdgesUndoAStepTheRectifierBent)
{
    // The poses given to close() (the rectified chain) have one step 0.3 m
    // and 4 deg off with a tight covariance, while the egomotion's own
    // motions, given to addKeyframe(), are right: the local registrations
    // agree with the egomotion's chain, so they are kept and repair the
    // bent step. Checked against the given poses instead, 3 of them are
    // refused and the step stays bent.
    EgomotionEstimator e;
    constexpr std::size_t KEYFRAMES = 10;
    const CorridorKeyframes kf = renderCorridorKeyframes(e, KEYFRAMES);
    const std::vector<CPose3D> rectified = withOneBentStep(kf.truth, 5);
    const ActionCovariance tight = diagonalCovariance(0.01, mrpt::DEG2RAD(0.3));
    LoopCloser::TParameters p = proximityOnly();
    p.enabled = true;
    p.local_edges = 2;
    LoopCloser closer(p);
    for (std::size_t k = 0; k < KEYFRAMES; ++k)
    {
        const CPose3D step = k > 0 ? kf.truth[k] - kf.truth[k - 1] : CPose3D();
        closer.addKeyframe(2 * k, kf.descriptions[k], tight, step);
    }
    const std::vector<CPose3D> closed = closer.close(rectified, e);
    const double before = positionRmse(rectified, kf.truth);
    const double after = positionRmse(closed, kf.truth);
    std::printf(
        "rectifier-bent step: RMSE %.3f -> %.3f m, %zu of %zu local registrations in the graph\n",
        before, after, closer.stats().local_edges, closer.stats().local_registrations);
    ASSERT_GT(before, 0.15);
    EXPECT_EQ(closer.stats().local_edges, closer.stats().local_registrations);
    EXPECT_LT(after, 0.5 * before);
}

TEST(LoopCloser, parametersRoundTripAndBadValuesThrow)
{
    LoopCloser::TParameters p;
    p.enabled = false;
    p.min_path_length = 7;
    p.max_distance = 1.5;
    p.max_angle_deg = 20;
    p.max_candidates = 5;
    p.kept_features = 150;
    p.consensus_window = 5;
    p.max_lag = 7;
    p.max_lag_ms = 40;
    p.local_edges = 4;
    p.vertical_prior = true;
    p.vertical.patch_px = 12;
    p.vertical.max_angle_deg = 15;
    p.vertical.min_patches = 6;
    mrpt::config::CConfigFileMemory c;
    p.saveToConfigFile(c, "LoopCloser");
    p.vertical.saveToConfigFile(c, "VerticalFromPlanes");  // EntropySlam's section
    // MRPT 2.5 reads defaults back from the object written: re-parse the text.
    mrpt::config::CConfigFileMemory reparsed(c.getContent());
    LoopCloser::TParameters q;
    q.loadFromConfigFile(reparsed, "LoopCloser");
    q.vertical.loadFromConfigFile(reparsed, "VerticalFromPlanes");
    EXPECT_FALSE(q.enabled);
    EXPECT_DOUBLE_EQ(q.min_path_length, 7);
    EXPECT_DOUBLE_EQ(q.max_distance, 1.5);
    EXPECT_DOUBLE_EQ(q.max_angle_deg, 20);
    EXPECT_EQ(q.max_candidates, 5);
    EXPECT_EQ(q.kept_features, 150);
    EXPECT_EQ(q.consensus_window, 5);
    EXPECT_EQ(q.max_lag, 7);
    EXPECT_DOUBLE_EQ(q.max_lag_ms, 40);
    EXPECT_EQ(q.local_edges, 4);
    EXPECT_TRUE(q.vertical_prior);
    EXPECT_EQ(q.vertical.patch_px, 12);
    EXPECT_DOUBLE_EQ(q.vertical.max_angle_deg, 15);
    EXPECT_EQ(q.vertical.min_patches, 6);
    for (const char* bad :
         {"max_angle_deg = 0", "max_candidates = 0", "kept_features = -1", "consensus_window = 0",
          "max_lag = 0", "max_lag_ms = -1", "max_lag_ms = inf", "min_path_length = -1",
          "max_distance = nan", "local_edges = -1"})
    {
        mrpt::config::CConfigFileMemory b(std::string("[LoopCloser]\n") + bad + "\n");
        LoopCloser::TParameters r;
        EXPECT_THROW(r.loadFromConfigFile(b, "LoopCloser"), std::invalid_argument) << bad;
    }
    for (const char* bad : {"patch_px = 3", "max_angle_deg = 90", "min_patches = 1"})
    {
        mrpt::config::CConfigFileMemory b(std::string("[VerticalFromPlanes]\n") + bad + "\n");
        emslam::stereo::VerticalFromPlanes::TParameters r;
        r.loadFromConfigFile(b, "VerticalFromPlanes");
        EXPECT_THROW(r.validate(), std::invalid_argument) << bad;
    }
}

TEST(LoopCloser, closesTheLoopOnlineBeforeTheEnd)
{
    // The square loop fed as a mapper feeds it: each keyframe with its
    // (drifting) motion, update() after each, as the background thread does.
    LoopCloser::TParameters p = proximityOnly();
    p.enabled = true;
    p.consensus_window = 3;  // the new loop is decided two keyframes after its first registration
    LoopCloser closer(p);
    const std::vector<CPose3D> truth = emslam::test::squareLoop(43);
    EgomotionEstimator e;
    const ActionCovariance step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(1.0));
    std::vector<CPose3D> drifted{CPose3D()};
    double gap_before_revisit = 0;
    for (std::size_t k = 0; k < truth.size(); ++k)
    {
        std::optional<CPose3D> motion;
        if (k > 0)
        {
            motion = (truth[k] - truth[k - 1]) + CPose3D(0, 0, 0, 0, mrpt::DEG2RAD(0.15), 0);
            drifted.push_back(drifted.back() + *motion);
        }
        const unsigned texture = static_cast<unsigned>(100 + (k >= 40 && k <= 41 ? k - 40 : k));
        closer.addKeyframe(k, describe(e, texture), step_cov, motion);
        EXPECT_EQ(closer.update(e), 1u);
        ASSERT_EQ(closer.processedCount(), k + 1);
        if (k == 39)
        {
            gap_before_revisit = distance(closer.currentPoses()[39].pose, truth[39]);
        }
    }
    // Before close(): the current poses already have the loop closed.
    const auto online = closer.currentPoses();
    ASSERT_EQ(online.size(), truth.size());
    const double gap_online = distance(online[40].pose, online[0].pose);
    std::printf(
        "online: keyframe 39 off by %.3f m before the revisit; gap %.3f -> %.3f m\n",
        gap_before_revisit, distance(drifted[40], drifted[0]), gap_online);
    ASSERT_GT(distance(drifted[40], drifted[0]), 0.5);
    EXPECT_LT(gap_online, 0.05);
    EXPECT_EQ(closer.loopEdges().size(), 2u);
    // What a viewer reads from another thread: the same two loops, each
    // joining the revisit (keyframe 40 or 41) to the start.
    const auto loops = closer.currentLoops();
    ASSERT_EQ(loops.size(), closer.loopEdges().size());
    for (std::size_t n = 0; n < loops.size(); ++n)
    {
        EXPECT_EQ(loops[n].first, closer.loopEdges()[n].frame_from);
        EXPECT_EQ(loops[n].second, closer.loopEdges()[n].frame_to);
        EXPECT_GE(std::max(loops[n].first, loops[n].second), 40u);
        EXPECT_LE(std::min(loops[n].first, loops[n].second), 1u);
    }
    EXPECT_LE(closer.stats().kept_bytes, truth.size() * 32u * 1024u);
    // close() polishes what is there: the loop stays closed.
    const auto closed = closer.close(drifted, e);
    EXPECT_LT(distance(closed[40], closed[0]), 0.05);
}

TEST(LoopCloser, aStopMakesUpdatePlaceKeyframesWithoutWork)
{
    LoopCloser::TParameters p = proximityOnly();
    p.enabled = true;
    p.local_edges = 3;
    LoopCloser closer(p);
    EgomotionEstimator e;
    const ActionCovariance step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(1.0));
    for (std::size_t k = 0; k < 10; ++k)
    {
        closer.addKeyframe(
            k, describe(e, 100), step_cov,
            k == 0 ? std::nullopt : std::optional<CPose3D>(CPose3D(0, 0, 0.5, 0, 0, 0)));
    }
    EXPECT_EQ(closer.update(e, [] { return true; }), 10u);
    EXPECT_EQ(closer.stats().local_registrations, 0u);
    EXPECT_EQ(closer.stats().registrations, 0u);
    const auto poses = closer.currentPoses();
    ASSERT_EQ(poses.size(), 10u);
    EXPECT_NEAR(poses[9].pose.z(), 4.5, 1e-9);  // placed by the motions
}

TEST(LoopCloser, theBacklogIsTheKeyframesWaitingTimesTheirRecentCost)
{
    LoopCloser::TParameters p = proximityOnly();
    p.local_edges = 3;  // some work per keyframe: registrations to the ones before
    LoopCloser closer(p);
    EgomotionEstimator e;
    const ActionCovariance step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(1.0));
    std::size_t k = 0;
    const auto add = [&](std::size_t count)
    {
        for (std::size_t n = 0; n < count; ++n, ++k)
        {
            closer.addKeyframe(
                k, describe(e, 100), step_cov,
                k == 0 ? std::nullopt : std::optional<CPose3D>(CPose3D(0, 0, 0.5, 0, 0, 0)));
        }
    };
    add(2);
    EXPECT_EQ(closer.backlogMs(), 0.0);  // no keyframe timed yet
    EXPECT_EQ(closer.update(e), 2u);
    EXPECT_EQ(closer.backlogMs(), 0.0);  // none waiting
    add(2);
    const double two = closer.backlogMs();
    add(2);
    const double four = closer.backlogMs();
    EXPECT_GT(two, 0.0);
    EXPECT_NEAR(four, 2 * two, 1e-9 * two);
    EXPECT_EQ(closer.update(e), 4u);
    EXPECT_EQ(closer.backlogMs(), 0.0);
}

TEST(LoopCloser, prepareToCloseForgetsTheRectifiedPosesWaiting)
{
    // Two closers given the same keyframes and the same rectified poses,
    // which bend the chain: one solves for them, the other was told that
    // close() comes next.
    const auto feed = [](LoopCloser& closer, EgomotionEstimator& e)
    {
        const ActionCovariance step_cov = diagonalCovariance(0.02, mrpt::DEG2RAD(1.0));
        std::vector<LoopCloser::KeyframePose> rectified;
        for (std::size_t k = 0; k < 6; ++k)
        {
            closer.addKeyframe(
                k, describe(e, 100), step_cov,
                k == 0 ? std::nullopt : std::optional<CPose3D>(CPose3D(0.5, 0, 0, 0, 0, 0)));
            rectified.push_back({k, CPose3D(0.5 * k, 0.05 * k * k, 0, 0, 0, 0)});
        }
        EXPECT_EQ(closer.update(e), 6u);
        closer.setRectifiedPoses(rectified);
    };
    EgomotionEstimator e;
    LoopCloser solving(proximityOnly()), closing(proximityOnly());
    feed(solving, e);
    feed(closing, e);
    closing.prepareToClose();
    solving.update(e);
    closing.update(e);
    EXPECT_GT(solving.stats().rounds, 0u);
    EXPECT_EQ(closing.stats().rounds, 0u);
    EXPECT_GT(solving.currentPoses()[5].pose.y(), 0.5);  // bent by the rectified poses
    EXPECT_NEAR(closing.currentPoses()[5].pose.y(), 0.0, 1e-9);
}
