// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/maps/WeightedHistogram.h>
#include <emslam/maps/WeightedPointCloud.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using emslam::maps::packCellKey;
using emslam::maps::WeightedHistogram;

namespace
{
/** A smooth non-negative 1D signal with three peaks on a low floor. */
double baseSignal(double x)
{
    const auto peak = [x](double c, double h, double s)
    { return h * std::exp(-0.5 * (x - c) * (x - c) / (s * s)); };
    return 0.02 + peak(50, 1.0, 3.0) + peak(90, 0.6, 5.0) + peak(140, 0.8, 2.0);
}
}  // namespace

// Paper §2.2.1, Fig. 8: three noisy 1D signals; the entropy of their sum over
// a grid of candidate displacements (d2, d3) is minimal at the true ones.
TEST(WeightedHistogram, paperFig8EntropyMinimumAtTrueDisplacements)
{
    constexpr int N = 200;
    constexpr int T2 = 7;
    constexpr int T3 = -12;
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> noise(0.0, 0.08);
    std::vector<double> s1(N), s2(N), s3(N);
    for (int x = 0; x < N; x++)
    {
        s1[x] = baseSignal(x) + noise(rng);
        s2[x] = baseSignal(x - T2) + noise(rng);  // S2 is the base shifted by T2
        s3[x] = baseSignal(x - T3) + noise(rng);
    }
    double best = 1e300;
    int best_d2 = 0, best_d3 = 0;
    for (int d2 = -20; d2 <= 20; d2++)
    {
        for (int d3 = -20; d3 <= 20; d3++)
        {
            // S(x) = S1(x) + S2(x + d2) + S3(x + d3): the sample of S2 at x
            // lands on bin x - d2.
            WeightedHistogram h(3 * N);
            for (int x = 0; x < N; x++)
            {
                h.add(packCellKey(x, 0, 0), s1[x]);
                h.add(packCellKey(x - d2, 0, 0), s2[x]);
                h.add(packCellKey(x - d3, 0, 0), s3[x]);
            }
            if (h.entropy() < best)
            {
                best = h.entropy();
                best_d2 = d2;
                best_d3 = d3;
            }
        }
    }
    EXPECT_EQ(best_d2, T2);
    EXPECT_EQ(best_d3, T3);
}

TEST(WeightedHistogram, entropyOfUniformHistogramIsLogN)
{
    for (int n : {1, 2, 7, 1000, 20000})
    {
        WeightedHistogram h;
        for (int i = 0; i < n; i++)
        {
            h.add(packCellKey(i, -i, 3 * i), 3.0);
        }
        EXPECT_NEAR(h.entropy(), std::log(static_cast<double>(n)), 1e-9) << "n=" << n;
        EXPECT_NEAR(h.entropyFromScratch(), std::log(static_cast<double>(n)), 1e-9);
        EXPECT_EQ(h.occupiedCells(), static_cast<std::size_t>(n));
    }
    EXPECT_EQ(WeightedHistogram().entropy(), 0.0);
}

TEST(WeightedHistogram, entropyIsInvariantToWeightScale)
{
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> cell(-50, 50);
    std::uniform_int_distribution<int> weight(1, 40);
    std::vector<std::pair<std::uint64_t, double>> samples;
    for (int i = 0; i < 3000; i++)
    {
        samples.emplace_back(packCellKey(cell(rng), cell(rng), 0), weight(rng));
    }
    const auto entropyScaled = [&](double s)
    {
        WeightedHistogram h;
        for (const auto& [k, w] : samples)
        {
            h.add(k, s * w);
        }
        return h.entropy();
    };
    const double h1 = entropyScaled(1.0);
    EXPECT_GT(h1, 1.0);
    for (double s : {2.0, 2.5, 1e-3, 1e4})
    {
        EXPECT_NEAR(entropyScaled(s), h1, 1e-9) << "scale " << s;
    }
}

TEST(WeightedHistogram, incrementalUpdatesEqualFromScratch)
{
    std::mt19937 rng(1234);
    std::uniform_int_distribution<int> cell(-30, 30);
    std::uniform_int_distribution<int> iw(1, 60);
    std::uniform_real_distribution<double> fw(0.1, 5.0);
    for (bool integer_weights : {true, false})
    {
        WeightedHistogram h(8);  // small on purpose: exercises growth
        std::vector<std::pair<std::uint64_t, double>> live;
        for (int step = 0; step < 20000; step++)
        {
            const bool remove = !live.empty() && (rng() % 3 == 0);
            const bool batch = (rng() % 2 == 0);
            if (batch)
            {
                h.beginBatch(8);
            }
            for (int k = 0; k < (batch ? 4 : 1); k++)
            {
                if (remove && !live.empty())
                {
                    const std::size_t i = rng() % live.size();
                    batch ? h.addDeferred(live[i].first, -live[i].second)
                          : h.add(live[i].first, -live[i].second);
                    live[i] = live.back();
                    live.pop_back();
                }
                else
                {
                    const auto key = packCellKey(cell(rng), cell(rng), cell(rng) / 10);
                    const double w = integer_weights ? iw(rng) : fw(rng);
                    batch ? h.addDeferred(key, w) : h.add(key, w);
                    live.emplace_back(key, w);
                }
            }
            if (batch)
            {
                h.endBatch();
            }
            if (step % 997 == 0)
            {
                ASSERT_NEAR(h.entropy(), h.entropyFromScratch(), 1e-9) << "step " << step;
            }
        }
        EXPECT_NEAR(h.entropy(), h.entropyFromScratch(), 1e-9);
        // Remove everything: back to an empty histogram.
        for (const auto& [k, w] : live)
        {
            h.add(k, -w);
        }
        EXPECT_EQ(h.occupiedCells(), 0u);
        EXPECT_NEAR(h.totalWeight(), 0.0, 1e-9);
    }
}

// A rejected rectification attempt is undone from the undo log: every path
// that changes cells (immediate, bulk, integral bulk, batch) is recorded, and
// rollback() restores the exact state; a table growth cancels the record.
TEST(WeightedHistogram, rollbackRestoresTheExactState)
{
    std::mt19937 rng(99);
    std::uniform_int_distribution<int> cell(-20, 20);
    std::uniform_int_distribution<int> iw(1, 40);
    WeightedHistogram h(4096);
    std::vector<WeightedHistogram::Update> base;
    for (int i = 0; i < 800; i++)
    {
        base.push_back({packCellKey(cell(rng), cell(rng), 0), double(iw(rng))});
    }
    h.addManyIntegral(base.data(), base.size());
    const auto snapshot = [&h]()
    {
        std::vector<std::pair<std::uint64_t, double>> cells;
        h.forEachCell([&](std::uint64_t k, double w) { cells.emplace_back(k, w); });
        return cells;
    };
    const auto cells_before = snapshot();
    const double entropy_before = h.entropy(), total_before = h.totalWeight(),
                 sum_before = h.sumWLogW();
    const std::size_t occupied_before = h.occupiedCells();

    h.beginUndoRecord();
    // Move some weight around (removals that empty cells, new cells), through
    // every update path.
    std::vector<WeightedHistogram::Update> moves;
    for (int i = 0; i < 300; i++)
    {
        const auto& b = base[static_cast<std::size_t>(i)];
        moves.push_back({b.key, -b.w});
        moves.push_back({packCellKey(cell(rng), cell(rng), 1), b.w});
    }
    h.addManyIntegral(moves.data(), 200);
    h.addMany(moves.data() + 200, 200);
    h.add(moves[400].key, moves[400].w);
    h.beginBatch(300);
    h.addDeferredMany(moves.data() + 401, moves.size() - 401);
    h.endBatch();
    ASSERT_NE(h.entropy(), entropy_before);
    ASSERT_TRUE(h.canRollback());
    h.rollback();
    EXPECT_FALSE(h.canRollback());
    EXPECT_EQ(h.entropy(), entropy_before);
    EXPECT_EQ(h.totalWeight(), total_before);
    EXPECT_EQ(h.sumWLogW(), sum_before);
    EXPECT_EQ(h.occupiedCells(), occupied_before);
    auto cells_after = snapshot();
    auto expected = cells_before;
    std::sort(cells_after.begin(), cells_after.end());
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(cells_after, expected);
    EXPECT_NEAR(h.entropy(), h.entropyFromScratch(), 1e-12);

    // Growth moves the slots: the record is cancelled, not silently wrong.
    h.beginUndoRecord();
    for (int i = 0; i < 5000; i++)
    {
        h.add(packCellKey(1000 + i, 0, 0), 1.0);
    }
    EXPECT_FALSE(h.canRollback());
    EXPECT_THROW(h.rollback(), std::exception);
}

TEST(WeightedHistogram, packAndUnpackCellKeys)
{
    for (int v : {0, 1, -1, 12345, -54321, (1 << 20) - 1, -(1 << 20)})
    {
        const auto c = emslam::maps::unpackCellKey(packCellKey(v, -v / 2, 3));
        EXPECT_EQ(c.x, v);
        EXPECT_EQ(c.y, -v / 2);
        EXPECT_EQ(c.z, 3);
    }
}

// §2.2.2: simplification keeps one point per l_d cell at the centroid,
// weighted by the number of original points.
TEST(WeightedPointCloud, simplifyCloudGivesCentroidsAndCounts)
{
    std::vector<mrpt::math::TPoint3Df> pts = {
        {0.01f, 0.01f, 0.01f},
        {0.05f, 0.03f, 0.02f},
        {0.09f, 0.02f, 0.0f},  // cell (0,0,0)
        {0.31f, 0.0f, 0.0f},
        {0.35f, 0.02f, 0.04f}};  // cell (2,0,0)
    const auto s = emslam::maps::simplifyCloud(pts, {}, 0.15);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_FLOAT_EQ(s.weights[0], 3.0f);
    EXPECT_FLOAT_EQ(s.weights[1], 2.0f);
    EXPECT_NEAR(s.points[0].x, 0.05, 1e-6);
    EXPECT_NEAR(s.points[0].y, 0.02, 1e-6);
    EXPECT_NEAR(s.points[1].x, 0.33, 1e-6);
    EXPECT_NEAR(s.totalWeight(), 5.0, 1e-9);
    // Weighted input: weights add up, centroids are weighted.
    const auto s2 = emslam::maps::simplifyCloud(pts, {1, 1, 2, 4, 4}, 0.15);
    EXPECT_FLOAT_EQ(s2.weights[0], 4.0f);
    EXPECT_NEAR(s2.points[0].x, (0.01 + 0.05 + 2 * 0.09) / 4, 1e-6);
}
