// SPDX-License-Identifier: BSD-3-Clause
// Per-frame cost of the egomotion stages (§2.1) between two consecutive real
// KITTI 06 frames (0 and 1), single-threaded, at the paper's 320x240 and at
// KITTI's full 1226x370; and one sequential step (frame 2 after 0 and 1) with
// the paper's full search and with guided matching. Run: bench_egomotion [--benchmark_filter=...]
// Needs the KITTI excerpt (EMSLAM_TEST_DATA, default ../shared/data).
#include "BenchCommon.h"

#include <emslam/egomotion/DppPoseEstimator.h>
#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/egomotion/FeatureMatcher.h>
#include <emslam/egomotion/LwoRefinement.h>
#include <emslam/egomotion/StereoReprojectionRefinement.h>
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/stereo/StereoFrontEnd.h>

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>

namespace
{
using emslam::egomotion::EgomotionEstimator;
using emslam::stereo::StereoFrame;

/** KITTI 06 frame `idx` through the stereo front-end, optionally as a
 * central 4:3 crop resized to width x height (as bench_stereo_frontend does).
 * Null if the data is absent. */
std::shared_ptr<StereoFrame> kittiFrame(int idx, int width, int height)
{
    const auto obs = emslam::bench::kittiObservation(idx, width, height);
    if (!obs)
    {
        return nullptr;
    }
    emslam::stereo::StereoMatcher::TParameters p;
    p.num_disparities = width > 0 ? 64 : 128;
    p.min_range = 1.0;
    p.max_range = 20.0;  // as config/odometry/kitti.ini
    return std::make_shared<StereoFrame>(emslam::stereo::StereoFrontEnd(p).process(*obs));
}

struct Pair
{
    std::shared_ptr<StereoFrame> prev, cur;
    std::vector<mrpt::math::TPoint3Df> a, b;    //!< matched points (before LWO)
    std::vector<mrpt::math::TPoint3Df> ka, kb;  //!< after LWO
};

/** Frames 0 and 1 with their matches, computed once per size. */
const Pair* kittiPair(int width, int height)
{
    static std::map<int, std::unique_ptr<Pair>> cache;
    auto& slot = cache[width];
    if (!slot)
    {
        auto p = std::make_unique<Pair>();
        p->prev = kittiFrame(0, width, height);
        p->cur = kittiFrame(1, width, height);
        if (!p->prev || !p->cur)
        {
            return nullptr;
        }
        const EgomotionEstimator::TParameters ep;
        emslam::egomotion::GlmFeatureExtractor::TParameters gp;
        gp.window_size = ep.window_size;
        const emslam::egomotion::GlmFeatureExtractor glm(gp);
        const emslam::egomotion::LogPolarDescriptorExtractor lp;
        const auto fp = glm.extract(*p->prev), fc = glm.extract(*p->cur);
        const auto matches = emslam::egomotion::matchMutual(
            lp.compute(p->prev->intensity, fp), lp.compute(p->cur->intensity, fc),
            static_cast<float>(ep.similarity_min));
        for (const auto& m : matches)
        {
            p->a.push_back(fp[static_cast<std::size_t>(m.prev)].point);
            p->b.push_back(fc[static_cast<std::size_t>(m.cur)].point);
        }
        const auto lwo = emslam::egomotion::refineLwo(p->a, p->b, ep.lwo_sigma_min);
        for (int i : lwo.kept)
        {
            p->ka.push_back(p->a[static_cast<std::size_t>(i)]);
            p->kb.push_back(p->b[static_cast<std::size_t>(i)]);
        }
        slot = std::move(p);
    }
    return slot.get();
}

void runLwo(benchmark::State& state, const Pair* p)
{
    if (!p)
    {
        state.SkipWithError("test data not found (set EMSLAM_TEST_DATA)");
        return;
    }
    for (auto _ : state)
    {
        auto r = emslam::egomotion::refineLwo(p->a, p->b, 0.005);
        benchmark::DoNotOptimize(r);
    }
    state.counters["matches"] = static_cast<double>(p->a.size());
    state.counters["kept"] = static_cast<double>(p->ka.size());
}

void runPose(benchmark::State& state, const Pair* p, bool joint_refinement = false)
{
    if (!p || p->ka.size() < 3)
    {
        state.SkipWithError("test data not found (set EMSLAM_TEST_DATA)");
        return;
    }
    emslam::egomotion::DppPoseEstimator::TParameters params;
    params.joint_refinement = joint_refinement;
    const emslam::egomotion::DppPoseEstimator est(params);
    int evals = 0;
    for (auto _ : state)
    {
        auto r = est.estimate(p->ka, p->kb);
        evals = r.evaluations;
        benchmark::DoNotOptimize(r);
    }
    state.counters["pairs"] = static_cast<double>(p->ka.size());
    state.counters["evaluations"] = evals;
}

/** The stereo reprojection refinement alone, from the Dpp's pose
 * ([EgomotionEstimator] reprojection_refinement). */
void runReprojection(benchmark::State& state, const Pair* p)
{
    if (!p || p->ka.size() < 4)
    {
        state.SkipWithError("test data not found (set EMSLAM_TEST_DATA)");
        return;
    }
    using emslam::egomotion::StereoReprojectionRefinement;
    const auto start = emslam::egomotion::DppPoseEstimator().estimate(p->ka, p->kb).T_prev_cur;
    const double baseline = emslam::stereo::baselineOf(p->cur->camera);
    const double focal = p->cur->camera.leftCamera.fx();
    StereoReprojectionRefinement::Result r;
    for (auto _ : state)
    {
        r = StereoReprojectionRefinement::refine(p->ka, p->kb, start, baseline, focal);
        benchmark::DoNotOptimize(r);
    }
    state.counters["pairs"] = static_cast<double>(r.pairs);
    state.counters["evaluations"] = r.evaluations;
}

/** Stages 1-5: features, descriptors (of both frames), matching, LWO, pose. */
void runEstimate(benchmark::State& state, const Pair* p)
{
    if (!p)
    {
        state.SkipWithError("test data not found (set EMSLAM_TEST_DATA)");
        return;
    }
    const EgomotionEstimator em;
    emslam::egomotion::EgomotionResult r;
    for (auto _ : state)
    {
        r = em.estimate(*p->prev, *p->cur);
        benchmark::DoNotOptimize(r);
    }
    state.counters["final_matches"] = static_cast<double>(r.final_matches);
    state.counters["ms_features"] = r.ms_features;
    state.counters["ms_descriptors"] = r.ms_descriptors;
    state.counters["ms_matching"] = r.ms_matching;
    state.counters["ms_lwo"] = r.ms_lwo;
    state.counters["ms_pose"] = r.ms_pose;
}

/** One sequential step, as the mapper runs it: process() of frame 2 after
 * frames 0 and 1 (which give guided matching its constant-velocity
 * prediction): describing frame 2, matching, LWO, pose. */
void runProcess(benchmark::State& state, int width, int height, bool guided)
{
    const auto f0 = kittiFrame(0, width, height), f1 = kittiFrame(1, width, height),
               f2 = kittiFrame(2, width, height);
    if (!f0 || !f1 || !f2)
    {
        state.SkipWithError("test data not found (set EMSLAM_TEST_DATA)");
        return;
    }
    EgomotionEstimator::TParameters p;
    p.guided_matching = guided;
    emslam::egomotion::EgomotionResult r;
    for (auto _ : state)
    {
        state.PauseTiming();
        EgomotionEstimator em(p);
        em.process(*f0);
        em.process(*f1);
        state.ResumeTiming();
        r = em.process(*f2);
        benchmark::DoNotOptimize(r);
    }
    state.counters["guided"] = r.guided ? 1 : 0;
    state.counters["final_matches"] = static_cast<double>(r.final_matches);
    state.counters["ms_matching"] = r.ms_matching;
}

void BM_Kitti320x240_Lwo(benchmark::State& s)
{
    runLwo(s, kittiPair(320, 240));
}
void BM_Kitti320x240_Pose(benchmark::State& s)
{
    runPose(s, kittiPair(320, 240));
}
void BM_Kitti320x240_PoseJointRefinement(benchmark::State& s)
{
    runPose(s, kittiPair(320, 240), true);
}
void BM_Kitti320x240_PoseReprojection(benchmark::State& s)
{
    runReprojection(s, kittiPair(320, 240));
}
void BM_Kitti320x240_Estimate(benchmark::State& s)
{
    runEstimate(s, kittiPair(320, 240));
}
void BM_KittiFull_Lwo(benchmark::State& s)
{
    runLwo(s, kittiPair(0, 0));
}
void BM_KittiFull_Pose(benchmark::State& s)
{
    runPose(s, kittiPair(0, 0));
}
void BM_KittiFull_PoseReprojection(benchmark::State& s)
{
    runReprojection(s, kittiPair(0, 0));
}
void BM_KittiFull_Estimate(benchmark::State& s)
{
    runEstimate(s, kittiPair(0, 0));
}
}  // namespace

BENCHMARK_CAPTURE(runProcess, Kitti320x240_FullSearch, 320, 240, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(runProcess, Kitti320x240_Guided, 320, 240, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(runProcess, KittiFull_FullSearch, 0, 0, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(runProcess, KittiFull_Guided, 0, 0, true)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Kitti320x240_Lwo)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Kitti320x240_Pose)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Kitti320x240_PoseJointRefinement)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Kitti320x240_PoseReprojection)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Kitti320x240_Estimate)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KittiFull_Lwo)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KittiFull_Pose)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KittiFull_PoseReprojection)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KittiFull_Estimate)->Unit(benchmark::kMillisecond);

EMSLAM_BENCHMARK_MAIN();
