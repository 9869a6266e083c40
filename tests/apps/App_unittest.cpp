// SPDX-License-Identifier: BSD-3-Clause
// The shared part of every emslam program (emslam::apps::App): the
// initialize() / run() flow, --help, and the --set / --max-frames / --quiet
// options, through a small program built on it the way the real ones are.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/App.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

namespace
{
/** A program with one [Demo] section (keys `count` and `name`), a
 * `--config` option and every shared option. */
class DemoApp : public emslam::apps::App
{
public:
    DemoApp() : App("emslam-demo") {}

    int runs{0};
    std::size_t max_frames_seen{0};
    bool quiet_seen{false};

protected:
    bool parseArguments(int argc, const char** argv) override
    {
        TCLAP::CmdLine cmd("A demo program.", ' ', "0.1");
        TCLAP::ValueArg<std::string> config("c", "config", "INI file", false, "", "INI", cmd);
        addSetOption(cmd, "Override: Demo.key=value");
        addMaxFramesOption(cmd, "Stop after N frames (0: all)");
        addQuietOption(cmd, "No progress");
        if (!parseCommandLine(cmd, argc, argv))
        {
            return false;
        }
        mrpt::config::CConfigFileMemory known;
        known.write("Demo", "count", 1);
        known.write("Demo", "name", "x");
        loadParameters(config.getValue(), &known);
        if (params.read_int("Demo", "count", 1) < 0)
        {
            usageError("Demo.count must be >= 0");
        }
        return true;
    }

    void execute() override
    {
        ++runs;
        max_frames_seen = maxFrames();
        quiet_seen = quiet();
    }
};

void init(DemoApp& app, std::vector<std::string> args)
{
    args.insert(args.begin(), "emslam-demo");
    auto argv = emslam::test::argvOf(args);
    app.initialize(static_cast<int>(argv.size()), argv.data());
}
}  // namespace

TEST(App, sharedOptionsAreReadAndRunExecutesOnce)
{
    DemoApp app;
    init(app, {"--max-frames", "7", "-q", "--set", "Demo.count=3"});
    EXPECT_FALSE(app.helpRequested());
    EXPECT_EQ(app.params.read_int("Demo", "count", 0), 3);
    app.run();
    EXPECT_EQ(app.runs, 1);
    EXPECT_EQ(app.max_frames_seen, 7U);
    EXPECT_TRUE(app.quiet_seen);

    DemoApp defaults;
    init(defaults, {});
    defaults.run();
    EXPECT_EQ(defaults.max_frames_seen, 0U);
    EXPECT_FALSE(defaults.quiet_seen);
}

TEST(App, helpMakesRunANoOp)
{
    DemoApp app;
    testing::internal::CaptureStdout();
    init(app, {"--help"});
    const std::string usage = testing::internal::GetCapturedStdout();
    EXPECT_TRUE(app.helpRequested());
    EXPECT_NE(usage.find("--max-frames"), std::string::npos);
    EXPECT_NE(usage.find("--set"), std::string::npos);
    app.run();
    EXPECT_EQ(app.runs, 0);
}

TEST(App, badSharedOptionsNameTheProblem)
{
    using emslam::test::expectThrowContaining;
    DemoApp a;
    expectThrowContaining([&] { init(a, {"--max-frames", "-1"}); }, {"--max-frames", "-1"});
    DemoApp b;
    expectThrowContaining(
        [&] {
            init(b, {"--set", "Demo.cuont=2"});
        },
        {"Demo", "cuont", "did you mean", "count"});
    DemoApp c;
    expectThrowContaining([&] { init(c, {"--set", "Demo.count=abc"}); }, {"count", "abc"});
    DemoApp d;
    expectThrowContaining(
        [&] {
            init(d, {"--set", "Demo.count=-2"});
        },
        {"bad command line", "Demo.count must be >= 0", "try emslam-demo --help"});
}

TEST(App, theConfigFileIsReadBeforeTheOverrides)
{
    const std::string ini = emslam::test::makeTempDir("app_unittest") + "/demo.ini";
    emslam::test::writeFile(ini, "[Demo]\ncount = 5\nname = from_file\n");
    DemoApp app;
    init(app, {"--config", ini, "--set", "Demo.count=9"});
    EXPECT_EQ(app.params.read_int("Demo", "count", 0), 9);
    EXPECT_EQ(app.params.read_string("Demo", "name", ""), "from_file");
    std::remove(ini.c_str());

    DemoApp missing;
    emslam::test::expectThrowContaining([&] { init(missing, {"--config", ini}); }, {"demo.ini"});
}
