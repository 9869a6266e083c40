// SPDX-License-Identifier: BSD-3-Clause
// The AnyTime runner under ThreadSanitizer: a producer adds frames, a reader
// polls the public state, the rectification thread works in between.
#include <emslam/rectify/AnyTimeRectification.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <random>
#include <thread>

using namespace emslam;
using namespace emslam::rectify;

TEST(AnyTimeUnderTsan, producerReaderAndRectificationThreadsDoNotRace)
{
    CEntropyVoxelMap::TCreationOptions map;
    map.energy = maps::EnergyType::PlanarStructured;
    map.dof = 3;
    TRectifierOptions opt;
    // The paper's search: the entropy alone, box proposals.
    opt.prior_weight = 0;
    opt.prior_covariance = emslam::rectify::PriorCovariance::Fixed;
    opt.proposal = emslam::rectify::ProposalShape::Box;
    opt.mode = RectificationMode::AnyTime;
    opt.buffer_size = 5;
    opt.n_max = 12;  // compressions happen during the run
    AnyTimeRectification runner(opt, map);

    std::atomic<bool> reading{true};
    std::thread reader(
        [&]
        {
            while (reading)
            {
                (void)runner.mapStable();
                (void)runner.statistics();
                (void)runner.progress();
                (void)runner.framePoses();
            }
        });
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (int i = 0; i < 60; ++i)
    {
        maps::WeightedPointCloud c;
        for (int k = 0; k < 300; ++k)  // two walls of a corridor ahead
        {
            c.push_back({k % 2 ? -1.5f : 1.5f, -1.f + 2.f * u(rng), 0.5f + 5.f * u(rng)}, 1.f);
        }
        runner.addFrame(mrpt::poses::CPose3D(0, 0, i == 0 ? 0.0 : 0.2, 0, 0, 0), c, i, i);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    runner.finish();
    reading = false;
    reader.join();
    EXPECT_EQ(runner.framePoses().size(), 60u);
    EXPECT_LE(runner.trajectory().size(), 12u);
    EXPECT_GE(runner.synchronisations(), 12u);
}
