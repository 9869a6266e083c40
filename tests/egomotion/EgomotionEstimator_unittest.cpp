// SPDX-License-Identifier: BSD-3-Clause
#include "SyntheticStereo.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/io/EurocSequence.h>
#include <emslam/io/KittiSequence.h>
#include <emslam/sim/StereoSimulator.h>
#include <emslam/stereo/StereoFrontEnd.h>

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

using emslam::egomotion::EgomotionEstimator;
using emslam::egomotion::EgomotionResult;
using emslam::stereo::StereoFrame;
using emslam::test::frameWithImage;
using emslam::test::noiseImage;
using mrpt::poses::CPose3D;

namespace
{
const char* NON_DEFAULT_INI = R"(
[EgomotionEstimator]
window_size = 6
min_gradient = 12.5
similarity_min = 0.7
lwo_sigma_min = 0.01
min_final_matches = 20
lp_num_rings = 6
lp_num_angles = 12
lp_radius = 10
euclidean_init = false
joint_refinement = true
reprojection_refinement = true
max_lwo_matches = 1500
guided_matching = true
guided_radius = 0.25
experimental_covariance_lwo_truncation = true
experimental_match_distinctiveness = 1.5
)";

void expectEqualParams(
    const EgomotionEstimator::TParameters& a, const EgomotionEstimator::TParameters& b)
{
    EXPECT_EQ(a.window_size, b.window_size);
    EXPECT_DOUBLE_EQ(a.min_gradient, b.min_gradient);
    EXPECT_DOUBLE_EQ(a.similarity_min, b.similarity_min);
    EXPECT_DOUBLE_EQ(a.lwo_sigma_min, b.lwo_sigma_min);
    EXPECT_EQ(a.min_final_matches, b.min_final_matches);
    EXPECT_EQ(a.lp_num_rings, b.lp_num_rings);
    EXPECT_EQ(a.lp_num_angles, b.lp_num_angles);
    EXPECT_DOUBLE_EQ(a.lp_radius, b.lp_radius);
    EXPECT_EQ(a.euclidean_init, b.euclidean_init);
    EXPECT_EQ(a.joint_refinement, b.joint_refinement);
    EXPECT_EQ(a.reprojection_refinement, b.reprojection_refinement);
    EXPECT_EQ(a.max_lwo_matches, b.max_lwo_matches);
    EXPECT_EQ(a.guided_matching, b.guided_matching);
    EXPECT_DOUBLE_EQ(a.guided_radius, b.guided_radius);
    EXPECT_EQ(a.experimental_covariance_lwo_truncation, b.experimental_covariance_lwo_truncation);
    EXPECT_DOUBLE_EQ(a.experimental_match_distinctiveness, b.experimental_match_distinctiveness);
}

/** KITTI-style translational drift [fraction]: the relative translation
 * error of every sub-trajectory whose length is 10, 20, 30, 40 or 50 % of the
 * whole path, divided by that length, averaged (Geiger et al. use fixed
 * 100-800 m segments; the excerpt is 60 m long). */
double translationalDrift(const std::vector<CPose3D>& est, const std::vector<CPose3D>& gt)
{
    const std::size_t n = gt.size();
    std::vector<double> dist(n, 0.0);
    for (std::size_t i = 1; i < n; ++i)
    {
        dist[i] = dist[i - 1] + (gt[i] - gt[i - 1]).norm();
    }
    double sum = 0;
    int count = 0;
    for (double frac : {0.1, 0.2, 0.3, 0.4, 0.5})
    {
        const double len = frac * dist.back();
        for (std::size_t i = 0; i < n; ++i)
        {
            std::size_t j = i;
            while (j < n && dist[j] - dist[i] < len)
            {
                ++j;
            }
            if (j >= n)
            {
                break;
            }
            const CPose3D rel_gt = gt[j] - gt[i], rel_est = est[j] - est[i];
            sum += (rel_est - rel_gt).norm() / len;
            ++count;
        }
    }
    return count > 0 ? sum / count : 0.0;
}

double rotationDeg(const CPose3D& T)
{
    const auto R = T.getRotationMatrix();
    return std::acos(std::clamp((R.trace() - 1) / 2, -1.0, 1.0)) * 180 / M_PI;
}
}  // namespace

TEST(EgomotionEstimator, loadsNonDefaultValues)
{
    mrpt::config::CConfigFileMemory c(NON_DEFAULT_INI);
    EgomotionEstimator::TParameters p;
    p.loadFromConfigFile(c, "EgomotionEstimator");
    EXPECT_EQ(p.window_size, 6);
    EXPECT_DOUBLE_EQ(p.min_gradient, 12.5);
    EXPECT_DOUBLE_EQ(p.similarity_min, 0.7);
    EXPECT_DOUBLE_EQ(p.lwo_sigma_min, 0.01);
    EXPECT_EQ(p.min_final_matches, 20);
    EXPECT_EQ(p.lp_num_rings, 6);
    EXPECT_EQ(p.lp_num_angles, 12);
    EXPECT_DOUBLE_EQ(p.lp_radius, 10);
    EXPECT_FALSE(p.euclidean_init);
    EXPECT_TRUE(p.joint_refinement);
    EXPECT_TRUE(p.reprojection_refinement);
    EXPECT_EQ(p.max_lwo_matches, 1500);
    EXPECT_TRUE(p.guided_matching);
    EXPECT_DOUBLE_EQ(p.guided_radius, 0.25);
    EXPECT_TRUE(p.experimental_covariance_lwo_truncation);
    EXPECT_DOUBLE_EQ(p.experimental_match_distinctiveness, 1.5);
}

TEST(EgomotionEstimator, lwoTruncationFactorMatchesTheSpreadOfACentralSample)
{
    // The central fraction q of a large Gaussian sample: its variance times
    // the factor gives back the sample's.
    std::mt19937 rng(5);
    std::normal_distribution<double> normal(0.0, 2.0);
    std::vector<double> x(200000);
    for (double& v : x)
        v = normal(rng);
    std::sort(x.begin(), x.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
    const auto variance = [&](std::size_t n)
    {
        double s2 = 0;
        for (std::size_t i = 0; i < n; ++i)
            s2 += x[i] * x[i];
        return s2 / static_cast<double>(n);
    };
    const double all = variance(x.size());
    for (const double q : {0.3, 0.5, 0.8, 0.95})
    {
        SCOPED_TRACE(q);
        const double central = variance(static_cast<std::size_t>(q * x.size()));
        EXPECT_NEAR(central * emslam::egomotion::lwoTruncationVarianceFactor(q) / all, 1.0, 0.02);
    }
    EXPECT_DOUBLE_EQ(emslam::egomotion::lwoTruncationVarianceFactor(1.0), 1.0);
    EXPECT_NEAR(emslam::egomotion::lwoTruncationVarianceFactor(0.5), 7.01, 0.01);
    EXPECT_THROW(emslam::egomotion::lwoTruncationVarianceFactor(0.0), std::invalid_argument);
    EXPECT_THROW(emslam::egomotion::lwoTruncationVarianceFactor(1.5), std::invalid_argument);
    EXPECT_THROW(
        emslam::egomotion::lwoTruncationVarianceFactor(std::nan("")), std::invalid_argument);
}

TEST(EgomotionEstimator, saveReparseLoadRoundTrip)
{
    mrpt::config::CConfigFileMemory c(NON_DEFAULT_INI);
    EgomotionEstimator::TParameters p;
    p.loadFromConfigFile(c, "EgomotionEstimator");
    mrpt::config::CConfigFileMemory saved;
    p.saveToConfigFile(saved, "EgomotionEstimator");
    // Reading back from the object that was written gives defaults in MRPT
    // 2.5: re-parse the text.
    mrpt::config::CConfigFileMemory reparsed(saved.getContent());
    EgomotionEstimator::TParameters q;
    q.loadFromConfigFile(reparsed, "EgomotionEstimator");
    expectEqualParams(p, q);
}

TEST(EgomotionEstimator, invalidValuesThrow)
{
    const std::vector<std::pair<std::string, std::string>> bad{
        {"window_size", "2"},
        {"similarity_min", "0"},
        {"similarity_min", "1.5"},
        {"lwo_sigma_min", "0"},
        {"lwo_sigma_min", "-1"},
        {"min_final_matches", "2"},
        {"min_gradient", "-1"},
        {"lp_num_rings", "1"},
        {"lp_radius", "0.5"},
        {"max_lwo_matches", "5"},
        {"experimental_match_distinctiveness", "0.5"},
        {"experimental_match_distinctiveness", "nan"},
        // Sizes that ran out of memory or for minutes after the work started:
        {"window_size", "2147483647"},
        {"lp_num_rings", "70000"},
        {"lp_num_angles", "100000"},
        {"lp_radius", "1e9"}};
    for (const auto& [key, value] : bad)
    {
        mrpt::config::CConfigFileMemory c("[EgomotionEstimator]\n" + key + " = " + value + "\n");
        EgomotionEstimator::TParameters p;
        emslam::test::expectThrowContaining(
            [&] { p.loadFromConfigFile(c, "EgomotionEstimator"); }, {key});
    }
}

TEST(EgomotionEstimator, defaultsAreValid)
{
    EXPECT_NO_THROW(EgomotionEstimator::TParameters().validate());
}

TEST(EgomotionEstimator, shippedConfigsLoad)
{
    for (const char* name : {"kitti.ini", "euroc.ini"})
    {
        mrpt::config::CConfigFile c(emslam::test::sourceDir() + "/config/odometry/" + name);
        EgomotionEstimator::TParameters p;
        EXPECT_NO_THROW(p.loadFromConfigFile(c, "EgomotionEstimator")) << name;
        emslam::stereo::StereoMatcher::TParameters sp;
        EXPECT_NO_THROW(sp.loadFromConfigFile(c, "StereoMatcher")) << name;
    }
}

TEST(EgomotionEstimator, emptyAndTexturelessFramesFailWithoutCrashing)
{
    EgomotionEstimator em;
    const StereoFrame empty;
    const StereoFrame flat = frameWithImage(cv::Mat(120, 160, CV_8UC1, cv::Scalar(128)));
    for (const auto* pair : {&empty, &flat})
    {
        const EgomotionResult r = em.estimate(*pair, *pair);
        EXPECT_FALSE(r.ok);
        EXPECT_FALSE(r.failure_reason.empty());
        EXPECT_TRUE(r.T_prev_cur == CPose3D());
    }
    // Sequential use: first frame, then a failure, never a crash.
    EXPECT_EQ(em.process(flat).failure_reason, "first frame");
    EXPECT_FALSE(em.process(empty).ok);
    em.reset();
    EXPECT_EQ(em.process(empty).failure_reason, "first frame");
}

TEST(EgomotionEstimator, nonFinitePointsAreSkipped)
{
    // Textured images whose 3D points are all NaN: no usable feature.
    StereoFrame f = frameWithImage(noiseImage(160, 120, 3));
    for (auto& p : f.points)
    {
        p.z = std::numeric_limits<float>::quiet_NaN();
    }
    const EgomotionResult r = EgomotionEstimator().estimate(f, f);
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(r.features_cur, 0u);
}

TEST(EgomotionEstimator, identicalTexturedFramesGiveIdentity)
{
    // A random texture on a plane tilted in depth: the same frame twice.
    StereoFrame f = frameWithImage(noiseImage(160, 120, 4));
    for (std::size_t i = 0; i < f.points.size(); ++i)
    {
        f.points[i].z = 3.0f + 0.01f * f.pixels[i].u;
        f.points[i].x *= f.points[i].z / 5.0f;
        f.points[i].y *= f.points[i].z / 5.0f;
    }
    const EgomotionResult r = EgomotionEstimator().estimate(f, f);
    ASSERT_TRUE(r.ok) << r.failure_reason;
    EXPECT_GE(r.final_matches, 12u);
    EXPECT_LT(r.T_prev_cur.norm(), 1e-4);
    EXPECT_LT(rotationDeg(r.T_prev_cur), 1e-3);
}

// The KITTI 06 excerpt (51 frames, a straight 60 m drive).
namespace
{
struct KittiRun
{
    double drift{0}, end_error{0}, path{0};
    std::size_t failures{0}, min_matches{std::numeric_limits<std::size_t>::max()};
    std::size_t guided{0}, fallbacks{0};
};

/** How a KITTI run is configured, beside config/odometry/kitti.ini. */
struct KittiSetup
{
    bool guided{true};        //!< guided_matching
    bool sparse{true};        //!< [StereoMatcher] sparse_at_features
    bool reprojection{true};  //!< reprojection_refinement (not in the paper)
};

/** Sequential egomotion over every `step`-th frame of the KITTI 06 excerpt
 * with config/odometry/kitti.ini, as emslam-odometry runs it (a failed step
 * repeats the last motion). */
KittiRun runKitti06(
    const std::string& seq_dir, const std::string& poses, std::size_t step, KittiSetup setup)
{
    mrpt::config::CConfigFile cfg(emslam::test::sourceDir() + "/config/odometry/kitti.ini");
    emslam::stereo::StereoMatcher::TParameters sp;
    sp.loadFromConfigFile(cfg, "StereoMatcher");
    sp.sparse_at_features = setup.sparse;
    EgomotionEstimator::TParameters ep;
    ep.loadFromConfigFile(cfg, "EgomotionEstimator");
    ep.guided_matching = setup.guided;
    ep.reprojection_refinement = setup.reprojection;

    const emslam::io::KittiSequence seq(seq_dir, poses);
    emslam::stereo::StereoFrontEnd front(sp);
    EgomotionEstimator em(ep);
    // As the apps wire them.
    front.setPixelSelector([&em](const cv::Mat& image) { return em.locateFeatures(image); });
    EXPECT_EQ(front.sparse(), setup.sparse);
    std::vector<CPose3D> est, gt;
    CPose3D T_first_cur, velocity;
    KittiRun run;
    for (std::size_t i = 0; i < seq.size(); i += step)
    {
        const auto r = em.process(front.process(*seq.frame(i).obs));
        if (i > 0)
        {
            run.failures += !r.ok;
            run.min_matches = std::min(run.min_matches, r.final_matches);
            run.guided += r.ok && r.guided;
            run.fallbacks += r.guided_fallback;
            if (r.ok)
            {
                velocity = r.T_prev_cur;
            }
            T_first_cur = T_first_cur + velocity;
        }
        est.push_back(T_first_cur);
        gt.push_back(seq.groundTruth(i));
    }
    run.drift = translationalDrift(est, gt);
    run.end_error = (est.back() - gt.back()).norm();
    run.path = gt.back().norm();
    std::printf(
        "KITTI 06 excerpt, every %zu frame(s), %s, %s stereo: drift %.3f %%, end-point error "
        "%.3f m over %.1f m, %zu failures, min %zu matches after LWO, %zu guided steps, %zu "
        "fallbacks\n",
        step, setup.guided ? "guided" : "full search", setup.sparse ? "sparse" : "dense",
        100 * run.drift, run.end_error, run.path, run.failures, run.min_matches, run.guided,
        run.fallbacks);
    return run;
}
}  // namespace

TEST(EgomotionEstimator, kitti06DriftIsSmall)
{
    EMSLAM_REQUIRE_TEST_DATA(seq_dir, "kitti-odometry/sequences/06");
    EMSLAM_REQUIRE_TEST_DATA(poses, "kitti-odometry/poses/06.txt");
    // The paper's pipeline (dense stereo, full search): measured 0.95 %
    // drift, 0.38 m end-point error.
    const KittiRun paper = runKitti06(seq_dir, poses, 1, {false, false, false});
    EXPECT_EQ(paper.failures, 0u);
    EXPECT_LT(paper.drift, 0.011);
    EXPECT_LT(paper.end_error, 0.6);
    // Guided matching, dense stereo, with the reprojection refinement:
    // measured 0.78 %, 0.35 m (without it 0.77 %, 0.28 m).
    const KittiRun guided = runKitti06(seq_dir, poses, 1, {true, false});
    EXPECT_EQ(guided.failures, 0u);
    EXPECT_GE(guided.guided, 45u);
    EXPECT_LT(guided.drift, 0.0095);
    EXPECT_LT(guided.end_error, 0.40);
    // The shipped config (guided, sparse stereo at the features, the
    // reprojection refinement): measured 0.73 %, 0.36 m (without the
    // refinement 0.83 %, 0.15 m).
    const KittiRun shipped = runKitti06(seq_dir, poses, 1, {true, true});
    EXPECT_EQ(shipped.failures, 0u);
    EXPECT_GE(shipped.guided, 45u);
    EXPECT_LT(shipped.drift, 0.0095);
    EXPECT_LT(shipped.end_error, 0.40);
}

// Fast motion: every third frame (about 3.6 m per step). The full search
// loses steps (far look-alikes take the mutual best); guided matching, which
// compares only features near the constant-velocity prediction, loses at
// most one.
TEST(EgomotionEstimator, kitti06EveryThirdFrameGuidedLosesNoStep)
{
    EMSLAM_REQUIRE_TEST_DATA(seq_dir, "kitti-odometry/sequences/06");
    EMSLAM_REQUIRE_TEST_DATA(poses, "kitti-odometry/poses/06.txt");
    const KittiRun full = runKitti06(seq_dir, poses, 3, {false, false, false});
    const KittiRun guided = runKitti06(seq_dir, poses, 3, {true, false});
    const KittiRun shipped = runKitti06(seq_dir, poses, 3, {true, true});
    EXPECT_GE(full.failures, 3u);  // measured 6 of 16
    EXPECT_EQ(guided.failures, 0u);
    EXPECT_LT(guided.drift, 0.02);  // measured 1.19 %; the full search 4.6 %
    EXPECT_LT(guided.drift, 0.5 * full.drift);
    EXPECT_LE(shipped.failures, 1u);  // measured 1 of 16
    EXPECT_LT(shipped.drift, 0.015);  // measured 1.26 %
}

// EuRoC V1_01 frames 21-60: the vehicle is at rest.
TEST(EgomotionEstimator, eurocAtRestReportsNoMotion)
{
    EMSLAM_REQUIRE_TEST_DATA(mav0, "euroc-v101-rest/mav0");
    mrpt::config::CConfigFile cfg(emslam::test::sourceDir() + "/config/odometry/euroc.ini");
    emslam::stereo::StereoMatcher::TParameters sp;
    sp.loadFromConfigFile(cfg, "StereoMatcher");
    EgomotionEstimator::TParameters ep;
    ep.loadFromConfigFile(cfg, "EgomotionEstimator");
    const emslam::io::EurocSequence seq(mav0);
    emslam::stereo::StereoFrontEnd front(sp);
    EgomotionEstimator em(ep);
    CPose3D T_first_cur;
    std::size_t failures = 0;
    for (std::size_t i = 0; i < seq.size(); ++i)
    {
        const auto r = em.process(front.process(*seq.frame(i).obs));
        failures += i > 0 && !r.ok;
        if (r.ok)
        {
            T_first_cur = T_first_cur + r.T_prev_cur;
        }
    }
    std::printf(
        "EuRoC at rest: %.4f m, %.4f deg over %zu frames, %zu failures\n", T_first_cur.norm(),
        rotationDeg(T_first_cur), seq.size(), failures);
    EXPECT_EQ(failures, 0u);
    EXPECT_LT(T_first_cur.norm(), 0.02);
    // Measured 2.6 mm and 0.066 deg (0.26 deg with max_range = 12 m).
    EXPECT_LT(rotationDeg(T_first_cur), 0.2);
}

// Frames with nothing in common: LWO rejects (almost) every match, and the
// step is reported as failed (the basis of min_final_matches).
TEST(EgomotionEstimator, unrelatedFramesFail)
{
    EMSLAM_REQUIRE_TEST_DATA(seq_dir, "kitti-odometry/sequences/06");
    EMSLAM_REQUIRE_TEST_DATA(mav0, "euroc-v101-rest/mav0");
    emslam::stereo::StereoMatcher::TParameters kp;
    kp.num_disparities = 128;
    kp.max_range = 20;
    emslam::stereo::StereoFrontEnd kitti_front(kp), euroc_front;
    const auto k = kitti_front.process(*emslam::io::KittiSequence(seq_dir).frame(0).obs);
    const auto e = euroc_front.process(*emslam::io::EurocSequence(mav0).frame(0).obs);
    const auto r = EgomotionEstimator().estimate(e, k);
    std::printf(
        "unrelated frames: %zu matches -> %zu after LWO\n", r.initial_matches, r.final_matches);
    EXPECT_FALSE(r.ok);
    EXPECT_LT(r.final_matches, 12u);
    EXPECT_TRUE(r.T_prev_cur == CPose3D());
}

TEST(EgomotionEstimator, compactDescriptionsAreSmallAndRegisterAsTheFullOnes)
{
    // Two rendered frames of the corridor world, four steps apart: the
    // compact description of the first (200 features, 8 bits) against the
    // full one of the second gives the motion the full pair gives.
    emslam::sim::StereoSimulator sim;
    sim.loadFile(emslam::test::sourceDir() + "/config/sim/three_corridors.ini");
    emslam::stereo::StereoFrontEnd front_end;
    EgomotionEstimator e;
    const auto a = sim.renderFrame(0);
    const auto b = sim.renderFrame(4);
    e.process(front_end.process(*a.obs));
    const auto full_a = e.lastDescription();
    e.reset();
    e.process(front_end.process(*b.obs));
    const auto full_b = e.lastDescription();
    const auto kept = EgomotionEstimator::compact(full_a, 200);
    EXPECT_LE(kept.features.size(), 200u);
    EXPECT_LE(kept.bytes(), 32u * 1024u);
    const EgomotionResult with_full = e.estimate(full_a, full_b);
    const EgomotionResult with_kept = e.estimate(EgomotionEstimator::expand(kept), full_b);
    ASSERT_TRUE(with_full.ok) << with_full.failure_reason;
    ASSERT_TRUE(with_kept.ok) << with_kept.failure_reason;
    const CPose3D truth = b.T_first_left - a.T_first_left;
    const double err_full = (with_full.T_prev_cur - truth).norm();
    const double err_kept = (with_kept.T_prev_cur - truth).norm();
    std::printf(
        "kept %zu features, %zu bytes; error full %.4f m, compact %.4f m\n", kept.features.size(),
        kept.bytes(), err_full, err_kept);
    EXPECT_LT(err_kept, 0.02);
    EXPECT_LT(rotationDeg(with_kept.T_prev_cur - truth), 0.5);
    // Nothing to keep: nothing to register.
    EXPECT_TRUE(EgomotionEstimator::compact(nullptr, 200).features.empty());
    EXPECT_EQ(EgomotionEstimator::expand(EgomotionEstimator::CompactDescription()), nullptr);
}
