// SPDX-License-Identifier: BSD-3-Clause
#include "PaperRectifierOptions.h"
#include "SimulatedDrive.h"

#include <emslam/rectify/ActionCovariance.h>
#include <emslam/rectify/EnergyAtPoses.h>
#include <emslam/rectify/SerialRectification.h>
#include <emslam/rectify/SpaceSampler.h>
#include <emslam/rectify/TrajectoryRectifier.h>
#include <emslam/rectify/VerticalBand.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/io/vector_loadsave.h>

#include <gtest/gtest.h>

#include <TestData.h>
#include <TestHelpers.h>

using namespace emslam;
using namespace emslam::rectify;

namespace
{
CEntropyVoxelMap::TCreationOptions planarMap()
{
    CEntropyVoxelMap::TCreationOptions map;
    map.energy = maps::EnergyType::PlanarLowStructured;
    map.dof = 3;
    return map;
}

const std::vector<test::DrivenFrame>& hallStart()
{
    static const auto frames = []
    {
        test::DriveOptions o;
        o.max_frames = 300;  // around the first corner of the hall
        return test::driveWorld("config/sim/hall_double_loop.ini", o);
    }();
    return frames;
}

Trajectory drifted(
    const std::vector<test::DrivenFrame>& frames,
    const CEntropyVoxelMap::TCreationOptions& map = planarMap())
{
    Trajectory t(map);
    for (const auto& f : frames)
    {
        t.append(
            f.action_drifted, keepVerticalBand(f.cloud, -1.5, 0.8), f.timestamp, f.frame_index);
        if (t.size() > 60)
            t.compress();
    }
    return t;
}
}  // namespace

TEST(TrajectoryRectifier, bestEnergyNeverIncreasesAndStopsAfterNcMaxFailures)
{
    Trajectory t = drifted(hallStart());
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.eps_xyz = 0.01;
    opt.eps_rot_deg = 0.5;
    TrajectoryRectifier r(opt);
    RectificationStats s;
    r.begin(t, s);
    double best = s.energy_before;
    int consecutive = 0;
    while (r.consecutiveFailures() < opt.nc_max && s.attempts < 5000)
    {
        const bool ok = r.attempt(t, s);
        consecutive = ok ? 0 : consecutive + 1;
        ASSERT_EQ(r.consecutiveFailures(), consecutive);
        ASSERT_LE(s.energy_after, best + 1e-12);
        best = s.energy_after;
    }
    r.finish(t, s);
    EXPECT_TRUE(s.converged);
    EXPECT_EQ(s.attempts, s.successes + s.failures);
    EXPECT_GT(s.successes, 0u);
    EXPECT_LT(s.energy_after, s.energy_before);
    EXPECT_NEAR(t.recomputeEnergy(), s.energy_after, 1e-9);
}

// With an energy that sees the global alignment a_0 is always perturbed,
// on top of S_sel: with S_sel = 1 (a tiny select_fraction) each attempt must
// still bend the trajectory at one other action, not move a_0 alone.
TEST(TrajectoryRectifier, anchoredEnergyPerturbsAZeroAndAtLeastOneOtherAction)
{
    CEntropyVoxelMap::TCreationOptions map = planarMap();
    map.energy = maps::EnergyType::PlanarStructured;  // Exp. 12: depends on a_0
    Trajectory t = drifted(hallStart(), map);
    ASSERT_TRUE(t.dependsOnGlobalAlignment());
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.select_fraction = 0.001;         // S_sel = 1
    opt.acceptance = Acceptance::Ratio;  // nearly every change is kept: each one is visible
    TrajectoryRectifier r(opt);
    RectificationStats s;
    r.begin(t, s);
    std::size_t kept = 0;
    for (int k = 0; k < 40; ++k)
    {
        const auto before = t.actions();
        r.attempt(t, s);
        std::vector<std::size_t> changed;
        for (std::size_t i = 0; i < before.size(); ++i)
        {
            if (!(t.action(i) == before[i]))
                changed.push_back(i);
        }
        if (changed.empty())
            continue;  // undone
        ++kept;
        ASSERT_EQ(changed.size(), 2U);
        EXPECT_EQ(changed[0], 0U);
    }
    r.finish(t, s);
    EXPECT_GT(kept, 20U);
}

TEST(TrajectoryRectifier, coarseToFineEndsOnTheFineGridBelowItsStart)
{
    Trajectory t = drifted(hallStart());
    const double cell = t.map().creationOptions().cell_size;
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.eps_xyz = 0.01;
    opt.eps_rot_deg = 0.5;
    opt.coarse_levels = 2;
    TrajectoryRectifier r(opt);
    const RectificationStats s = r.rectify(t);
    EXPECT_TRUE(s.converged);
    EXPECT_EQ(t.resolutionLevel(), 0);
    EXPECT_DOUBLE_EQ(t.map().creationOptions().cell_size, cell);
    // Two coarse levels of at least NC_max attempts each, then l_d's.
    EXPECT_GE(s.coarse_attempts, 2u * static_cast<std::size_t>(opt.nc_max));
    EXPECT_GE(s.attempts, s.coarse_attempts + static_cast<std::size_t>(opt.nc_max));
    EXPECT_EQ(s.attempts, s.successes + s.failures);
    EXPECT_LT(s.energy_after, s.energy_before);
    EXPECT_NEAR(t.recomputeEnergy(), s.energy_after, 1e-9);

    // Stepwise (AnyTime's way): refine() walks the levels down to l_d.
    Trajectory u = drifted(hallStart());
    RectificationStats su;
    r.begin(u, su);
    EXPECT_EQ(u.resolutionLevel(), 2);
    EXPECT_DOUBLE_EQ(u.map().creationOptions().cell_size, 4 * cell);
    EXPECT_TRUE(r.refine(u));
    EXPECT_EQ(u.resolutionLevel(), 1);
    EXPECT_TRUE(r.refine(u));
    EXPECT_FALSE(r.refine(u));
    EXPECT_EQ(u.resolutionLevel(), 0);
    // Stopped on a coarse level, finish() still leaves l_d's energy.
    r.begin(u, su);
    r.attempt(u, su);
    r.finish(u, su);
    EXPECT_EQ(u.resolutionLevel(), 0);
    EXPECT_NEAR(u.recomputeEnergy(), su.energy_after, 1e-9);
}

/** The hall's first 150 frames with noiseless depth at their true poses,
 * compressed twice: nothing real to gain there. */
const Trajectory& hallTruth()
{
    static const Trajectory truth = []
    {
        test::DriveOptions o;
        o.max_frames = 150;
        o.depth_noise = 0.0;
        const auto frames = test::driveWorld("config/sim/hall_double_loop.ini", o);
        Trajectory t(planarMap());
        for (std::size_t i = 0; i < frames.size(); ++i)
        {
            const auto action = i == 0 ? frames[0].T_world_true
                                       : frames[i].T_world_true - frames[i - 1].T_world_true;
            t.append(action, keepVerticalBand(frames[i].cloud, -1.5, 0.8), frames[i].timestamp, i);
        }
        t.compress();
        t.compress();
        return t;
    }();
    return truth;
}

/** The energy averaged over 4 shifted grids of `t` with `actions`. */
double fourGridEntropy(const Trajectory& t, const std::vector<mrpt::poses::CPose3D>& actions)
{
    std::vector<mrpt::poses::CPose3D> poses;
    for (const auto& a : actions)
    {
        poses.push_back(poses.empty() ? a : poses.back() + a);
    }
    return entropyAtElementPoses(t, poses, 4);
}

TEST(TrajectoryRectifier, shiftedGridsKeepARealGainAndUndoAGridOne)
{
    const Trajectory& truth = hallTruth();
    TRectifierOptions opt =
        emslam::test::paperRectifierOptions();  // one action per attempt, so the search finds the
                                                // kink below
    opt.select_fraction = 0.03;
    opt.eps_xyz = 0.1;
    opt.eps_rot_deg = 4.0;
    opt.nc_max = 300;
    opt.validate_phases = 4;
    TRectifierOptions paper = opt;
    paper.validate_phases = 0;

    // At the truth, what one grid accepts the shifted ones do not confirm:
    // the trajectory goes back exactly to the truth.
    {
        Trajectory single = truth;
        const RectificationStats s1 = TrajectoryRectifier(paper).rectify(single);
        ASSERT_GT(s1.successes, 0u);  // the single grid finds "gains" at the truth
        Trajectory t = truth;
        const RectificationStats s4 = TrajectoryRectifier(opt).rectify(t);
        EXPECT_EQ(s4.successes, s1.successes);   // the same search...
        EXPECT_TRUE(s4.rejected_by_validation);  // ...undone
        EXPECT_EQ(t.actions(), truth.actions());
        EXPECT_NEAR(s4.energy_after, s4.energy_before, 1e-9);
    }
    // One action off by 0.15 m and 3 degrees: the searched changes lower the
    // energy on the shifted grids too, so they are kept. (Kept, not right:
    // this energy's minimum is not at the truth either,
    // doc/notes/2026-12-02-where-the-energy-is-wrong.md.)
    {
        Trajectory t = truth;
        const std::size_t k = t.size() / 2;
        t.changeActions(
            {{k, t.action(k) + mrpt::poses::CPose3D(0.15, 0, 0, 0, mrpt::DEG2RAD(3.0), 0)}});
        t.commitChange();
        const auto start = t.actions();
        const RectificationStats s = TrajectoryRectifier(opt).rectify(t);
        EXPECT_FALSE(s.rejected_by_validation);
        EXPECT_GT(s.successes, 0u);
        EXPECT_LT(s.energy_after, s.energy_before);
        EXPECT_LT(fourGridEntropy(t, t.actions()), fourGridEntropy(t, start));
    }
}

TEST(TrajectoryRectifier, confirmPhasesRefuseLongMovesTheShiftedGridsDoNotSee)
{
    TRectifierOptions paper =
        emslam::test::paperRectifierOptions();  // one action by up to 0.6 m and 4 degrees
    paper.select_fraction = 0.03;
    paper.eps_xyz = 0.6;
    paper.eps_rot_deg = 4.0;
    TRectifierOptions confirm = paper;
    confirm.confirm_phases = 4;
    struct Step
    {
        bool success;
        std::size_t unconfirmed;
        double before, after;  // four-grid entropy (the prior is off)
    };
    const auto run = [](const TRectifierOptions& opt)
    {
        Trajectory t = hallTruth();
        TrajectoryRectifier r(opt);
        RectificationStats s;
        r.begin(t, s);
        std::vector<Step> steps;
        double before = fourGridEntropy(t, t.actions());
        for (int k = 0; k < 300; ++k)
        {
            const bool success = r.attempt(t, s);
            const double after = fourGridEntropy(t, t.actions());
            steps.push_back({success, s.unconfirmed, before, after});
            before = after;
        }
        EXPECT_EQ(s.attempts, s.successes + s.failures);
        EXPECT_LE(s.unconfirmed, s.failures);
        return steps;
    };
    // The same seed draws the same changes until the check first refuses
    // one: there, one grid alone took a step the shifted grids see as worse.
    const std::vector<Step> one = run(paper);
    const std::vector<Step> four = run(confirm);
    std::size_t k = 0;
    while (k < one.size() && one[k].success == four[k].success)
    {
        EXPECT_NEAR(one[k].after, four[k].after, 1e-12);
        EXPECT_EQ(four[k].unconfirmed, 0u);
        ++k;
    }
    ASSERT_LT(k, one.size()) << "the check never refused a change";
    EXPECT_TRUE(one[k].success);
    EXPECT_FALSE(four[k].success);
    EXPECT_EQ(four[k].unconfirmed, 1u);
    EXPECT_GE(one[k].after, one[k].before);             // what the paper's grid kept
    EXPECT_NEAR(four[k].after, four[k].before, 1e-12);  // refused: nothing moved
    EXPECT_GT(std::count_if(four.begin(), four.end(), [](const Step& s) { return s.success; }), 0);
}

TEST(TrajectoryRectifier, confirmMinMoveZeroChecksTheSmallMovesToo)
{
    // On the true trajectory every gain is the grid's. Moves of a few
    // centimetres and a tenth of a degree move no map point by a cell, so
    // only confirm_min_move = 0 checks them.
    TRectifierOptions small = emslam::test::paperRectifierOptions();
    small.select_fraction = 0.03;
    small.eps_xyz = 0.03;
    small.eps_rot_deg = 0.1;
    small.confirm_phases = 4;
    TRectifierOptions every = small;
    every.confirm_min_move = 0;
    const auto run = [](const TRectifierOptions& opt)
    {
        Trajectory t = hallTruth();
        TrajectoryRectifier r(opt);
        RectificationStats s;
        r.begin(t, s);
        double before = fourGridEntropy(t, t.actions());
        std::size_t worse_kept = 0;  // successes that raised the four-grid entropy
        for (int k = 0; k < 300; ++k)
        {
            const bool success = r.attempt(t, s);
            const double after = fourGridEntropy(t, t.actions());
            worse_kept += success && after > before ? 1 : 0;
            before = after;
        }
        return std::make_pair(s, worse_kept);
    };
    const auto [s_small, worse_small] = run(small);
    const auto [s_every, worse_every] = run(every);
    EXPECT_EQ(s_small.unconfirmed, 0u);  // no move beyond a cell: never checked
    EXPECT_GT(worse_small, 0u);          // ... so grid-only gains were kept
    EXPECT_GT(s_every.unconfirmed, 0u);
    EXPECT_EQ(worse_every, 0u);  // every kept success lowered the four grids' entropy
    EXPECT_GT(s_every.successes, 0u);
}

TEST(TrajectoryRectifier, paperRatioRuleKeepsTheBestStateSeen)
{
    Trajectory t = drifted(hallStart());
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.acceptance = Acceptance::Ratio;  // the paper's rule
    opt.max_attempts = 300;
    TrajectoryRectifier r(opt);
    const RectificationStats s = r.rectify(t);
    EXPECT_EQ(s.attempts, s.successes + s.failures);
    EXPECT_GT(s.accepted_worse, 0u);  // p = E_old / E_try is close to 1
    // (Restoring the best state replays moves: the running sums then differ
    // from the start's by rounding when no better state was found.)
    EXPECT_LE(s.energy_after, s.energy_before + 1e-12);
    EXPECT_NEAR(t.recomputeEnergy(), s.energy_after, 1e-9);  // the best state is restored
}

TEST(TrajectoryRectifier, sameSeedSameResult)
{
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.seed = 42;
    opt.vertical_band = true;
    const auto run = [&]
    {
        SerialRectification slam(opt, planarMap());
        for (const auto& f : hallStart())
        {
            slam.addFrame(f.action_drifted, f.cloud, f.timestamp, f.frame_index);
        }
        slam.finish();
        return std::make_pair(slam.framePoses(), slam.statistics());
    };
    const auto [poses_a, stats_a] = run();
    const auto [poses_b, stats_b] = run();
    ASSERT_EQ(poses_a.size(), poses_b.size());
    ASSERT_EQ(stats_a.size(), stats_b.size());
    for (std::size_t i = 0; i < stats_a.size(); ++i)
    {
        EXPECT_EQ(stats_a[i].attempts, stats_b[i].attempts);
        EXPECT_EQ(stats_a[i].energy_after, stats_b[i].energy_after);
    }
    for (std::size_t i = 0; i < poses_a.size(); ++i)
    {
        ASSERT_EQ(poses_a[i].T_world_frame.asString(), poses_b[i].T_world_frame.asString());
    }
    // A different seed takes a different path.
    opt.seed = 43;
    const auto [poses_c, stats_c] = run();
    EXPECT_NE(poses_a.back().T_world_frame.asString(), poses_c.back().T_world_frame.asString());
}

TEST(TrajectoryRectifier, optionsRoundTripAndRejectBadValues)
{
    TRectifierOptions o;
    o.eps_xyz = 0.02;
    o.mode = RectificationMode::AnyTime;
    o.acceptance = Acceptance::Greedy;
    o.seed = 1234567890123ULL;
    o.prior_weight = 3e-7;
    o.prior_sigma_rot_deg = 0.25;
    o.experimental_grid_phases = 3;
    o.prior_covariance = PriorCovariance::Fixed;
    o.proposal = ProposalShape::Coherent;
    o.proposal_scale = 0.5;
    o.coarse_levels = 2;
    o.validate_phases = 4;
    o.confirm_phases = 3;
    o.confirm_min_move = 0.5;
    o.confirm_all_before_revisit = true;
    o.hold_before_revisit = true;
    o.threads = 1;
    mrpt::config::CConfigFileMemory out;
    o.saveToConfigFile(out, "Rectifier");
    mrpt::config::CConfigFileMemory in(out.getContent());
    TRectifierOptions back;
    back.loadFromConfigFile(in, "Rectifier");
    EXPECT_DOUBLE_EQ(back.eps_xyz, 0.02);
    EXPECT_EQ(back.mode, RectificationMode::AnyTime);
    EXPECT_EQ(back.acceptance, Acceptance::Greedy);
    EXPECT_EQ(back.seed, 1234567890123ULL);
    EXPECT_EQ(back.nc_max, 50);
    EXPECT_DOUBLE_EQ(back.prior_weight, 3e-7);  // not rounded to 0
    EXPECT_DOUBLE_EQ(back.prior_sigma_rot_deg, 0.25);
    EXPECT_EQ(back.experimental_grid_phases, 3);
    EXPECT_DOUBLE_EQ(back.odometryPrior().sigma_xyz, 0.02);
    EXPECT_EQ(back.odometryPrior().covariance, PriorCovariance::Fixed);
    EXPECT_EQ(back.proposal, ProposalShape::Coherent);
    EXPECT_DOUBLE_EQ(back.proposal_scale, 0.5);
    EXPECT_EQ(back.coarse_levels, 2);
    EXPECT_EQ(back.validate_phases, 4);
    EXPECT_EQ(back.confirm_phases, 3);
    EXPECT_DOUBLE_EQ(back.confirm_min_move, 0.5);
    EXPECT_TRUE(back.confirm_all_before_revisit);
    EXPECT_TRUE(back.hold_before_revisit);
    EXPECT_FALSE(TRectifierOptions{}.hold_before_revisit);
    EXPECT_EQ(back.threads, 1);
    EXPECT_EQ(TRectifierOptions{}.threads, 2);

    const auto load = [](const std::string& kv)
    {
        mrpt::config::CConfigFileMemory c("[Rectifier]\n" + kv + "\n");
        TRectifierOptions p;
        p.loadFromConfigFile(c, "Rectifier");
    };
    test::expectThrowContaining([&] { load("mode = parallel"); }, {"[Rectifier] mode"});
    test::expectThrowContaining([&] { load("acceptance = maybe"); }, {"ratio, greedy"});
    test::expectThrowContaining([&] { load("select_fraction = 0"); }, {"select_fraction"});
    test::expectThrowContaining([&] { load("nc_max = 0"); }, {"nc_max"});
    test::expectThrowContaining([&] { load("n_max = 2"); }, {"n_max"});
    test::expectThrowContaining([&] { load("eps_rot_deg = -1"); }, {"eps_rot_deg"});
    test::expectThrowContaining([&] { load("seed = -3"); }, {"seed"});
    test::expectThrowContaining([&] { load("prior_weight = -1"); }, {"prior_weight"});
    test::expectThrowContaining([&] { load("prior_sigma_xyz = 0"); }, {"prior_sigma_xyz"});
    test::expectThrowContaining(
        [&] { load("prior_sigma_rot_deg = nan"); }, {"prior_sigma_rot_deg"});
    test::expectThrowContaining(
        [&] { load("experimental_grid_phases = 0"); }, {"experimental_grid_phases", "1..8"});
    test::expectThrowContaining(
        [&] { load("experimental_grid_phases = 9"); }, {"experimental_grid_phases", "1..8"});
    test::expectThrowContaining([&] { load("coarse_levels = -1"); }, {"coarse_levels", "0..4"});
    test::expectThrowContaining([&] { load("coarse_levels = 5"); }, {"coarse_levels", "0..4"});
    test::expectThrowContaining([&] { load("validate_phases = 1"); }, {"validate_phases", "2..8"});
    test::expectThrowContaining([&] { load("validate_phases = 9"); }, {"validate_phases", "2..8"});
    test::expectThrowContaining([&] { load("confirm_phases = 1"); }, {"confirm_phases", "2..8"});
    test::expectThrowContaining([&] { load("confirm_phases = 9"); }, {"confirm_phases", "2..8"});
    test::expectThrowContaining([&] { load("confirm_min_move = -1"); }, {"confirm_min_move"});
    test::expectThrowContaining([&] { load("confirm_min_move = nan"); }, {"confirm_min_move"});
    test::expectThrowContaining(
        [&] { load("prior_covariance = hessian"); }, {"prior_covariance", "fixed, egomotion"});
    test::expectThrowContaining([&] { load("proposal = gauss"); }, {"proposal", "coherent"});
    test::expectThrowContaining([&] { load("proposal_scale = 0"); }, {"proposal_scale"});
    test::expectThrowContaining([&] { load("proposal_scale = inf"); }, {"proposal_scale"});
    test::expectThrowContaining([&] { load("threads = 3"); }, {"threads", "1 or 2"});
    test::expectThrowContaining([&] { load("threads = 0"); }, {"threads", "1 or 2"});
}

TEST(TrajectoryRectifier, paperConfigLoadsThePaperValues)
{
    mrpt::config::CConfigFileMemory c(
        mrpt::io::file_get_contents(test::sourceDir() + "/config/mapper/paper.ini"));
    TRectifierOptions o;
    o.loadFromConfigFile(c, "Rectifier");
    EXPECT_DOUBLE_EQ(o.eps_xyz, 0.05);
    EXPECT_DOUBLE_EQ(o.eps_rot_deg, 3.0);
    EXPECT_DOUBLE_EQ(o.select_fraction, 0.10);
    EXPECT_EQ(o.nc_max, 50);
    EXPECT_EQ(o.rectify_every, 25);
    EXPECT_EQ(o.buffer_size, 10);
    EXPECT_EQ(o.n_max, 60);
    EXPECT_EQ(o.mode, RectificationMode::Serial);
    EXPECT_EQ(o.acceptance, Acceptance::Ratio);
    EXPECT_EQ(o.proposal, ProposalShape::Box);
    EXPECT_FALSE(o.odometryPrior().enabled());  // the paper's energy
    SpaceSampler::TParameters sp;
    sp.loadFromConfigFile(c, "SpaceSampler");
    EXPECT_DOUBLE_EQ(sp.t_min, 0.15);
    EXPECT_DOUBLE_EQ(sp.theta_min_deg, 5.0);
}

TEST(TrajectoryRectifier, covarianceProposalsMoveOnlyWhatTheEgomotionLeftUncertain)
{
    // Every step is certain except along x: Gaussian proposals drawn from
    // that covariance may change δx only.
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.proposal = ProposalShape::Covariance;
    opt.max_attempts = 300;
    CEntropyVoxelMap::TCreationOptions map;
    map.energy = maps::EnergyType::Unstructured;
    map.dof = 6;
    ActionCovariance cov;
    cov.setZero();
    cov(0, 0) = 0.03 * 0.03;
    Trajectory t(map);
    const auto& frames = hallStart();
    // No compression: composing two steps would turn x into other axes.
    for (std::size_t i = 0; i < 40 && i < frames.size(); ++i)
    {
        t.append(
            frames[i].action_drifted, keepVerticalBand(frames[i].cloud, -1.5, 0.8),
            frames[i].timestamp, frames[i].frame_index, cov);
    }
    TrajectoryRectifier r(opt);
    const RectificationStats s = r.rectify(t);
    ASSERT_GT(s.successes, 0u);
    double moved_x = 0;
    for (std::size_t i = 1; i < t.size(); ++i)
    {
        const ActionDelta d = actionDifference(t.action(i), t.referenceAction(i));
        moved_x = std::max(moved_x, std::abs(d[0]));
        for (std::size_t k = 1; k < 6; ++k)
        {
            EXPECT_NEAR(d[k], 0.0, 1e-9) << "action " << i << " component " << k;
        }
    }
    EXPECT_GT(moved_x, 1e-4);
}

TEST(TrajectoryRectifier, alignmentTurnMovesNoPointByMoreThanACell)
{
    // An anchored energy perturbs a_0, which turns the whole map about the
    // first camera, in every attempt. With the egomotion's proposals that
    // turn is capped so that no map point moves by more than a cell, whatever
    // eps_rot_deg says.
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.proposal = ProposalShape::Covariance;
    opt.acceptance = Acceptance::Ratio;  // nearly every change is kept: each one is visible
    opt.eps_rot_deg = 10;
    CEntropyVoxelMap::TCreationOptions map;
    map.energy = maps::EnergyType::Structured;  // Exp. 10: depends on a_0
    map.dof = 6;
    Trajectory t(map);
    const auto& frames = hallStart();
    for (std::size_t i = 0; i < 40 && i < frames.size(); ++i)
    {
        t.append(
            frames[i].action_drifted, keepVerticalBand(frames[i].cloud, -1.5, 0.8),
            frames[i].timestamp, frames[i].frame_index);
    }
    ASSERT_TRUE(t.dependsOnGlobalAlignment());
    // The farthest map point from the first camera.
    double reach = 0;
    const auto origin = t.pose(0).translation();
    for (std::size_t i = 0; i < t.size(); ++i)
    {
        for (const auto& p : t.map().observationCloud(i).points)
        {
            const auto w = t.pose(i).composePoint(mrpt::math::TPoint3D(p.x, p.y, p.z));
            reach = std::max(reach, (w - origin).norm());
        }
    }
    const double max_turn = map.cell_size / reach;
    ASSERT_LT(max_turn, mrpt::DEG2RAD(opt.eps_rot_deg) / 4);  // the cap is what limits it

    TrajectoryRectifier r(opt);
    RectificationStats s;
    r.begin(t, s);
    std::size_t kept = 0;
    double largest = 0;
    for (int k = 0; k < 40; ++k)
    {
        const mrpt::poses::CPose3D before = t.action(0);
        r.attempt(t, s);
        if (t.action(0) == before)
            continue;  // undone
        ++kept;
        const ActionDelta d = actionDifference(t.action(0), before);
        for (std::size_t c = 3; c < 6; ++c)
        {
            EXPECT_LE(std::abs(d[c]), max_turn) << "a_0 rotation component " << c;
            largest = std::max(largest, std::abs(d[c]));
        }
    }
    r.finish(t, s);
    EXPECT_GT(kept, 20U);
    EXPECT_GT(largest, max_turn / 4);  // it does turn
}
