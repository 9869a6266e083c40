// SPDX-License-Identifier: BSD-3-Clause
// emslam-run: stock MRPT apps read and create emslam's classes through the
// wrapper (rawlog-edit on entropy_map.bin and on a simulated rawlog;
// observations2map building a CEntropyVoxelMap from config/maps/entropy-map.ini).
// Skipped when the stock apps are not installed.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/SimApp.h>
#include <emslam/maps/CEntropyVoxelMap.h>

#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#ifdef EMSLAM_RUN_EXE
namespace
{
bool inPath(const std::string& program)
{
    const char* path = std::getenv("PATH");
    std::istringstream dirs(path ? path : "");
    for (std::string dir; std::getline(dirs, dir, ':');)
    {
        if (::access((dir + "/" + program).c_str(), X_OK) == 0)
        {
            return true;
        }
    }
    return false;
}

struct Result
{
    int code{-1};
    std::string output;  // stdout and stderr
};

/** Runs a shell command (stdin from /dev/null: the stock apps wait for a key
 * otherwise), with `timeout` as a guard. */
Result run(const std::string& command)
{
    Result r;
    FILE* p = ::popen(("timeout 60 " + command + " </dev/null 2>&1").c_str(), "r");
    if (!p)
    {
        return r;
    }
    char buf[4096];
    while (std::fgets(buf, sizeof(buf), p))
    {
        r.output += buf;
    }
    const int status = ::pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

/** A small entropy map (a 2 m x 2 m wall), serialized as emslam-mapper writes entropy_map.bin. */
std::string writeEntropyMapFile(const std::string& dir)
{
    emslam::maps::WeightedPointCloud c;
    for (int i = 0; i < 20; ++i)
    {
        for (int j = 0; j < 20; ++j)
        {
            c.points.emplace_back(0.1f * i, 0.1f * j, 3.0f);
        }
    }
    c.weights.assign(c.points.size(), 1.0f);
    emslam::CEntropyVoxelMap map;
    map.insertWeightedCloud(c, mrpt::poses::CPose3D());
    const std::string file = dir + "/entropy_map.bin";
    mrpt::io::CFileOutputStream f(file);
    mrpt::serialization::archiveFrom(f) << map;
    return file;
}

const std::string WRAPPER = EMSLAM_RUN_EXE;
}  // namespace

TEST(EmslamRun, helpAndMissingProgramAreClear)
{
    const Result help = run(WRAPPER + " --help");
    EXPECT_EQ(help.code, 0);
    EXPECT_NE(help.output.find("Usage: emslam-run PROGRAM"), std::string::npos) << help.output;
    const Result none = run(WRAPPER);
    EXPECT_EQ(none.code, 2);
    const Result missing = run(WRAPPER + " no-such-mrpt-program --info");
    EXPECT_EQ(missing.code, 127);
    EXPECT_NE(missing.output.find("program 'no-such-mrpt-program' not found"), std::string::npos)
        << missing.output;
}

TEST(EmslamRun, rawlogEditReadsTheEntropyMapOnlyThroughTheWrapper)
{
    if (!inPath("rawlog-edit"))
    {
        GTEST_SKIP() << "stock rawlog-edit not installed (Debian package mrpt-apps)";
    }
    const std::string file = writeEntropyMapFile(emslam::test::makeTempDir("emslam_run_edit"));

    const std::string one_object = "Overall number of objects         : 1\n";
    const Result plain = run("rawlog-edit --info -i " + file);
    EXPECT_NE(plain.output.find("which is not registered"), std::string::npos) << plain.output;

    const Result wrapped = run(WRAPPER + " rawlog-edit --info -i " + file);
    EXPECT_EQ(wrapped.code, 0) << wrapped.output;
    EXPECT_EQ(wrapped.output.find("not registered"), std::string::npos) << wrapped.output;
    EXPECT_NE(wrapped.output.find(one_object), std::string::npos) << wrapped.output;
}

TEST(EmslamRun, rawlogEditReadsASimulatedRawlog)
{
    if (!inPath("rawlog-edit"))
    {
        GTEST_SKIP() << "stock rawlog-edit not installed (Debian package mrpt-apps)";
    }
    const std::string dir = emslam::test::makeTempDir("emslam_run_sim");
    emslam::apps::SimApp sim;
    const std::vector<std::string> args = {
        "emslam-sim",   emslam::test::sourceDir() + "/config/sim/hall_double_loop.ini",
        "-o",           dir + "/sim.rawlog",
        "--max-frames", "3",
        "--quiet"};
    std::vector<const char*> argv;
    for (const auto& a : args)
    {
        argv.push_back(a.c_str());
    }
    sim.initialize(static_cast<int>(argv.size()), argv.data());
    sim.run();
    const Result r = run(WRAPPER + " rawlog-edit --info -i " + dir + "/sim.rawlog");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("Overall number of objects         : 3\n"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("STEREO /      3"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("not registered"), std::string::npos) << r.output;
}

TEST(EmslamRun, observations2mapCreatesTheEntropyMapFromTheShippedIni)
{
    if (!inPath("observations2map"))
    {
        GTEST_SKIP() << "stock observations2map not installed (Debian package mrpt-apps)";
    }
    const std::string dir = emslam::test::makeTempDir("emslam_run_o2m");
    // Two observations of a 3 m x 2 m wall, 0.5 m apart.
    mrpt::maps::CSimpleMap sm;
    for (int k = 0; k < 2; ++k)
    {
        auto pts = mrpt::maps::CSimplePointsMap::Create();
        for (int i = 0; i < 30; ++i)
        {
            for (int j = 0; j < 20; ++j)
            {
                pts->insertPoint(4.0f, -1.5f + 0.1f * i, -1.0f + 0.1f * j);
            }
        }
        auto obs = mrpt::obs::CObservationPointCloud::Create();
        obs->pointcloud = pts;
        auto sf = mrpt::obs::CSensoryFrame::Create();
        sf->insert(obs);
        sm.insert(
            mrpt::poses::CPose3DPDFGaussian(mrpt::poses::CPose3D(0.5 * k, 0, 0, 0, 0, 0)), *sf);
    }
    const std::string simplemap = dir + "/obs.simplemap";
    ASSERT_TRUE(sm.saveToFile(simplemap));
    const std::string ini = emslam::test::sourceDir() + "/config/maps/entropy-map.ini";
    const std::string args = ini + " " + simplemap + " " + dir + "/out -s EntropyVoxelMap";

    const auto cellsFiles = [&]
    {
        std::vector<std::string> files;
        for (const auto& e : std::filesystem::directory_iterator(dir))
        {
            const std::string name = e.path().filename().string();
            if (name.find("CEntropyVoxelMap") != std::string::npos &&
                name.find("_cells.txt") != std::string::npos)
            {
                files.push_back(e.path().string());
            }
        }
        return files;
    };
    const Result plain = run("observations2map " + args);
    EXPECT_TRUE(cellsFiles().empty()) << plain.output;  // the class is silently ignored

    const Result wrapped = run(WRAPPER + " observations2map " + args);
    EXPECT_EQ(wrapped.code, 0) << wrapped.output;
    const auto files = cellsFiles();
    ASSERT_EQ(files.size(), 1U) << wrapped.output;
    std::ifstream in(files.front());
    std::size_t cells = 0;
    for (std::string line; std::getline(in, line);)
    {
        cells += !line.empty() && line[0] != '%';
    }
    // The wall (3 m x 2 m) at cell size 0.15 m: about 20 x 14 cells.
    EXPECT_GT(cells, 150U);
    EXPECT_LT(cells, 800U);
}
#endif
