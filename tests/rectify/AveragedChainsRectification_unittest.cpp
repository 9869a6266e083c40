// SPDX-License-Identifier: BSD-3-Clause
// chains = K: K independent serial rectifications of the same frames,
// averaged pose by pose.
#include "PaperRectifierOptions.h"
#include "SimulatedDrive.h"

#include <emslam/rectify/AveragedChainsRectification.h>
#include <emslam/rectify/PoseMean.h>
#include <emslam/rectify/RectificationRunner.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>

using namespace emslam;
using namespace emslam::rectify;

namespace
{
CEntropyVoxelMap::TCreationOptions hallMap()
{
    CEntropyVoxelMap::TCreationOptions map;
    map.energy = maps::EnergyType::PlanarLowStructured;
    map.dof = 3;
    return map;
}

TRectifierOptions hallOptions()
{
    TRectifierOptions opt = emslam::test::paperRectifierOptions();
    opt.vertical_band = true;
    opt.n_max = 8;  // compressions happen: elements hold several frames
    return opt;
}

std::vector<TimedPose> run(RectificationRunner& r, const std::vector<test::DrivenFrame>& frames)
{
    for (const auto& f : frames)
    {
        r.addFrame(f.action_drifted, f.cloud, f.timestamp, f.frame_index);
    }
    r.finish();
    return r.framePoses();
}

std::vector<mrpt::poses::CPose3D> posesOf(const std::vector<TimedPose>& p)
{
    std::vector<mrpt::poses::CPose3D> out;
    for (const auto& t : p)
        out.push_back(t.T_world_frame);
    return out;
}

std::vector<test::DrivenFrame> hallStart()
{
    test::DriveOptions o;
    o.max_frames = 90;
    return test::driveWorld("config/sim/hall_double_loop.ini", o);
}
}  // namespace

TEST(AveragedChainsRectification, isTheMeanOfTheSeparateSearches)
{
    const auto frames = hallStart();
    const auto map = hallMap();
    TRectifierOptions opt = hallOptions();
    opt.seed = 5;
    opt.chains = 3;
    auto averaged = createRectificationRunner(opt, map);
    ASSERT_NE(dynamic_cast<AveragedChainsRectification*>(averaged.get()), nullptr);
    const auto mean = run(*averaged, frames);

    // The same frames through three plain serial runners, seeds 5, 6, 7.
    std::vector<std::unique_ptr<RectificationRunner>> separate;
    std::vector<std::vector<mrpt::poses::CPose3D>> chains;
    std::size_t attempts = 0;
    for (std::uint64_t s = 5; s < 8; ++s)
    {
        TRectifierOptions one = hallOptions();
        one.seed = s;
        separate.push_back(createRectificationRunner(one, map));
        chains.push_back(posesOf(run(*separate.back(), frames)));
        for (const auto& st : separate.back()->statistics())
            attempts += st.attempts;
    }
    ASSERT_EQ(mean.size(), frames.size());
    double spread = 0;  // how far the chains are apart: the test is not vacuous
    for (std::size_t f = 0; f < mean.size(); ++f)
    {
        const auto expected = meanPose({chains[0][f], chains[1][f], chains[2][f]});
        EXPECT_NEAR(mean[f].T_world_frame.distanceTo(expected), 0.0, 1e-9) << "frame " << f;
        spread = std::max(spread, chains[0][f].distanceTo(chains[1][f]));
    }
    EXPECT_GT(spread, 1e-3);

    std::size_t averaged_attempts = 0;
    for (const auto& st : averaged->statistics())
    {
        averaged_attempts += st.attempts;
        EXPECT_GT(st.seconds, 0.0);
    }
    EXPECT_EQ(averaged_attempts, attempts);

    // The trajectory (energy, entropy map) holds the mean element poses.
    const auto& t = averaged->trajectory();
    ASSERT_EQ(t.size(), separate[0]->trajectory().size());
    EXPECT_GT(t.compressionCount(), 0u);
    for (std::size_t i = 0; i < t.size(); ++i)
    {
        const auto expected = meanPose(
            {separate[0]->trajectory().pose(i), separate[1]->trajectory().pose(i),
             separate[2]->trajectory().pose(i)});
        EXPECT_NEAR(t.pose(i).distanceTo(expected), 0.0, 1e-6) << "element " << i;
    }
    EXPECT_THROW(
        averaged->addFrame(frames[0].action_drifted, frames[0].cloud, 0, 0), std::logic_error);
}

TEST(AveragedChainsRectification, averagingReducesTheSpreadOverSeeds)
{
    // Four chains against one: over three base seeds, the averaged runs end
    // closer together than the single ones.
    const auto frames = hallStart();
    const auto map = hallMap();
    std::vector<mrpt::poses::CPose3D> single_end, averaged_end;
    for (std::uint64_t s : {1, 11, 21})
    {
        TRectifierOptions one = hallOptions();
        one.seed = s;
        auto r1 = createRectificationRunner(one, map);
        single_end.push_back(run(*r1, frames).back().T_world_frame);
        TRectifierOptions four = one;
        four.chains = 4;
        auto r4 = createRectificationRunner(four, map);
        averaged_end.push_back(run(*r4, frames).back().T_world_frame);
    }
    const auto spread = [](const std::vector<mrpt::poses::CPose3D>& p)
    {
        const auto m = meanPose(p);
        double s = 0;
        for (const auto& x : p)
            s += x.distanceTo(m);
        return s / static_cast<double>(p.size());
    };
    EXPECT_LT(spread(averaged_end), spread(single_end));
}

TEST(AveragedChainsRectification, oneChainIsThePlainSerialRunner)
{
    TRectifierOptions opt = hallOptions();
    auto r = createRectificationRunner(opt, hallMap());
    EXPECT_EQ(dynamic_cast<AveragedChainsRectification*>(r.get()), nullptr);
}

TEST(AveragedChainsRectification, optionsAreCheckedAndRoundTrip)
{
    TRectifierOptions o;
    EXPECT_EQ(o.chains, 1);
    o.chains = 0;
    EXPECT_THROW(o.validate(), std::invalid_argument);
    o.chains = 17;
    EXPECT_THROW(o.validate(), std::invalid_argument);
    o.chains = 2;
    o.mode = RectificationMode::AnyTime;
    EXPECT_THROW(o.validate(), std::invalid_argument);
    o.mode = RectificationMode::Serial;
    EXPECT_NO_THROW(o.validate());

    mrpt::config::CConfigFileMemory out;
    o.chains = 4;
    o.saveToConfigFile(out, "Rectifier");
    const mrpt::config::CConfigFileMemory in(out.getContent());  // as a file is read
    TRectifierOptions back;
    back.loadFromConfigFile(in, "Rectifier");
    EXPECT_EQ(back.chains, 4);
}
