// SPDX-License-Identifier: BSD-3-Clause
// A map whose moves are split over two threads (IncrementalEntropyGrid::
// setThreads(2)) under ThreadSanitizer: the 3D and the marginal histograms,
// and the two halves of the binning, must share nothing.
#include <emslam/maps/IncrementalEntropyGrid.h>

#include <gtest/gtest.h>

#include <random>
#include <vector>

using emslam::maps::IncrementalEntropyGrid;
using mrpt::poses::CPose3D;

TEST(SplitMovesUnderTsan, movesUndosAndRebuildsOnTwoThreadsDoNotRace)
{
    IncrementalEntropyGrid one(
        0.15, emslam::maps::energyTerms(emslam::maps::EnergyType::Structured));
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-2.f, 2.f);
    std::size_t points = 0;
    for (int i = 0; i < 10; i++)
    {
        emslam::maps::WeightedPointCloud c;
        for (int j = 0; j < 2400; j++)
        {
            c.push_back({u(rng), u(rng), 4.f + u(rng)}, 1.f);
        }
        one.addObservation(c, CPose3D(0.05 * i, 0, 0, 0, 0, 0), true);
        points += c.size();
    }
    ASSERT_GE(points, IncrementalEntropyGrid::PARALLEL_MIN_POINTS);
    IncrementalEntropyGrid two = one;
    two.setThreads(2);
    std::uniform_real_distribution<double> d(-0.05, 0.05);
    for (int it = 0; it < 6; it++)
    {
        std::vector<IncrementalEntropyGrid::ObservationMove> moves;
        std::vector<CPose3D> poses;
        for (std::size_t i = 0; i < one.observationCount(); i++)
        {
            poses.push_back(one.observationPose(i) + CPose3D(d(rng), d(rng), d(rng), d(rng), 0, 0));
            moves.push_back({i, poses.back()});
        }
        EXPECT_EQ(two.energyAtPoses(poses), one.energyAtPoses(poses));
        EXPECT_EQ(two.moveObservations(moves), one.moveObservations(moves));
        if (it % 2 == 1)
        {
            EXPECT_EQ(two.revertLastMove(), one.revertLastMove());
        }
    }
}
