// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/CommandLine.h>
#include <emslam/apps/EvalApp.h>
#include <emslam/apps/ExperimentsApp.h>
#include <emslam/apps/GrabberApp.h>
#include <emslam/apps/ImportApp.h>
#include <emslam/apps/MapperApp.h>
#include <emslam/apps/OdometryApp.h>
#include <emslam/apps/SimApp.h>
#include <emslam/apps/StereoApp.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using emslam::apps::DeprecatedSpelling;
using emslam::apps::rewriteDeprecatedSpellings;

namespace
{
/** Runs App::initialize() on `program args...`. */
template <class App>
void initWith(App& app, const std::string& program, std::vector<std::string> args)
{
    args.insert(args.begin(), program);
    std::vector<const char*> argv;
    for (const auto& a : args)
    {
        argv.push_back(a.c_str());
    }
    app.initialize(static_cast<int>(argv.size()), argv.data());
}

/** initialize() must throw a message holding every one of `parts`. */
template <class App>
void expectInitFails(
    const std::string& program,
    const std::vector<std::string>& args,
    std::initializer_list<std::string> parts)
{
    App app;
    emslam::test::expectThrowContaining([&] { initWith(app, program, args); }, parts);
}

std::string readFile(const std::string& file)
{
    std::ifstream f(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
}

/** The --help text of an App. */
template <class App>
std::string helpOf(const std::string& program)
{
    App app;
    testing::internal::CaptureStdout();
    initWith(app, program, {"--help"});
    return testing::internal::GetCapturedStdout();
}

const std::vector<DeprecatedSpelling> EVAL_LIKE = {
    {"--gt", "", 0, "GT.tum"}, {"--est", "", 1, "EST.tum"}, {"--poses", "--truth", 0, "FILE"}};

std::string mapperConfig()
{
    return emslam::test::sourceDir() + "/config/mapper/kitti.ini";
}
}  // namespace

TEST(CommandLine, deprecatedFlagsMoveToTheirPositionsOrNewNames)
{
    using V = std::vector<std::string>;
    EXPECT_EQ(
        rewriteDeprecatedSpellings("p", {"--est", "e.tum", "--json", "j", "--gt=g.tum"}, EVAL_LIKE),
        (V{"g.tum", "e.tum", "--json", "j"}));
    EXPECT_EQ(
        rewriteDeprecatedSpellings("p", {"a", "--poses", "x.txt", "-q"}, EVAL_LIKE),
        (V{"a", "--truth", "x.txt", "-q"}));
    // New spellings pass untouched, and so do longer flags sharing a prefix.
    EXPECT_EQ(
        rewriteDeprecatedSpellings("p", {"g", "e", "--gt-format", "kitti"}, EVAL_LIKE),
        (V{"g", "e", "--gt-format", "kitti"}));
    emslam::test::expectThrowContaining(
        [] { rewriteDeprecatedSpellings("p", {"--gt"}, EVAL_LIKE); }, {"--gt", "needs a value"});
    emslam::test::expectThrowContaining(
        [] {
            rewriteDeprecatedSpellings("p", {"g", "--est", "e"}, EVAL_LIKE);
        },
        {"positionally"});
    emslam::test::expectThrowContaining(
        [] {
            rewriteDeprecatedSpellings("p", {"--gt", "a", "--gt", "b"}, EVAL_LIKE);
        },
        {"given twice"});
}

TEST(CommandLine, setTyposAndNonNumbersAreRejectedInEveryAppThatTakesSet)
{
    const std::string none = "/nonexistent/in.rawlog";
    // emslam-odometry: [StereoMatcher] and [EgomotionEstimator].
    expectInitFails<emslam::apps::OdometryApp>(
        "emslam-odometry", {none, "-o", "x.tum", "--set", "EgomotionEstimatr.S_min=1"},
        {"unknown section [EgomotionEstimatr]", "did you mean [EgomotionEstimator]"});
    expectInitFails<emslam::apps::OdometryApp>(
        "emslam-odometry", {none, "-o", "x.tum", "--set", "EgomotionEstimator.similarity_mn=0.5"},
        {"unknown key 'similarity_mn'", "did you mean 'similarity_min'"});
    expectInitFails<emslam::apps::OdometryApp>(
        "emslam-odometry", {none, "-o", "x.tum", "--set", "EgomotionEstimator.similarity_min=high"},
        {"similarity_min", "'high'", "is not a number"});
    // emslam-stereo: [StereoMatcher].
    expectInitFails<emslam::apps::StereoApp>(
        "emslam-stereo", {none, "--set", "StereoMatcher.num_disparity=64"},
        {"unknown key 'num_disparity'", "did you mean 'num_disparities'"});
    expectInitFails<emslam::apps::StereoApp>(
        "emslam-stereo", {none, "--set", "StereoMatcher.num_disparities=abc"},
        {"num_disparities", "'abc'", "not a whole number"});
    // emslam-mapper: every section of its INI file.
    expectInitFails<emslam::apps::MapperApp>(
        "emslam-mapper",
        {mapperConfig(), none, "-o", "/tmp/x", "--set", "StereoMatcher.max_range=far"},
        {"max_range", "'far'", "not a number"});
    expectInitFails<emslam::apps::MapperApp>(
        "emslam-mapper",
        {mapperConfig(), none, "-o", "/tmp/x", "--set", "EntropySlam.egomotion_only=maybe"},
        {"egomotion_only", "'maybe'", "not true or false"});
}

TEST(CommandLine, missingRequiredArgumentsAreNamed)
{
    expectInitFails<emslam::apps::MapperApp>(
        "emslam-mapper", {mapperConfig(), "in.rawlog"},
        {"missing required argument --out <DIR>", "emslam-mapper --help"});
    expectInitFails<emslam::apps::MapperApp>(
        "emslam-mapper", {"-o", "d"},
        {"missing required arguments <CONFIG.ini>, <DATASET.rawlog>"});
    expectInitFails<emslam::apps::OdometryApp>(
        "emslam-odometry", {"-o", "x.tum"}, {"missing required argument <DATASET.rawlog>"});
    expectInitFails<emslam::apps::StereoApp>(
        "emslam-stereo", {}, {"missing required argument <DATASET.rawlog | LEFT RIGHT CALIB.ini>"});
    expectInitFails<emslam::apps::EvalApp>(
        "emslam-eval", {"gt.tum"}, {"missing required argument <EST>"});
    expectInitFails<emslam::apps::ImportApp>(
        "emslam-import", {"kitti", "seq"}, {"missing required argument --output <OUT.rawlog>"});
    expectInitFails<emslam::apps::SimApp>(
        "emslam-sim", {"-o", "x.rawlog"}, {"missing required argument <WORLD.ini>"});
    expectInitFails<emslam::apps::ExperimentsApp>(
        "emslam-experiments", {"suite.ini"}, {"missing required argument --out <DIR>"});
    expectInitFails<emslam::apps::GrabberApp>("emslam-grabber", {"-q"}, {"CONFIG.ini"});
}

TEST(CommandLine, oldSpellingsStillWork)
{
    const std::string dir = emslam::test::makeTempDir("cli_old_spellings");
    {
        emslam::apps::OdometryApp app;
        initWith(app, "emslam-odometry", {"--rawlog", dir + "/in.rawlog", "-o", dir + "/t.tum"});
        emslam::test::expectThrowContaining([&] { app.run(); }, {dir + "/in.rawlog"});
    }
    {
        emslam::apps::StereoApp app;
        initWith(app, "emslam-stereo", {"--rawlog", dir + "/in.rawlog"});
        emslam::test::expectThrowContaining([&] { app.run(); }, {dir + "/in.rawlog"});
    }
    {
        emslam::apps::StereoApp app;
        initWith(
            app, "emslam-stereo",
            {"--left", dir + "/l.png", "--right", dir + "/r.png", "--calib", dir + "/c.ini"});
        emslam::test::expectThrowContaining([&] { app.run(); }, {dir});
    }
    {
        emslam::apps::EvalApp app;
        initWith(app, "emslam-eval", {"--est", dir + "/e.tum", "--gt", dir + "/g.tum"});
        emslam::test::expectThrowContaining([&] { app.run(); }, {"g.tum"});
    }
}

TEST(CommandLine, formerSectionNamesAreReadUnderTheNewOnesWithAWarning)
{
    const std::string dir = emslam::test::makeTempDir("cli_former_names");
    emslam::test::writeFile(
        dir + "/old.ini",
        "[Stereo]\nblock_size = 7\nmax_range = 9\n[Mapper]\nmap_cell_size = 0.2\n");
    mrpt::config::CConfigFileMemory cfg;
    testing::internal::CaptureStderr();
    // An old name in --set overrides the file's value either way.
    emslam::apps::loadConfig(
        cfg, dir + "/old.ini", {"Stereo.max_range=11", "EntropySlam.map_cell_size=0.3"});
    const std::string warnings = testing::internal::GetCapturedStderr();
    EXPECT_FALSE(cfg.sectionExists("Stereo"));
    EXPECT_EQ(cfg.read_int("StereoMatcher", "block_size", 0), 7);
    EXPECT_DOUBLE_EQ(cfg.read_double("StereoMatcher", "max_range", 0), 11);
    EXPECT_DOUBLE_EQ(cfg.read_double("EntropySlam", "map_cell_size", 0), 0.3);
    EXPECT_NE(warnings.find("[Stereo] is now [StereoMatcher]"), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("[Mapper] is now [EntropySlam]"), std::string::npos) << warnings;
    // The overrides are checked under the new names too.
    mrpt::config::CConfigFileMemory reference;
    reference.write("StereoMatcher", "max_range", 10.0);
    EXPECT_NO_THROW(emslam::apps::requireValidOverrides({"Stereo.max_range=11"}, reference));
    emslam::test::expectThrowContaining(
        [&] { emslam::apps::requireValidOverrides({"Stereo.max_rang=11"}, reference); },
        {"max_rang"});
}

TEST(CommandLine, helpShowsTheProgramNameAndDefaults)
{
    const std::string eval = helpOf<emslam::apps::EvalApp>("emslam-eval");
    EXPECT_NE(eval.find("emslam-eval"), std::string::npos) << eval;
    EXPECT_EQ(eval.find("(required)  --"), std::string::npos) << eval;
    EXPECT_NE(eval.find("(default: se3)"), std::string::npos) << eval;
    EXPECT_NE(eval.find("(default: 0.02)"), std::string::npos) << eval;
    EXPECT_NE(eval.find("(default: 10)"), std::string::npos) << eval;
    const std::string odo = helpOf<emslam::apps::OdometryApp>("emslam-odometry");
    EXPECT_NE(odo.find("   emslam-odometry "), std::string::npos) << odo;
    EXPECT_NE(odo.find("(default: 0)"), std::string::npos) << odo;
    const std::string stereo = helpOf<emslam::apps::StereoApp>("emslam-stereo");
    EXPECT_NE(stereo.find("(default: CAMERA)"), std::string::npos) << stereo;
}

// An unknown flag is named as unknown, before TCLAP complains about a
// required argument it never reached (on 80c9fba, `emslam-sim W.ini --bogus
// -o x.rawlog` said "missing required argument --output").
TEST(CommandLine, anUnknownFlagIsNamedInEveryApp)
{
    const std::vector<std::string> bogus = {"W.ini", "--bogus", "-o", "x.rawlog"};
    const std::initializer_list<std::string> expected = {"unknown option '--bogus'", "--help"};
    expectInitFails<emslam::apps::SimApp>("emslam-sim", bogus, expected);
    expectInitFails<emslam::apps::MapperApp>("emslam-mapper", bogus, expected);
    expectInitFails<emslam::apps::OdometryApp>("emslam-odometry", bogus, expected);
    expectInitFails<emslam::apps::StereoApp>("emslam-stereo", bogus, expected);
    expectInitFails<emslam::apps::EvalApp>("emslam-eval", bogus, expected);
    expectInitFails<emslam::apps::ImportApp>("emslam-import", {"kitti", "--bogus=3"}, expected);
    expectInitFails<emslam::apps::GrabberApp>("emslam-grabber", bogus, expected);
    expectInitFails<emslam::apps::ExperimentsApp>("emslam-experiments", bogus, expected);
    expectInitFails<emslam::apps::SimApp>("emslam-sim", {"W.ini", "-x"}, {"unknown option '-x'"});
}

TEST(CommandLine, knownOptionsPassWithValuesThatLookLikeOptions)
{
    TCLAP::CmdLine cmd("test", ' ', "0");
    TCLAP::ValueArg<double> offset("", "time-offset", "", false, 0.0, "S", cmd);
    TCLAP::ValueArg<std::string> out("o", "output", "", false, "", "F", cmd);
    TCLAP::SwitchArg quiet("q", "quiet", "", cmd);
    TCLAP::SwitchArg verbose("v", "verbose", "", cmd);
    using V = std::vector<std::string>;
    EXPECT_EQ(
        emslam::apps::requireKnownOptions(
            cmd, "p", {"--time-offset", "-5", "-o", "-dash.rawlog", "-qv", "-.5", "--", "--x"}),
        (V{"--time-offset", "-5", "-o", "-dash.rawlog", "-qv", "-.5", "--", "--x"}));
    // GNU style --name=value is split for TCLAP.
    EXPECT_EQ(
        emslam::apps::requireKnownOptions(cmd, "p", {"--output=a=b.rawlog", "--time-offset=-1"}),
        (V{"--output", "a=b.rawlog", "--time-offset", "-1"}));
    emslam::test::expectThrowContaining(
        [&] { emslam::apps::requireKnownOptions(cmd, "p", {"--quiet=1"}); },
        {"--quiet takes no value"});
    emslam::test::expectThrowContaining(
        [&] { emslam::apps::requireKnownOptions(cmd, "p", {"-qx"}); }, {"unknown option '-qx'"});
}

// One spelling of the frame limit: --max-frames everywhere; emslam-sim's and
// emslam-grabber's old --frames N is still taken, with a warning.
TEST(CommandLine, maxFramesIsTheFrameLimitOfEveryApp)
{
    for (const char* program : {"emslam-sim", "emslam-grabber"})
    {
        const std::string help = std::string(program) == "emslam-sim"
                                     ? helpOf<emslam::apps::SimApp>(program)
                                     : helpOf<emslam::apps::GrabberApp>(program);
        EXPECT_NE(help.find("--max-frames <N>"), std::string::npos) << help;
    }
    EXPECT_NE(
        helpOf<emslam::apps::MapperApp>("emslam-mapper").find("--max-frames <N>"),
        std::string::npos);
    EXPECT_NE(
        helpOf<emslam::apps::OdometryApp>("emslam-odometry").find("--max-frames <N>"),
        std::string::npos);
    const std::string dir = emslam::test::makeTempDir("max_frames_alias");
    emslam::apps::SimApp sim;
    testing::internal::CaptureStderr();
    initWith(
        sim, "emslam-sim",
        {emslam::test::sourceDir() + "/config/sim/hall_double_loop.ini", "-o", dir + "/a.rawlog",
         "--frames", "7"});
    const std::string warning = testing::internal::GetCapturedStderr();
    EXPECT_NE(warning.find("--frames is deprecated"), std::string::npos) << warning;
    ASSERT_TRUE(sim.max_frames.has_value());
    EXPECT_EQ(*sim.max_frames, 7u);
}

// An output that is one of the inputs is refused before any work, naming
// both (on 80c9fba each was overwritten, exit 0).
TEST(CommandLine, anOutputThatIsAnInputIsRefusedInEveryApp)
{
    const std::string dir = emslam::test::makeTempDir("outputs_are_inputs");
    const std::string world = dir + "/W.ini";
    std::filesystem::copy_file(
        emslam::test::sourceDir() + "/config/sim/hall_double_loop.ini", world);
    const std::string gt = dir + "/gt.tum";
    emslam::test::writeFile(gt, "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n");
    const std::string before = readFile(world);
    expectInitFails<emslam::apps::SimApp>(
        "emslam-sim", {world, "-o", world}, {"output rawlog '" + world + "' is the world file"});
    expectInitFails<emslam::apps::SimApp>(
        "emslam-sim",
        {world, "-o", dir + "/a.rawlog", "--gt-out",
         dir + "/../" + std::filesystem::path(dir).filename().string() + "/W.ini"},
        {"--gt-out", "is the world file '" + world + "'"});
    EXPECT_EQ(readFile(world), before);
    expectInitFails<emslam::apps::EvalApp>(
        "emslam-eval", {gt, gt, "--json", gt}, {"--json", "is the ground truth"});
    expectInitFails<emslam::apps::OdometryApp>(
        "emslam-odometry", {gt, "-o", gt}, {"output trajectory", "is the rawlog"});
    // A trajectory of an earlier run given as ground truth of the next one.
    std::filesystem::copy_file(gt, dir + "/trajectory_slam.tum");
    expectInitFails<emslam::apps::MapperApp>(
        "emslam-mapper",
        {emslam::test::sourceDir() + "/config/mapper/3dof-low-structured.ini", gt, "-o", dir,
         "--gt", dir + "/trajectory_slam.tum"},
        {"output '" + dir + "/trajectory_slam.tum' is the ground truth (--gt)"});
}
