// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/eval/TrajectoryMetrics.h>

#include <mrpt/random/RandomGenerators.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

using emslam::eval::associateByTimestamp;
using emslam::io::TumTrajectory;
using mrpt::poses::CPose3D;

namespace
{
/** Pose i of a trajectory carries i in x, so a pair tells which poses it joins. */
TumTrajectory withIndexedPoses(const std::vector<double>& times)
{
    TumTrajectory t;
    for (std::size_t i = 0; i < times.size(); ++i)
    {
        t.add(times[i], CPose3D(static_cast<double>(i), 0, 0, 0, 0, 0));
    }
    return t;
}

/** (est index, gt index) of every pair, in output order. */
std::vector<std::pair<int, int>> indexPairs(const emslam::eval::AssociatedPoses& a)
{
    std::vector<std::pair<int, int>> out;
    for (std::size_t i = 0; i < a.size(); ++i)
    {
        out.emplace_back(static_cast<int>(a.est[i].x()), static_cast<int>(a.gt[i].x()));
    }
    return out;
}

/** The definition (TUM's associate.py): every pair within max_dt, sorted by
 * |dt| (ties: estimate index, then ground-truth time order), taken greedily.
 * Quadratic: only for small inputs. */
std::vector<std::pair<int, int>> allPairsReference(
    const std::vector<double>& t_gt, const std::vector<double>& t_est, double max_dt)
{
    std::vector<std::size_t> og(t_gt.size());
    for (std::size_t i = 0; i < og.size(); ++i)
    {
        og[i] = i;
    }
    std::stable_sort(
        og.begin(), og.end(), [&](std::size_t a, std::size_t b) { return t_gt[a] < t_gt[b]; });
    std::vector<std::tuple<double, std::size_t, std::size_t>> cand;
    for (std::size_t e = 0; e < t_est.size(); ++e)
    {
        for (const std::size_t g : og)
        {
            if (!(t_gt[g] < t_est[e] - max_dt) && t_gt[g] <= t_est[e] + max_dt)
            {
                cand.emplace_back(std::abs(t_gt[g] - t_est[e]), e, g);
            }
        }
    }
    std::stable_sort(
        cand.begin(), cand.end(),
        [](const auto& a, const auto& b) { return std::get<0>(a) < std::get<0>(b); });
    std::vector<bool> used_e(t_est.size()), used_g(t_gt.size());
    std::vector<std::pair<int, int>> pairs;
    for (const auto& [dt, e, g] : cand)
    {
        if (!used_e[e] && !used_g[g])
        {
            used_e[e] = used_g[g] = true;
            pairs.emplace_back(static_cast<int>(e), static_cast<int>(g));
        }
    }
    return pairs;
}

/** Random stamps on a coarse grid (many exact repeats and equal |dt| ties). */
std::vector<double> gridTimes(std::size_t n, int grid_points, double step)
{
    auto& rng = mrpt::random::getRandomGenerator();
    std::vector<double> t(n);
    for (auto& x : t)
    {
        x = 100.0 + step * static_cast<double>(rng.drawUniform32bit() % grid_points);
    }
    return t;
}

std::set<std::pair<int, int>> asSet(const std::vector<std::pair<int, int>>& v)
{
    return {v.begin(), v.end()};
}
}  // namespace

// The same pairs as the quadratic definition, on inputs full of repeated stamps and ties.
TEST(TimestampAssociation, samePairsAsAllPairsGreedyOnRandomInputs)
{
    mrpt::random::getRandomGenerator().randomize(20);
    for (int trial = 0; trial < 300; ++trial)
    {
        const std::size_t n_gt = 1 + trial % 37, n_est = 1 + (trial * 7) % 41;
        const int grid = 2 + trial % 25;
        const double step = trial % 2 == 0 ? 0.01 : 0.004;
        const auto t_gt = gridTimes(n_gt, grid, step);
        const auto t_est = gridTimes(n_est, grid, step);
        const double max_dt = 0.005 * static_cast<double>(trial % 5);
        const auto got = indexPairs(
            associateByTimestamp(withIndexedPoses(t_gt), withIndexedPoses(t_est), max_dt));
        const auto want = allPairsReference(t_gt, t_est, max_dt);
        ASSERT_EQ(asSet(got), asSet(want)) << "trial " << trial;
        // Output in estimate time order.
        for (std::size_t i = 1; i < got.size(); ++i)
        {
            ASSERT_LE(t_est[got[i - 1].first], t_est[got[i].first]) << "trial " << trial;
        }
    }
}

// Jittered stamps at different rates, as real trajectories: same pairs too.
TEST(TimestampAssociation, samePairsAsAllPairsGreedyOnJitteredRates)
{
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(21);
    for (int trial = 0; trial < 20; ++trial)
    {
        std::vector<double> t_gt, t_est;
        for (int i = 0; i < 200; ++i)
        {
            t_gt.push_back(1.4e9 + 0.005 * i + rng.drawUniform(-0.002, 0.002));
        }
        for (int i = 0; i < 70; ++i)
        {
            t_est.push_back(1.4e9 + 0.0143 * i + rng.drawUniform(-0.004, 0.004));
        }
        const auto got =
            indexPairs(associateByTimestamp(withIndexedPoses(t_gt), withIndexedPoses(t_est), 0.02));
        EXPECT_EQ(asSet(got), asSet(allPairsReference(t_gt, t_est, 0.02))) << "trial " << trial;
    }
}

// 20,000 poses sharing one stamp in both files: the all-pairs candidate list
// would hold 4e8 entries (about 10 GB); the lazy association pairs them one to
// one in file order.
TEST(TimestampAssociation, twentyThousandEqualStampsPairOneToOne)
{
    constexpr std::size_t N = 20000;
    const std::vector<double> t(N, 1.4e9);
    const auto a = associateByTimestamp(withIndexedPoses(t), withIndexedPoses(t), 0.02);
    ASSERT_EQ(a.size(), N);
    const auto pairs = indexPairs(a);
    std::set<int> gts;
    for (const auto& [e, g] : pairs)
    {
        EXPECT_EQ(e, g);  // the k-th estimate takes the k-th ground truth (ties: file order)
        gts.insert(g);
    }
    EXPECT_EQ(gts.size(), N);
}

// One stamp for every estimate against 20,000 distinct ground-truth stamps
// within max_dt (and the reverse): every pose is paired, nearest first.
TEST(TimestampAssociation, equalStampsAgainstADenseWindow)
{
    constexpr std::size_t N = 20000;
    const std::vector<double> t_est(N, 1000.0);
    std::vector<double> t_gt(N);
    for (std::size_t i = 0; i < N; ++i)
    {
        // Alternating sides of 1000 s, 1 us apart: 0, +1, -1, +2, -2, ... us.
        const double k = static_cast<double>((i + 1) / 2);
        t_gt[i] = 1000.0 + (i % 2 == 1 ? 1e-6 : -1e-6) * k;
    }
    const auto est = withIndexedPoses(t_est), gt = withIndexedPoses(t_gt);
    const auto a = associateByTimestamp(gt, est, 0.02);
    ASSERT_EQ(a.size(), N);
    const auto pairs = indexPairs(a);
    const auto pair_set = asSet(pairs);
    EXPECT_EQ(pair_set.count({0, 0}), 1U);  // the exact match goes to the first estimate
    EXPECT_EQ(pair_set.size(), N);
    std::set<int> gts;
    for (const auto& p : pairs)
    {
        gts.insert(p.second);
    }
    EXPECT_EQ(gts.size(), N);  // one to one
    const auto b = associateByTimestamp(est, gt, 0.02);
    ASSERT_EQ(b.size(), N);
}

// Distinct interleaved stamps all within max_dt of each other (every pose a
// candidate of every other: the all-pairs worst case), in time order and with
// the estimates reversed in the file: the same pairs as the definition.
TEST(TimestampAssociation, samePairsAsAllPairsGreedyOnADenseInterleavedWindow)
{
    constexpr std::size_t N = 1500;
    std::vector<double> t_gt(N), t_est(N);
    for (std::size_t i = 0; i < N; ++i)
    {
        t_gt[i] = 1000.0 + 1e-6 * static_cast<double>(2 * i + 1);
        t_est[i] = 1000.0 + 1e-6 * static_cast<double>(2 * i) + (i % 3 == 0 ? 3e-7 : 0.0);
    }
    for (const bool reversed : {false, true})
    {
        auto t = t_est;
        if (reversed)
        {
            std::reverse(t.begin(), t.end());
        }
        const auto got =
            indexPairs(associateByTimestamp(withIndexedPoses(t_gt), withIndexedPoses(t), 0.02));
        EXPECT_EQ(got.size(), N);
        EXPECT_EQ(asSet(got), asSet(allPairsReference(t_gt, t, 0.02))) << reversed;
    }
}

TEST(TimestampAssociation, nothingWithinANegativeOrNanMaxDt)
{
    const auto t = withIndexedPoses({1.0, 2.0});
    EXPECT_EQ(associateByTimestamp(t, t, 0.0).size(), 2U);
    EXPECT_EQ(associateByTimestamp(t, t, -1.0).size(), 0U);
    EXPECT_EQ(associateByTimestamp(t, t, std::nan("")).size(), 0U);
    EXPECT_EQ(associateByTimestamp(t, TumTrajectory(), 1.0).size(), 0U);
}
