// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/ExperimentSuite.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

using emslam::apps::ExperimentSuite;
using emslam::apps::parseSeedList;

namespace
{
/** A suite INI in a temporary folder with one world and one mapper beside it. */
std::string writeSuite(const std::string& tag, const std::string& body)
{
    const std::string dir = emslam::test::makeTempDir(tag);
    const std::string src = emslam::test::sourceDir();
    emslam::test::writeFile(dir + "/world.ini", "[World]\ntype = empty\n");
    emslam::test::writeFile(dir + "/mapper.ini", "[Rectifier]\nseed = 1\n");
    emslam::test::writeFile(dir + "/suite.ini", body);
    return dir + "/suite.ini";
}

const std::string GOOD =
    "[Experiments]\nexperiments = a b\nseeds = 4, 5\nquick_frames = 12\n"
    "[a]\ntitle = Alpha\nfigure = Fig. 1\nworld = world.ini\nloop = false\n"
    "mappers = mapper.ini mapper.ini\nset = Rectifier.seed=2 StereoMatcher.max_range=8\n"
    "paper_path_m = 10.5\npaper_observations = -\npaper_slam_gap_m = 0.1 -\n"
    "world_set = World.type=building\n"
    "[b]\nworld = world.ini\nmappers = mapper.ini\n";
}  // namespace

TEST(ExperimentSuite, theShippedSuiteHasEveryExperimentOfThePaper)
{
    const auto s =
        ExperimentSuite::load(emslam::test::sourceDir() + "/config/experiments/paper.ini");
    ASSERT_EQ(s.experiments.size(), 6u);
    EXPECT_EQ(s.seeds, (std::vector<int>{1, 2, 3}));
    std::size_t runs = 0;
    for (const auto& e : s.experiments)
    {
        SCOPED_TRACE(e.name);
        EXPECT_FALSE(e.mappers.empty());
        EXPECT_EQ(e.paper_slam_gap_m.size(), e.mappers.size());
        EXPECT_TRUE(std::isfinite(e.paper_path_m));
        runs += e.mappers.size();
    }
    EXPECT_EQ(runs, 11u);
    EXPECT_EQ(s.experiments[3].name, "polytechnic_two_floors_loop");
    EXPECT_DOUBLE_EQ(s.experiments[3].paper_slam_gap_m[1], 0.36);
    EXPECT_FALSE(s.experiments[1].loop);  // three corridors: acyclic
    // The paper's method alone beside everything shipped.
    ASSERT_EQ(s.variants.size(), 2u);
    EXPECT_EQ(s.variants[0].name, "paper");
    EXPECT_EQ(s.variants[0].sets, (std::vector<std::string>{"LoopCloser.enabled=false"}));
    EXPECT_EQ(s.variants[1].name, "full");
    EXPECT_TRUE(s.variants[1].sets.empty());
}

// The paper's drift regime: the same six experiments and figures, each world
// slowed by world_set, the rectifier alone beside the full mapper.
TEST(ExperimentSuite, theShippedPaperRegimeSuiteSlowsEveryWorldItNeedsTo)
{
    const std::string dir = emslam::test::sourceDir() + "/config/experiments/";
    const auto regime = ExperimentSuite::load(dir + "paper-regime.ini");
    const auto paper = ExperimentSuite::load(dir + "paper.ini");
    ASSERT_EQ(regime.experiments.size(), paper.experiments.size());
    for (std::size_t i = 0; i < regime.experiments.size(); ++i)
    {
        const auto& r = regime.experiments[i];
        const auto& p = paper.experiments[i];
        SCOPED_TRACE(r.name);
        EXPECT_EQ(r.name, p.name);
        EXPECT_EQ(r.world, p.world);
        EXPECT_EQ(r.mappers, p.mappers);
        EXPECT_EQ(r.paper_slam_gap_m.size(), p.paper_slam_gap_m.size());
        // Only the river keeps its frame rate (the paper's step already).
        EXPECT_EQ(r.world_sets.empty(), r.name == "river_bed_loop");
    }
    ASSERT_EQ(regime.variants.size(), 2u);
    EXPECT_EQ(regime.variants[0].name, "alone");
    const auto& alone = regime.variants[0].sets;
    EXPECT_NE(std::find(alone.begin(), alone.end(), "LoopCloser.enabled=false"), alone.end());
}

TEST(ExperimentSuite, variantsAreReadInOrderAndSelectedByName)
{
    // Without `variants`: one unnamed variant with no overrides.
    const auto plain = ExperimentSuite::load(writeSuite("suite-plain", GOOD));
    ASSERT_EQ(plain.variants.size(), 1u);
    EXPECT_TRUE(plain.variants[0].name.empty());
    EXPECT_TRUE(plain.variants[0].sets.empty());

    const std::string text =
        "[Experiments]\nexperiments = a\nvariants = y x\n"
        "[Variants]\nx = Rectifier.seed=3 StereoMatcher.max_range=9\ny =\n"
        "[a]\nworld = world.ini\nmappers = mapper.ini\n";
    const auto s = ExperimentSuite::load(writeSuite("suite-variants", text));
    ASSERT_EQ(s.variants.size(), 2u);
    EXPECT_EQ(s.variants[0].name, "y");  // the order of `variants`, not of [Variants]
    EXPECT_TRUE(s.variants[0].sets.empty());
    EXPECT_EQ(s.variants[1].name, "x");
    EXPECT_EQ(
        s.variants[1].sets,
        (std::vector<std::string>{"Rectifier.seed=3", "StereoMatcher.max_range=9"}));
    EXPECT_EQ(s.selectVariants("").size(), 2u);
    ASSERT_EQ(s.selectVariants("x").size(), 1u);
    EXPECT_EQ(s.selectVariants("x,y")[0].name, "y");
    emslam::test::expectThrowContaining(
        [&] { s.selectVariants("z"); }, {"--variants", "'z'", "valid: y, x"});
}

TEST(ExperimentSuite, loadsPathsRelativeToTheFileAndEveryKey)
{
    const std::string file = writeSuite("suite-good", GOOD);
    const auto s = ExperimentSuite::load(file);
    EXPECT_EQ(s.seeds, (std::vector<int>{4, 5}));
    EXPECT_EQ(s.quick_frames, 12u);
    ASSERT_EQ(s.experiments.size(), 2u);
    const auto& a = s.experiments[0];
    EXPECT_EQ(a.title, "Alpha");
    EXPECT_EQ(a.figure, "Fig. 1");
    EXPECT_FALSE(a.loop);
    EXPECT_NE(a.world.find("world.ini"), std::string::npos);
    EXPECT_EQ(a.mappers.size(), 2u);
    EXPECT_EQ(a.sets, (std::vector<std::string>{"Rectifier.seed=2", "StereoMatcher.max_range=8"}));
    EXPECT_DOUBLE_EQ(a.paper_path_m, 10.5);
    EXPECT_TRUE(std::isnan(a.paper_observations));
    EXPECT_DOUBLE_EQ(a.paper_slam_gap_m[0], 0.1);
    EXPECT_TRUE(std::isnan(a.paper_slam_gap_m[1]));
    EXPECT_EQ(a.world_sets, (std::vector<std::string>{"World.type=building"}));
    const auto& b = s.experiments[1];
    EXPECT_TRUE(b.world_sets.empty());
    EXPECT_EQ(b.title, "b");
    EXPECT_TRUE(b.loop);
    EXPECT_EQ(b.paper_slam_gap_m.size(), 1u);

    EXPECT_EQ(s.select("").size(), 2u);
    ASSERT_EQ(s.select("b").size(), 1u);
    EXPECT_EQ(s.select("b,a")[0].name, "a");  // the suite's order
    emslam::test::expectThrowContaining([&] { s.select("a,c"); }, {"--only", "'c'", "valid: a, b"});
}

TEST(ExperimentSuite, badSuitesNameTheFileSectionAndKey)
{
    const std::pair<std::string, std::vector<std::string>> cases[] = {
        {"[Experiments]\nexperiments = a\n[a]\nworld = world.ini\nmapers = mapper.ini\n",
         {"unknown key 'mapers'", "did you mean 'mappers'"}},
        {"[Experiments]\nexperiments = a\n[a]\nmappers = mapper.ini\n", {"[a] world: missing"}},
        {"[Experiments]\nexperiments = a\n[a]\nworld = nowhere.ini\nmappers = mapper.ini\n",
         {"[a] world", "nowhere.ini", "is not a file"}},
        {"[Experiments]\nexperiments = a z\n[a]\nworld = world.ini\nmappers = mapper.ini\n",
         {"[Experiments] experiments", "no section [z]"}},
        {"[Experiments]\nexperiments = a\n[a]\nworld = world.ini\nmappers = mapper.ini\n"
         "paper_slam_gap_m = 1 2\n",
         {"[a] paper_slam_gap_m", "one value per mapper (1), got 2"}},
        {"[Experiments]\nexperiments = a\n[a]\nworld = world.ini\nmappers = mapper.ini\n"
         "paper_path_m = 12abc\n",
         {"[a] paper_path_m", "'12abc'"}},
        {"[Experiments]\nexperiments = a\n[a]\nworld = world.ini\nmappers = mapper.ini\n"
         "loop = maybe\n",
         {"[a] loop", "'maybe'"}},
        {"[Experiments]\nexperiments = a\nseeds = 1, x\n[a]\nworld = world.ini\n"
         "mappers = mapper.ini\n",
         {"[Experiments] seeds", "'1, x'"}},
        {"[Experiments]\nexperiments = a\nquick_frames = 1.5\n[a]\nworld = world.ini\n"
         "mappers = mapper.ini\n",
         {"[Experiments] quick_frames", "'1.5'"}},
        {"[Experiments]\nexperiments = a\nvariants = p q\n[Variants]\np =\n"
         "[a]\nworld = world.ini\nmappers = mapper.ini\n",
         {"[Experiments] variants", "no key 'q' in [Variants]"}},
        {"[Experiments]\nexperiments = a\nvariants = p p\n[Variants]\np =\n"
         "[a]\nworld = world.ini\nmappers = mapper.ini\n",
         {"[Experiments] variants", "'p' is named twice"}},
        {"[Experiments]\nexperiments = a\nvariants = p\n[Variants]\np = seed=2\n"
         "[a]\nworld = world.ini\nmappers = mapper.ini\n",
         {"[Variants] p", "Section.key=value", "'seed=2'"}},
        {"[Experiments]\nexperiments = a\nvariants = p\n[Variants]\np =\nfull =\n"
         "[a]\nworld = world.ini\nmappers = mapper.ini\n",
         {"unknown key 'full'"}},
        {"[Experiments]\nexperiments = a\n[a]\nworld = world.ini\nmappers = mapper.ini\n"
         "world_set = World.tpye=building\n",
         {"[a] world_set", "world.ini", "no key 'tpye' in [World]"}},
        {"[Experiments]\nexperiments = a\n[a]\nworld = world.ini\nmappers = mapper.ini\n"
         "world_set = type=building\n",
         {"[a] world_set", "Section.key=value", "'type=building'"}},
    };
    int k = 0;
    for (const auto& [text, parts] : cases)
    {
        SCOPED_TRACE(text);
        const std::string file = writeSuite("suite-bad-" + std::to_string(k++), text);
        std::vector<std::string> all{"suite.ini"};
        all.insert(all.end(), parts.begin(), parts.end());
        try
        {
            ExperimentSuite::load(file);
            ADD_FAILURE() << "no error";
        }
        catch (const std::exception& e)
        {
            for (const auto& p : all)
            {
                EXPECT_NE(std::string(e.what()).find(p), std::string::npos)
                    << "missing '" << p << "' in: " << e.what();
            }
        }
    }
    emslam::test::expectThrowContaining(
        [] { ExperimentSuite::load("no-such-suite.ini"); }, {"no-such-suite.ini", "not a file"});
}

// A repeated key or section is refused naming both lines; an oversized
// (sparse) file is refused before it is read.
TEST(ExperimentSuite, repeatedEntriesAndHugeFilesAreRefused)
{
    const std::string dup = writeSuite(
        "suite-dup",
        "[Experiments]\nexperiments = a\n[a]\nworld = world.ini\n"
        "mappers = mapper.ini\nworld = other.ini\n");
    emslam::test::expectThrowContaining(
        [&] { ExperimentSuite::load(dup); },
        {dup + ":6: key 'world' repeated in [a] (first at " + dup + ":4)"});
    const std::string sec = writeSuite(
        "suite-sec",
        "[Experiments]\nexperiments = a\n[a]\nworld = world.ini\n"
        "mappers = mapper.ini\n[Experiments]\nseeds = 3\n");
    emslam::test::expectThrowContaining(
        [&] { ExperimentSuite::load(sec); },
        {sec + ":6: section [Experiments] repeated (first at " + sec + ":1)"});

    // 2 GiB of holes: refused from its size at once (it used to be read whole).
    const std::string huge = writeSuite("suite-huge", "");
    std::filesystem::resize_file(huge, std::uintmax_t{2} << 30);
    const auto t0 = std::chrono::steady_clock::now();
    emslam::test::expectThrowContaining(
        [&] { ExperimentSuite::load(huge); },
        {"experiment set '" + huge + "' is 2048.0 MiB", "at most 16.0 MiB"});
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1));
    std::filesystem::remove(huge);
}

TEST(ExperimentSuite, seedListsTakeCommasOrSpaces)
{
    EXPECT_EQ(parseSeedList("1,2,3"), (std::vector<int>{1, 2, 3}));
    EXPECT_EQ(parseSeedList(" 7  8 "), (std::vector<int>{7, 8}));
    for (const char* bad : {"", "1,,x", "-1", "2.5", "99999999999"})
    {
        EXPECT_THROW(parseSeedList(bad), std::invalid_argument) << bad;
    }
}
