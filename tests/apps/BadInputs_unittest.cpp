// SPDX-License-Identifier: BSD-3-Clause
// The bad-input matrix (doc/reliability.md): every input of the reliability
// rounds run against the built apps, checking exit code, message and outputs.
// Each test prints its row of the table.
#include "PngWithSize.h"
#include "SimulatedHall.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/TumTrajectory.h>

#include <mrpt/obs/CObservationStereoImages.h>

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#if defined(EMSLAM_MAPPER_EXE) && defined(EMSLAM_ODOMETRY_EXE) && defined(EMSLAM_STEREO_EXE) && \
    defined(EMSLAM_EVAL_EXE) && defined(EMSLAM_EXPERIMENTS_EXE)

namespace fs = std::filesystem;
using emslam::test::ProgramRun;
using emslam::test::runProgram;

namespace
{
constexpr std::size_t FRAMES = 300;

std::string source(const std::string& relative)
{
    return emslam::test::sourceDir() + "/" + relative;
}

std::string mapperConfig()
{
    return source("config/mapper/3dof-low-structured.ini");
}

std::string readText(const std::string& file)
{
    std::ifstream f(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
}

/** Prints one row of the matrix: the input, the exit code, what it said. */
void row(const std::string& input, int exit_code, const std::string& outcome)
{
    std::printf("| %s | %d | %s |\n", input.c_str(), exit_code, outcome.c_str());
}

/** The first line of `text` that holds `part`, for the table. */
std::string lineWith(const std::string& text, const std::string& part)
{
    const auto at = text.find(part);
    if (at == std::string::npos)
    {
        return "(not found: " + part + ")";
    }
    const auto begin = text.rfind('\n', at);
    const auto end = text.find('\n', at);
    return text.substr(
        begin == std::string::npos ? 0 : begin + 1,
        (end == std::string::npos ? text.size() : end) -
            (begin == std::string::npos ? 0 : begin + 1));
}

void expectRefused(const ProgramRun& run, const std::string& input, const std::string& message)
{
    EXPECT_EQ(run.exit_code, 1) << run.stderr_text;
    EXPECT_NE(run.stderr_text.find(message), std::string::npos) << run.stderr_text;
    row(input, run.exit_code, lineWith(run.stderr_text, message));
}

/** True if the times of the TUM file strictly increase. */
bool strictlyIncreasing(const std::string& tum)
{
    const auto t = emslam::test::trajectoryTimes(tum);
    for (std::size_t i = 1; i < t.size(); ++i)
    {
        if (!(t[i] > t[i - 1]))
        {
            return false;
        }
    }
    return !t.empty();
}
}  // namespace

TEST(BadInputs, sighupStopsTheMapperWithEveryOutput)
{
    const std::string out = emslam::test::makeTempDir("bad_sighup_mapper");
    const auto run = emslam::test::interruptedRun(
        EMSLAM_MAPPER_EXE, {mapperConfig(), emslam::test::simulatedHall(FRAMES), "--out", out},
        "frame ", SIGHUP);
    ASSERT_TRUE(run.exited) << run.stderr_text;
    EXPECT_EQ(run.exit_code, 129) << run.stderr_text;
    EXPECT_LT(run.seconds_to_exit, 30.0);
    const auto slam = emslam::io::TumTrajectory::fromFile(out + "/trajectory_slam.tum");
    EXPECT_GT(slam.size(), 0U);
    EXPECT_LT(slam.size(), FRAMES);
    const std::string json = readText(out + "/summary.json");
    EXPECT_NE(json.find("\"interrupted\": true"), std::string::npos) << json;
    for (const char* f : {"stats.csv", "map.ply", "map.3Dscene", "report.html"})
    {
        EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
    }
    row("SIGHUP to `emslam-mapper`", run.exit_code,
        "stops after the current frame (" + std::to_string(run.seconds_to_exit).substr(0, 4) +
            " s); every output of the " + std::to_string(slam.size()) + " frames mapped");
}

TEST(BadInputs, sigintDuringTheLoopClosingEndsItWithEveryOutput)
{
    const std::string out = emslam::test::makeTempDir("bad_sigint_end");
    const auto run = emslam::test::interruptedRun(
        EMSLAM_MAPPER_EXE, {mapperConfig(), emslam::test::simulatedHall(FRAMES), "--out", out},
        "(100%)", SIGINT);
    ASSERT_TRUE(run.exited) << run.stderr_text;
    EXPECT_EQ(run.exit_code, 130) << run.stderr_text;
    EXPECT_LT(run.seconds_to_exit, 60.0);
    EXPECT_EQ(emslam::io::TumTrajectory::fromFile(out + "/trajectory_slam.tum").size(), FRAMES);
    const std::string json = readText(out + "/summary.json");
    EXPECT_NE(json.find("\"interrupted\": true"), std::string::npos) << json;
    row("SIGINT after the last frame (loop closing, polish)", run.exit_code,
        "ends in " + std::to_string(run.seconds_to_exit).substr(0, 4) +
            " s with every output, `\"interrupted\": true`");
}

TEST(BadInputs, sighupAndSigtermStopOdometryStereoAndSimWithTheirOutputs)
{
    for (const int signum : {SIGHUP, SIGTERM})
    {
        const std::string out = emslam::test::makeTempDir("bad_signal_odometry");
        const auto run = emslam::test::interruptedRun(
            EMSLAM_ODOMETRY_EXE, {emslam::test::simulatedHall(FRAMES), "-o", out + "/t.tum"},
            "frame 5:", signum);
        ASSERT_TRUE(run.exited) << run.stderr_text;
        EXPECT_EQ(run.exit_code, 128 + signum) << run.stderr_text;
        const auto t = emslam::io::TumTrajectory::fromFile(out + "/t.tum");
        EXPECT_GE(t.size(), 6U);
        EXPECT_LT(t.size(), FRAMES);
        row(std::string(signum == SIGHUP ? "SIGHUP" : "SIGTERM") + " to `emslam-odometry`",
            run.exit_code, lineWith(run.stderr_text, "interrupted after"));
    }
    {
        const std::string out = emslam::test::makeTempDir("bad_signal_stereo");
        const auto run = emslam::test::interruptedRun(
            EMSLAM_STEREO_EXE,
            {emslam::test::simulatedHall(FRAMES), "--out-rawlog", out + "/scans.rawlog"},
            "frame 5:", SIGHUP);
        ASSERT_TRUE(run.exited) << run.stderr_text;
        EXPECT_EQ(run.exit_code, 129) << run.stderr_text;
        EXPECT_TRUE(fs::exists(out + "/scans.rawlog"));
        EXPECT_FALSE(fs::exists(out + "/scans.rawlog.partial"));
        row("SIGHUP to `emslam-stereo`", run.exit_code,
            lineWith(run.stderr_text, "interrupted after"));
    }
    {
        const std::string out = emslam::test::makeTempDir("bad_signal_sim");
        const auto run = emslam::test::interruptedRun(
            EMSLAM_SIM_EXE,
            {source("config/sim/hall_double_loop.ini"), "-o", out + "/hall.rawlog", "--gt-out",
             out + "/hall.tum", "--max-frames", "400"},
            "frame ", SIGHUP);
        ASSERT_TRUE(run.exited) << run.stderr_text;
        EXPECT_EQ(run.exit_code, 129) << run.stderr_text;
        EXPECT_FALSE(fs::exists(out + "/hall.rawlog.partial"));
        EXPECT_GT(emslam::io::TumTrajectory::fromFile(out + "/hall.tum").size(), 0U);
        row("SIGHUP to `emslam-sim`", run.exit_code,
            lineWith(run.stderr_text, "interrupted after"));
    }
}

TEST(BadInputs, odometryWithOneBadFrameWritesTheTrajectory)
{
    const std::string dir = emslam::test::makeTempDir("bad_odometry_frame");
    emslam::test::writeEditedHall(
        dir + "/one_bad.rawlog", 20,
        [](std::size_t i, mrpt::obs::CObservationStereoImages& s)
        {
            if (i == 7)
            {
                emslam::test::shrinkRightImage(s);
            }
        });
    const auto run =
        runProgram(EMSLAM_ODOMETRY_EXE, {dir + "/one_bad.rawlog", "-o", dir + "/t.tum"});
    EXPECT_EQ(run.exit_code, 0) << run.stderr_text;
    EXPECT_EQ(emslam::io::TumTrajectory::fromFile(dir + "/t.tum").size(), 19U);
    row("`emslam-odometry`, one frame with a 160×120 right image", run.exit_code,
        lineWith(run.stderr_text, "skipping"));
}

TEST(BadInputs, anOutputThatIsAnInputIsRefusedAndLeftAlone)
{
    const std::string dir = emslam::test::makeTempDir("bad_output_input");
    const std::string world = dir + "/W.ini";
    fs::copy_file(source("config/sim/hall_double_loop.ini"), world);
    const std::string before = readText(world);
    expectRefused(
        runProgram(EMSLAM_SIM_EXE, {world, "-o", world}), "`emslam-sim W.ini -o W.ini`",
        "is the world file");
    expectRefused(
        runProgram(EMSLAM_SIM_EXE, {world, "-o", dir + "/x.rawlog", "--gt-out", world}),
        "`emslam-sim W.ini --gt-out W.ini`", "is the world file");
    EXPECT_EQ(readText(world), before);
    const std::string gt = dir + "/GT.tum";
    emslam::test::writeFile(gt, "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n");
    expectRefused(
        runProgram(EMSLAM_EVAL_EXE, {gt, gt, "--json", gt}),
        "`emslam-eval GT.tum GT.tum --json GT.tum`", "is the ground truth");
}

TEST(BadInputs, rawlogStampsDuplicatedBackwardsOrInvalidAreSkippedAndCounted)
{
    const std::string dir = emslam::test::makeTempDir("bad_stamps");
    mrpt::Clock::time_point previous;
    emslam::test::writeEditedHall(
        dir + "/stamps.rawlog", 30,
        [&](std::size_t i, mrpt::obs::CObservationStereoImages& s)
        {
            const auto own = s.timestamp;
            if (i == 10)
            {
                s.timestamp = previous;
            }
            if (i == 15)
            {
                s.timestamp = own - std::chrono::seconds(1);
            }
            if (i == 20)
            {
                s.timestamp = INVALID_TIMESTAMP;
            }
            previous = own;
        });
    const auto run = runProgram(
        EMSLAM_MAPPER_EXE, {mapperConfig(), dir + "/stamps.rawlog", "--out", dir + "/out"});
    EXPECT_EQ(run.exit_code, 0) << run.stderr_text;
    EXPECT_TRUE(strictlyIncreasing(dir + "/out/trajectory_slam.tum"));
    const std::string json = readText(dir + "/out/summary.json");
    EXPECT_NE(json.find("\"skipped_bad_stamps\": 3"), std::string::npos) << json;
    row("rawlog stamps duplicated, 1 s back, invalid", run.exit_code,
        "skipped, named, counted (`skipped_bad_stamps`: 3); the trajectory increases");
}

TEST(BadInputs, aCameraChangedForGoodIsMappedAsFarAsTheFirstCameraGoes)
{
    const std::string dir = emslam::test::makeTempDir("bad_camera");
    emslam::test::writeEditedHall(
        dir + "/camera.rawlog", 30,
        [](std::size_t i, mrpt::obs::CObservationStereoImages& s)
        {
            if (i >= 15)
            {
                emslam::test::resizeStereoFrame(s, 640, 480);
            }
        });
    const auto run = runProgram(
        EMSLAM_MAPPER_EXE, {mapperConfig(), dir + "/camera.rawlog", "--out", dir + "/out"});
    EXPECT_EQ(run.exit_code, 0) << run.stderr_text;
    EXPECT_EQ(emslam::io::TumTrajectory::fromFile(dir + "/out/trajectory_slam.tum").size(), 15U);
    EXPECT_NE(run.stderr_text.find("camera changed from"), std::string::npos) << run.stderr_text;
    row("a rawlog whose camera changes (320×240 → 640×480 at frame 15)", run.exit_code,
        lineWith(run.stderr_text, "camera changed from"));
}

TEST(BadInputs, aClosedStdoutPipeKeepsTheExitCode)
{
    const std::string out = emslam::test::makeTempDir("bad_sigpipe");
    const int rc = emslam::test::runWithStdoutReaderGone(
        EMSLAM_MAPPER_EXE, {mapperConfig(), emslam::test::simulatedHall(20), "--out", out});
    EXPECT_EQ(rc, 0);
    EXPECT_TRUE(fs::exists(out + "/summary.json"));
    row("`emslam-mapper … | true`", rc, "complete run, exit 0 (the console text is lost)");
}

TEST(BadInputs, evalRefusesAbsurdCoordinatesAndPrintsStampsExactly)
{
    const std::string dir = emslam::test::makeTempDir("bad_eval");
    emslam::test::writeFile(dir + "/gt.tum", "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n2 2 0 0 0 0 0 1\n");
    emslam::test::writeFile(
        dir + "/huge.tum", "0 0 0 0 0 0 0 1\n1 1e300 0 0 0 0 0 1\n2 2 0 0 0 0 0 1\n");
    expectRefused(
        runProgram(EMSLAM_EVAL_EXE, {dir + "/gt.tum", dir + "/huge.tum"}),
        "`emslam-eval`: an estimate with 1e300 coordinates", "lies at (1e+300, 0, 0) m");
    emslam::test::writeFile(
        dir + "/late.tum", "2317340800 0 0 0 0 0 0 1\n2317340801.000001 1 0 0 0 0 0 1\n");
    expectRefused(
        runProgram(EMSLAM_EVAL_EXE, {dir + "/gt.tum", dir + "/late.tum"}),
        "`emslam-eval`: no overlap", "estimate [2317340800, 2317340801.000001] s");
}

TEST(BadInputs, anUnknownFlagIsNamed)
{
    expectRefused(
        runProgram(
            EMSLAM_SIM_EXE,
            {source("config/sim/hall_double_loop.ini"), "--bogus", "-o", "x.rawlog"}),
        "`emslam-sim W.ini --bogus -o x.rawlog`", "unknown option '--bogus'");
}

/** A EuRoC folder of the first `n` stereo pairs of the real excerpt with
 * cam0's stamps replaced by `stamps` (empty if the data is absent). */
std::string eurocWithStamps(const std::string& name, const std::vector<std::string>& stamps)
{
    const std::string mav0 = emslam::test::testDataPath("euroc-v101-rest/mav0");
    if (mav0.empty())
    {
        return {};
    }
    const std::string dir = emslam::test::makeTempDir("bad_euroc_" + name) + "/mav0";
    for (const char* cam : {"cam0", "cam1"})
    {
        fs::create_directories(dir + "/" + cam + "/data");
        fs::copy_file(mav0 + "/" + cam + "/sensor.yaml", dir + "/" + cam + "/sensor.yaml");
        std::ifstream list(mav0 + "/" + cam + "/data.csv");
        std::string line, csv;
        std::getline(list, line);
        csv = line + "\n";
        for (std::size_t i = 0; i < stamps.size() && std::getline(list, line); ++i)
        {
            const std::string stamp = line.substr(0, line.find(','));
            fs::copy_file(
                mav0 + "/" + cam + "/data/" + stamp + ".png",
                dir + "/" + cam + "/data/" + stamp + ".png");
            csv += (std::string(cam) == "cam0" ? stamps[i] : stamp) + "," + stamp + ".png\n";
        }
        emslam::test::writeFile(dir + "/" + cam + "/data.csv", csv);
    }
    return dir;
}

TEST(BadInputs, eurocStampsRepeatedZeroHugeOrFractionalAreRefusedWithFileAndLine)
{
    const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
        {"a stamp of cam0 repeated",
         {"1403715274312143104", "1403715274362142976", "1403715274312143104"}},
        {"a stamp of 0 in the middle", {"1403715274312143104", "0", "1403715274412143104"}},
        {"INT64_MAX in the middle",
         {"1403715274312143104", "9223372036854775807", "1403715274412143104"}},
        {"a fraction of a nanosecond",
         {"1403715274312143104", "1403715274362142976.5", "1403715274412143104"}}};
    for (const auto& [what, stamps] : cases)
    {
        const std::string mav0 = eurocWithStamps(std::to_string(&what - &cases[0].first), stamps);
        if (mav0.empty())
        {
            GTEST_SKIP() << "test data 'euroc-v101-rest' not found";
        }
        const auto run =
            runProgram(EMSLAM_IMPORT_EXE, {"euroc", mav0, "-o", mav0 + "/../e.rawlog", "-q"});
        expectRefused(run, "EuRoC `data.csv`: " + what, "cam0/data.csv:");
        EXPECT_FALSE(fs::exists(mav0 + "/../e.rawlog"));
    }
}

TEST(BadInputs, aHugePngIsRefusedFromItsHeader)
{
    const std::string dir = emslam::test::makeTempDir("bad_png");
    const std::string seq = dir + "/seq";
    for (const char* sub : {"image_0", "image_1"})
    {
        fs::create_directories(seq + "/" + sub);
        for (int i = 0; i < 2; ++i)
        {
            cv::imwrite(
                seq + "/" + sub + "/00000" + std::to_string(i) + ".png",
                cv::Mat(24, 40, CV_8UC1, cv::Scalar(i)));
        }
    }
    emslam::test::writeFile(seq + "/times.txt", "0\n0.1\n");
    emslam::test::writeFile(
        seq + "/calib.txt", "P0: 50 0 20 0 0 50 12 0 0 0 1 0\nP1: 50 0 20 -25 0 50 12 0 0 0 1 0\n");
    // Frame 1's left image declares 30000x30000 in its header (IHDR and CRC patched).
    emslam::test::writePngDeclaring(seq + "/image_0/000001.png", 30000, 30000);
    const auto t0 = std::chrono::steady_clock::now();
    const auto run = runProgram(EMSLAM_IMPORT_EXE, {"kitti", seq, "-o", dir + "/k.rawlog", "-q"});
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    expectRefused(run, "a 30000×30000 PNG in a KITTI folder", "30000x30000");
    std::printf("refused in %.2f s\n", seconds);
}

TEST(BadInputs, aRepeatedIniKeyOrSectionIsRefusedNamingBothLines)
{
    const std::string dir = emslam::test::makeTempDir("bad_ini");
    std::string text = readText(mapperConfig());
    emslam::test::writeFile(dir + "/key.ini", text + "\n[EgomotionEstimator]\nwindow_size = 9\n");
    expectRefused(
        runProgram(
            EMSLAM_MAPPER_EXE,
            {dir + "/key.ini", emslam::test::simulatedHall(20), "--out", dir + "/out"}),
        "mapper INI with a repeated section", "section [EgomotionEstimator] repeated (first at");
    const std::string world = readText(source("config/sim/hall_double_loop.ini"));
    emslam::test::writeFile(dir + "/w.ini", world + "\n[Camera]\nbaseline = 0.2\n");
    expectRefused(
        runProgram(EMSLAM_SIM_EXE, {dir + "/w.ini", "-o", dir + "/x.rawlog"}),
        "sim world with a repeated section", "repeated (first at");
}

TEST(BadInputs, aHugeSparseSuiteIsRefusedAtOnce)
{
    const std::string dir = emslam::test::makeTempDir("bad_suite");
    {
        std::ofstream f(dir + "/suite.ini");
        f << "[Suite]\n";
    }
    fs::resize_file(dir + "/suite.ini", std::uintmax_t{2} << 30);  // sparse: no disk used
    const auto run =
        runProgram(EMSLAM_EXPERIMENTS_EXE, {dir + "/suite.ini", "--out", dir + "/out"});
    expectRefused(run, "a 2 GB sparse suite INI to `emslam-experiments`", "2048.0 MiB");
}

TEST(BadInputs, aFullDiskNamesTheFileAndTheReason)
{
    const std::string dir = emslam::test::makeTempDir("bad_full");
    emslam::test::putOnFullDisk(dir + "/full.rawlog");
    const auto run = runProgram(
        EMSLAM_SIM_EXE, {source("config/sim/hall_double_loop.ini"), "-o", dir + "/full.rawlog",
                         "--max-frames", "3", "-q"});
    expectRefused(run, "full disk (`emslam-sim`)", "No space left on device");
    EXPECT_NE(run.stderr_text.find("full.rawlog"), std::string::npos) << run.stderr_text;
}

TEST(BadInputs, theLevellingBiasOfAShortRunIsNotReported)
{
    const std::string out = emslam::test::makeTempDir("bad_levelling");
    const auto run = runProgram(
        EMSLAM_MAPPER_EXE, {mapperConfig(), emslam::test::simulatedHall(60), "--out", out});
    EXPECT_EQ(run.exit_code, 0) << run.stderr_text;
    const std::string json = readText(out + "/summary.json");
    EXPECT_NE(json.find("\"vertical_bias_deg\": null"), std::string::npos) << json;
    row("the first 60 frames of the hall", run.exit_code,
        lineWith(run.stdout_text + run.stderr_text, "levelling:"));
}

TEST(BadInputs, aLongLineOfABadSensorYamlIsCutInTheMessage)
{
    EMSLAM_REQUIRE_TEST_DATA(mav0, "euroc-v101-rest/mav0");
    const std::string dir = eurocWithStamps(
        "yaml", {"1403715274312143104", "1403715274362142976", "1403715274412143104"});
    emslam::test::writeFile(
        dir + "/cam0/sensor.yaml",
        readText(mav0 + "/cam0/sensor.yaml") + std::string(100000, 'x') + "\n");
    const auto run = runProgram(EMSLAM_IMPORT_EXE, {"euroc", dir, "-o", dir + "/../e.rawlog"});
    EXPECT_EQ(run.exit_code, 1) << run.stderr_text.substr(0, 500);
    EXPECT_LT(run.stderr_text.size(), 1000U);
    row("a 100,000-character line in a bad `sensor.yaml`", run.exit_code,
        lineWith(run.stderr_text, "error"));
}

TEST(BadInputs, importOutputsThatAreInputsAreRefused)
{
    const std::string mav0 = eurocWithStamps(
        "outputs", {"1403715274312143104", "1403715274362142976", "1403715274412143104"});
    if (mav0.empty())
    {
        GTEST_SKIP() << "test data 'euroc-v101-rest' not found";
    }
    const std::string image = mav0 + "/cam0/data/1403715274362142976.png";
    const std::string before = readText(image);
    expectRefused(
        runProgram(EMSLAM_IMPORT_EXE, {"euroc", mav0, "-o", image}),
        "`emslam-import … -o DIR/cam0/data/….png`", "is a file of the dataset");
    EXPECT_EQ(readText(image), before);
}

#endif
