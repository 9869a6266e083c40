// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/maps/IncrementalEntropyGrid.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

using emslam::maps::EnergyType;
using emslam::maps::EntropyTerm;
using emslam::maps::IncrementalEntropyGrid;
using emslam::maps::termBit;
using emslam::maps::WeightedPointCloud;
using mrpt::poses::CPose3D;

namespace
{
constexpr double DEG = M_PI / 180.0;

/** All seven terms. */
constexpr emslam::maps::TermMask ALL_TERMS = 0x7f;

/** Shannon entropy [nats] of weights (normalised here). */
double entropyOf(const std::vector<double>& w)
{
    double W = 0;
    for (double v : w)
    {
        W += v;
    }
    double h = 0;
    for (double v : w)
    {
        h -= v / W * std::log(v / W);
    }
    return h;
}

WeightedPointCloud cloudOf(const std::vector<mrpt::math::TPoint3Df>& p, const std::vector<float>& w)
{
    WeightedPointCloud c;
    for (std::size_t i = 0; i < p.size(); i++)
    {
        c.push_back(p[i], w[i]);
    }
    return c;
}

/** Three points at cell centres of a 1 m grid, weights 1, 1, 2, in cells
 * (0,0,0), (1,0,0), (0,1,0). */
WeightedPointCloud threeCells()
{
    return cloudOf({{0.5f, 0.5f, 0.5f}, {1.5f, 0.5f, 0.5f}, {0.5f, 1.5f, 0.5f}}, {1, 1, 2});
}

/** Random planar patches (a floor and two walls) with point-count weights,
 * split into `n` observations, each given a small random pose. */
IncrementalEntropyGrid makeScene(EnergyType e, unsigned seed, int n)
{
    IncrementalEntropyGrid g(0.15, emslam::maps::energyTerms(e));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f);
    std::uniform_real_distribution<double> s(-1.0, 1.0);
    for (int i = 0; i < n; i++)
    {
        WeightedPointCloud c;
        for (int j = 0; j < 1500; j++)
        {
            const float a = u(rng), b = u(rng);
            const mrpt::math::TPoint3Df p = j % 3 == 0   ? mrpt::math::TPoint3Df(a, 1.4f, b + 4)
                                            : j % 3 == 1 ? mrpt::math::TPoint3Df(-2.1f, a, b + 4)
                                                         : mrpt::math::TPoint3Df(a, b, 6.2f);
            c.push_back(p, static_cast<float>(1 + j % 4));
        }
        g.addObservation(c, CPose3D(0.1 * s(rng), 0.05 * s(rng), 0.1 * s(rng), 0, 0, 0));
    }
    return g;
}

/** A small random perturbation of observation `i`'s pose. */
CPose3D perturbed(const IncrementalEntropyGrid& g, std::size_t i, std::mt19937& rng)
{
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    return g.observationPose(i) + CPose3D(
                                      0.04 * u(rng), 0.04 * u(rng), 0.04 * u(rng), 2 * DEG * u(rng),
                                      2 * DEG * u(rng), 2 * DEG * u(rng));
}

void expectEntropiesMatchScratch(const IncrementalEntropyGrid& g, const std::string& where)
{
    const auto inc = g.entropies();
    const auto ref = g.computeEntropiesFromScratch();
    for (std::size_t t = 0; t < emslam::maps::NUM_ENTROPY_TERMS; t++)
    {
        EXPECT_NEAR(inc[t], ref[t], 1e-9)
            << where << ", term " << emslam::maps::toString(static_cast<EntropyTerm>(t));
    }
}
}  // namespace

// H(A) of three cells with weights 1, 1, 2 is (3/2) log 2; its marginals
// merge cells along the dropped axes.
TEST(IncrementalEntropyGrid, entropiesOfAHandComputableHistogram)
{
    IncrementalEntropyGrid g(1.0, ALL_TERMS);
    EXPECT_EQ(g.addObservation(threeCells(), CPose3D(), true), 0u);
    EXPECT_DOUBLE_EQ(g.totalWeight(), 4.0);
    const double h3 = 1.5 * std::log(2.0);
    const double hx = entropyOf({3, 1});  // x = 0: weights 1 + 2; x = 1: 1
    const double hy = std::log(2.0);      // y = 0: 1 + 1; y = 1: 2
    EXPECT_NEAR(g.entropy(EntropyTerm::H3D), h3, 1e-12);
    EXPECT_NEAR(g.entropy(EntropyTerm::XY), h3, 1e-12);
    EXPECT_NEAR(g.entropy(EntropyTerm::XZ), hx, 1e-12);
    EXPECT_NEAR(g.entropy(EntropyTerm::YZ), hy, 1e-12);
    EXPECT_NEAR(g.entropy(EntropyTerm::X), hx, 1e-12);
    EXPECT_NEAR(g.entropy(EntropyTerm::Y), hy, 1e-12);
    EXPECT_NEAR(g.entropy(EntropyTerm::Z), 0.0, 1e-12);
    EXPECT_NEAR(g.energy(), 2 * h3 + 2 * hx + 2 * hy, 1e-12);  // all seven tracked

    // Structured energy (Exp. 10) tracks H(A) + H(A_XY) + H(A_XZ) + H(A_YZ).
    IncrementalEntropyGrid s(1.0, emslam::maps::energyTerms(EnergyType::Structured));
    s.addObservation(threeCells(), CPose3D(), true);
    EXPECT_NEAR(s.energy(), 2 * h3 + hx + hy, 1e-12);
    EXPECT_EQ(s.trackedHistogram(EntropyTerm::X), nullptr);
    EXPECT_NEAR(s.entropy(EntropyTerm::X), hx, 1e-12);  // built from scratch

    // At l_d = 2 m every point falls in cell (0,0,0).
    s.setGrid(2.0, s.trackedTerms());
    EXPECT_NEAR(s.energy(), 0.0, 1e-12);
}

// Two one-point observations in one cell: H = 0; one cell apart: H(A) = H(A_X)
// = log 2 and H(A_Y) = 0; reverting restores 0.
TEST(IncrementalEntropyGrid, moveAndRevertOfTwoPoints)
{
    IncrementalEntropyGrid g(1.0, termBit(EntropyTerm::H3D) | termBit(EntropyTerm::Y));
    const auto point = cloudOf({{0.5f, 0.5f, 0.5f}}, {1});
    g.addObservation(point, CPose3D(), true);
    g.addObservation(point, CPose3D(), true);
    EXPECT_EQ(g.energy(), 0.0);
    EXPECT_FALSE(g.canRevert());

    EXPECT_NEAR(g.moveObservation(1, CPose3D(1, 0, 0, 0, 0, 0)), std::log(2.0), 1e-12);
    EXPECT_NEAR(g.entropy(EntropyTerm::H3D), std::log(2.0), 1e-12);
    EXPECT_NEAR(g.entropy(EntropyTerm::X), std::log(2.0), 1e-12);
    EXPECT_EQ(g.entropy(EntropyTerm::Y), 0.0);
    EXPECT_EQ(g.observationPose(1).x(), 1.0);
    ASSERT_TRUE(g.canRevert());

    EXPECT_EQ(g.revertLastMove(), 0.0);
    EXPECT_EQ(g.observationPose(1).x(), 0.0);
    EXPECT_FALSE(g.canRevert());
    EXPECT_THROW(g.revertLastMove(), std::exception);

    // A committed move is kept.
    g.moveObservation(1, CPose3D(0, 1, 0, 0, 0, 0));
    g.commitMove();
    EXPECT_FALSE(g.canRevert());
    EXPECT_NEAR(g.entropy(EntropyTerm::Y), std::log(2.0), 1e-12);
}

// While no histogram grows, a reverted move restores every tracked entropy
// bit for bit (the histograms replay their undo logs).
TEST(IncrementalEntropyGrid, revertRestoresTheEnergyExactly)
{
    for (int e = 0; e <= static_cast<int>(EnergyType::PlanarStructured); e++)
    {
        const auto energy = static_cast<EnergyType>(e);
        IncrementalEntropyGrid g = makeScene(energy, 10 + e, 5);
        std::mt19937 rng(20 + e);
        int exact_reverts = 0;
        for (int it = 0; it < 100; it++)
        {
            const auto before = g.entropies();
            const double e0 = g.energy();
            std::vector<IncrementalEntropyGrid::ObservationMove> moves;
            for (int k = 0; k < 1 + it % 3; k++)
            {
                const auto i = static_cast<std::size_t>(it + 2 * k) % g.observationCount();
                moves.push_back({i, perturbed(g, i, rng)});
            }
            g.moveObservations(moves);
            bool rollback = true;
            for (std::size_t t = 0; t < emslam::maps::NUM_ENTROPY_TERMS; t++)
            {
                if (const auto* h = g.trackedHistogram(static_cast<EntropyTerm>(t)))
                {
                    rollback = rollback && h->canRollback();
                }
            }
            const double e1 = g.revertLastMove();
            if (!rollback)
            {
                EXPECT_NEAR(e1, e0, 1e-9);  // a table grew: the move was applied back
                continue;
            }
            exact_reverts++;
            EXPECT_EQ(e1, e0) << emslam::maps::toString(energy) << ", iteration " << it;
            const auto after = g.entropies();
            for (std::size_t t = 0; t < emslam::maps::NUM_ENTROPY_TERMS; t++)
            {
                if (g.trackedHistogram(static_cast<EntropyTerm>(t)))
                {
                    EXPECT_EQ(after[t], before[t]);
                }
            }
        }
        EXPECT_GT(exact_reverts, 50) << emslam::maps::toString(energy);
    }
}

// After many kept and reverted moves (single, batched, a repeated index),
// the running entropies equal a rebuild from the poses.
TEST(IncrementalEntropyGrid, incrementalEnergyEqualsRecomputationFromScratch)
{
    for (int e = 0; e <= static_cast<int>(EnergyType::PlanarStructured); e++)
    {
        const auto energy = static_cast<EnergyType>(e);
        IncrementalEntropyGrid g = makeScene(energy, 30 + e, 6);
        std::mt19937 rng(40 + e);
        for (int it = 0; it < 120; it++)
        {
            std::vector<IncrementalEntropyGrid::ObservationMove> moves;
            for (int k = 0; k < 1 + it % 4; k++)
            {
                const std::size_t i = rng() % g.observationCount();
                moves.push_back({i, perturbed(g, i, rng)});
            }
            if (it % 7 == 0)
            {
                moves.push_back({moves[0].index, perturbed(g, moves[0].index, rng)});
            }
            g.moveObservations(moves);
            const CPose3D& last = g.observationPose(moves.back().index);  // the last pose wins
            EXPECT_EQ(last.x(), moves.back().pose.x());
            EXPECT_EQ(last.yaw(), moves.back().pose.yaw());
            if (it % 3 == 0)
            {
                g.revertLastMove();
            }
        }
        // A move into empty space grows every table.
        g.moveObservation(0, CPose3D(40, -30, 25, 0, 0, 0));
        expectEntropiesMatchScratch(g, emslam::maps::toString(energy));
        const double inc = g.energy();
        EXPECT_NEAR(g.recomputeFromScratch(), inc, 1e-9) << emslam::maps::toString(energy);
        EXPECT_NEAR(
            emslam::maps::energyFromTerms(energy, g.computeEntropiesFromScratch()), inc, 1e-9);
    }
}

// Two threads per move update the same histograms in the same order as one:
// bit-identical energies after moves of every observation (dense marginal
// grids), a move far away (hashed marginal updates), and undos.
TEST(IncrementalEntropyGrid, twoThreadsGiveTheSameEnergiesAsOne)
{
    for (int e = 0; e <= static_cast<int>(EnergyType::PlanarStructured); e++)
    {
        const auto energy = static_cast<EnergyType>(e);
        IncrementalEntropyGrid one = makeScene(energy, 60 + e, 16);
        std::size_t points = 0;
        for (std::size_t i = 0; i < one.observationCount(); i++)
        {
            points += one.observationCloud(i).size();
        }
        ASSERT_GE(points, IncrementalEntropyGrid::PARALLEL_MIN_POINTS);  // the split is used
        IncrementalEntropyGrid two = one;
        two.setThreads(2);
        EXPECT_EQ(two.threads(), 2);
        std::mt19937 rng(70 + e);
        for (int it = 0; it < 12; it++)
        {
            std::vector<IncrementalEntropyGrid::ObservationMove> moves;
            for (std::size_t i = 0; i < one.observationCount(); i++)
            {
                moves.push_back({i, perturbed(one, i, rng)});
            }
            if (it == 5)
            {
                moves[3].pose = CPose3D(40, -30, 25, 0, 0, 0);
            }
            const double e1 = one.moveObservations(moves);
            EXPECT_EQ(two.moveObservations(moves), e1) << emslam::maps::toString(energy);
            if (it % 2 == 0)
            {
                const double r1 = one.revertLastMove();
                EXPECT_EQ(two.revertLastMove(), r1) << emslam::maps::toString(energy);
            }
        }
        EXPECT_NEAR(two.recomputeFromScratch(), two.energy(), 1e-9);
    }
    IncrementalEntropyGrid g;
    EXPECT_THROW(g.setThreads(0), std::exception);
    EXPECT_THROW(g.setThreads(3), std::exception);
    EXPECT_EQ(g.threads(), 1);
}

// The energy at other poses equals the energy after moving there, and the
// grid stays where it was.
TEST(IncrementalEntropyGrid, energyAtPosesEqualsTheEnergyThereWithoutMoving)
{
    for (int threads = 1; threads <= 2; threads++)
    {
        for (int e = 0; e <= static_cast<int>(EnergyType::PlanarStructured); e++)
        {
            const auto energy = static_cast<EnergyType>(e);
            IncrementalEntropyGrid g = makeScene(energy, 80 + e, 16);
            g.setThreads(threads);
            std::mt19937 rng(90 + e);
            std::vector<CPose3D> poses;
            std::vector<IncrementalEntropyGrid::ObservationMove> moves;
            for (std::size_t i = 0; i < g.observationCount(); i++)
            {
                poses.push_back(perturbed(g, i, rng));
                moves.push_back({i, poses.back()});
            }
            const double here = g.energy();
            const CPose3D first = g.observationPose(0);
            const double there = g.energyAtPoses(poses);
            EXPECT_EQ(g.energy(), here);
            EXPECT_EQ(g.observationPose(0).x(), first.x());
            EXPECT_NE(there, here);
            EXPECT_NEAR(g.moveObservations(moves), there, 1e-9) << emslam::maps::toString(energy);
            poses.pop_back();
            EXPECT_THROW(g.energyAtPoses(poses), std::exception);
        }
    }
}

// Observations assigned at once are kept as given and binned from scratch:
// same entropies as the same clouds added one by one.
TEST(IncrementalEntropyGrid, assignedObservationsMatchAddedOnes)
{
    const IncrementalEntropyGrid added = makeScene(EnergyType::Structured, 50, 4);
    std::vector<IncrementalEntropyGrid::PosedCloud> obs;
    for (std::size_t i = 0; i < added.observationCount(); i++)
    {
        obs.push_back({added.observationCloud(i), added.observationPose(i)});
    }
    IncrementalEntropyGrid g;
    g.assignObservations(0.15, added.trackedTerms(), obs);
    ASSERT_EQ(g.observationCount(), added.observationCount());
    EXPECT_EQ(g.observationCloud(2).points.size(), added.observationCloud(2).points.size());
    EXPECT_NEAR(g.energy(), added.energy(), 1e-9);
    EXPECT_DOUBLE_EQ(g.totalWeight(), added.totalWeight());
    EXPECT_GT(g.memoryStats().occupied_cells_3d, 0u);

    g.clear();
    EXPECT_EQ(g.observationCount(), 0u);
    EXPECT_EQ(g.energy(), 0.0);
    EXPECT_EQ(g.totalWeight(), 0.0);
}

// Bad arguments throw and leave the grid as it was.
TEST(IncrementalEntropyGrid, invalidArgumentsThrow)
{
    EXPECT_THROW(IncrementalEntropyGrid(0.0, ALL_TERMS), std::exception);
    IncrementalEntropyGrid g(1.0, ALL_TERMS);
    g.addObservation(threeCells(), CPose3D(), true);
    const double e = g.energy();
    EXPECT_THROW(
        g.moveObservations({{0, CPose3D(1, 0, 0, 0, 0, 0)}, {1, CPose3D()}}), std::exception);
    EXPECT_EQ(g.energy(), e);
    EXPECT_EQ(g.observationPose(0).x(), 0.0);
    EXPECT_FALSE(g.canRevert());
    EXPECT_THROW(g.observationPose(1), std::exception);
    WeightedPointCloud bad = threeCells();
    bad.weights.pop_back();
    EXPECT_THROW(g.addObservation(bad, CPose3D()), std::exception);
    EXPECT_EQ(g.observationCount(), 1u);
}
