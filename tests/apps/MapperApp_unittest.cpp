// SPDX-License-Identifier: BSD-3-Clause
// emslam-mapper end to end: a small simulated rawlog through the app, every
// output read back; truncated rawlogs; Ctrl-C; each bad input.
#include "SimulatedHall.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/AppMain.h>
#include <emslam/apps/EntropyVoxelObject.h>
#include <emslam/apps/ImportApp.h>
#include <emslam/apps/MapScene.h>
#include <emslam/apps/MapperApp.h>
#include <emslam/apps/SimApp.h>
#include <emslam/eval/PointKdTree.h>
#include <emslam/eval/TrajectoryMetrics.h>
#include <emslam/io/RawlogInput.h>
#include <emslam/io/TrajectoryReader.h>
#include <emslam/io/TumTrajectory.h>
#include <emslam/maps/CEntropyVoxelMap.h>
#include <emslam/sim/StereoSimulator.h>
#include <emslam/sim/SurfaceSampler.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <gtest/gtest.h>

#include <octomap/OcTree.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace
{
using emslam::apps::MapperApp;
using emslam::test::simulatedHall;
using emslam::test::writeEditedHall;

std::vector<const char*> argvOf(const std::vector<std::string>& args)
{
    std::vector<const char*> argv;
    for (const auto& a : args)
    {
        argv.push_back(a.c_str());
    }
    return argv;
}

void initApp(MapperApp& app, std::vector<std::string> args)
{
    args.insert(args.begin(), "emslam-mapper");
    auto argv = argvOf(args);
    app.initialize(static_cast<int>(argv.size()), argv.data());
}

std::string config(const std::string& name)
{
    return emslam::test::sourceDir() + "/config/mapper/" + name + ".ini";
}

std::string readText(const std::string& file)
{
    std::ifstream in(file, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string groundTruthOf(const std::string& rawlog)
{
    return rawlog.substr(0, rawlog.size() - 7) + ".tum";
}

/** Runs the app in-process on `rawlog`; returns the output folder. */
std::string mapRawlog(
    const std::string& rawlog, const std::string& out_name, std::vector<std::string> extra = {})
{
    const std::string out = emslam::test::makeTempDir(out_name);
    MapperApp app;
    std::vector<std::string> args = {
        config("3dof-low-structured"), rawlog, "--out", out, "-q", "--set",
        "Rectifier.rectify_every=10"};
    args.insert(args.end(), extra.begin(), extra.end());
    initApp(app, args);
    app.run();
    return out;
}

std::size_t countLinesStartingWith(const std::string& text, const std::string& prefix)
{
    std::size_t n = 0;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
    {
        n += line.rfind(prefix, 0) == 0;
    }
    return n;
}
}  // namespace

TEST(MapperApp, everyShippedConfigLoads)
{
    for (const auto& entry :
         std::filesystem::directory_iterator(emslam::test::sourceDir() + "/config/mapper"))
    {
        SCOPED_TRACE(entry.path().string());
        MapperApp app;
        EXPECT_NO_THROW(initApp(app, {entry.path().string(), simulatedHall(8), "--out", "/tmp/x"}));
    }
}

TEST(MapperApp, exportMaxHeightLoadsSavesAndRejectsNan)
{
    using Options = emslam::slam::EntropySlam::TOptions;
    Options defaults;
    EXPECT_TRUE(std::isinf(defaults.export_max_height));
    mrpt::config::CConfigFileMemory saved;
    defaults.saveToConfigFile(saved, "EntropySlam");
    Options back;
    back.export_max_height = 3.0;
    back.loadFromConfigFile(mrpt::config::CConfigFileMemory(saved.getContent()), "EntropySlam");
    EXPECT_TRUE(std::isinf(back.export_max_height) && back.export_max_height > 0);

    back.loadFromConfigFile(
        mrpt::config::CConfigFileMemory("[EntropySlam]\nexport_max_height = 1.25\n"),
        "EntropySlam");
    EXPECT_DOUBLE_EQ(back.export_max_height, 1.25);
    emslam::test::expectThrowContaining(
        [&]
        {
            back.loadFromConfigFile(
                mrpt::config::CConfigFileMemory("[EntropySlam]\nexport_max_height = nan\n"),
                "EntropySlam");
        },
        {"[EntropySlam] export_max_height"});
}

TEST(MapperApp, helpDoesNotRun)
{
    MapperApp app;
    initApp(app, {"--help"});
    EXPECT_TRUE(app.helpRequested());
    EXPECT_NO_THROW(app.run());
}

// map.bt, read back by OctoMap itself, against the simulated world: its
// occupied voxels lie on the true surfaces within the stereo noise, its free
// space between the cameras and the walls, inside the hall.
TEST(MapperApp, mapsAnOctoMapThatMatchesTheWorld)
{
    const std::string rawlog = simulatedHall(60);
    const std::string out = mapRawlog(rawlog, "mapper_octomap");
    octomap::OcTree tree(0.5);
    ASSERT_TRUE(tree.readBinary(out + "/map.bt"));
    EXPECT_NEAR(tree.getResolution(), 0.1, 1e-9);

    emslam::sim::StereoSimulator sim;
    sim.loadFile(emslam::test::sourceDir() + "/config/sim/hall_double_loop.ini");
    emslam::sim::SurfaceSampler::TParameters sp;
    sp.spacing = 0.05;
    std::vector<mrpt::math::TPoint3Df> surface;
    for (const auto& s : emslam::sim::SurfaceSampler(sp).visibleSurfaces(sim, 60))
    {
        surface.emplace_back(s.position[0], s.position[1], s.position[2]);
    }
    const emslam::eval::PointKdTree truth(surface);
    std::size_t occupied = 0, on_surface = 0, free = 0, inside = 0;
    for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it)
    {
        const mrpt::math::TPoint3Df c(it.getX(), it.getY(), it.getZ());
        if (tree.isNodeOccupied(*it))
        {
            float d2 = 0;
            truth.nearest(c, d2);
            ++occupied;
            on_surface += d2 <= 0.3F * 0.3F ? 1 : 0;
        }
        else
        {
            // The hall's floor is 1 m below the first camera (y down), its
            // ceiling 2.5 m above.
            ++free;
            inside += c.y > -2.5F && c.y < 1.0F ? 1 : 0;
        }
    }
    EXPECT_GT(occupied, 1000U);
    EXPECT_GT(free, 1000U);
    const double on_surface_share = static_cast<double>(on_surface) / static_cast<double>(occupied);
    const double inside_share = static_cast<double>(inside) / static_cast<double>(free);
    EXPECT_GT(on_surface_share, 0.0) << "occupied voxels within 0.3 m of a true surface";
    EXPECT_GT(inside_share, 0.0) << "free voxels inside the hall";
    std::printf(
        "map.bt: %zu occupied (%.3f on a surface), %zu free (%.3f inside)\n", occupied,
        on_surface_share, free, inside_share);
}

TEST(MapperApp, mapsASimulatedRawlogAndWritesEveryOutput)
{
    const std::string rawlog = simulatedHall(60);
    const std::string out =
        mapRawlog(rawlog, "mapper_outputs", {"--gt", groundTruthOf(rawlog), "--energy-scan"});

    const auto ego = emslam::io::TumTrajectory::fromFile(out + "/trajectory_egomotion.tum");
    const auto slam = emslam::io::TumTrajectory::fromFile(out + "/trajectory_slam.tum");
    EXPECT_EQ(ego.size(), 60U);
    EXPECT_EQ(slam.size(), 60U);  // every frame, keyframes or not
    // Space sampling drops the on-the-spot slow frames: fewer keyframes.
    const std::string keyframes = readText(out + "/keyframes.txt");
    const std::size_t keyframe_lines =
        countLinesStartingWith(keyframes, "") - countLinesStartingWith(keyframes, "#");
    EXPECT_GT(keyframe_lines, 20U);
    EXPECT_LT(keyframe_lines, 60U);

    // The map: a binary PLY whose size matches its header.
    const std::string ply = readText(out + "/map.ply");
    const auto header_end = ply.find("end_header\n");
    ASSERT_NE(header_end, std::string::npos);
    const auto pos = ply.find("element vertex ");
    const std::size_t vertices = std::stoul(ply.substr(pos + 15));
    EXPECT_GT(vertices, 1000U);
    EXPECT_EQ(ply.size() - header_end - 11, vertices * 15);

    mrpt::opengl::COpenGLScene scene;
    EXPECT_TRUE(scene.loadFromFile(out + "/map.3Dscene"));
    EXPECT_GE(scene.getViewport()->size(), 2U);
    // SceneViewer3D opens it with this camera: above the map, not inside it.
    EXPECT_TRUE(scene.followCamera());
    EXPECT_GT(scene.getViewport()->getCamera().getZoomDistance(), 5.0f);

    // The drawings: ground truth (given) and entropy voxels in the scene,
    // the floor plan, and the entropy map alone for SceneViewer3D.
    EXPECT_TRUE(scene.getByName(emslam::apps::GROUND_TRUTH_NAME));
    EXPECT_TRUE(scene.getByName(emslam::apps::ENTROPY_VOXELS_NAME));
    EXPECT_TRUE(scene.getByName(emslam::apps::LEGEND_NAME));
    const cv::Mat top = cv::imread(out + "/map_top.png");
    ASSERT_FALSE(top.empty());
    cv::Mat top_grey;
    cv::cvtColor(top, top_grey, cv::COLOR_BGR2GRAY);
    EXPECT_GT(cv::countNonZero(top_grey < 200), 500);
    mrpt::opengl::COpenGLScene voxels;
    EXPECT_TRUE(voxels.loadFromFile(out + "/entropy_map.3Dscene"));
    EXPECT_TRUE(voxels.getByName(emslam::apps::ENTROPY_VOXELS_NAME));

    // The occupancy grid: an MRPT grid in a gzip file, free space around the
    // path, obstacles met, and its picture.
    {
        mrpt::io::CFileGZInputStream g(out + "/map_grid.gridmap");
        mrpt::maps::COccupancyGridMap2D grid;
        mrpt::serialization::archiveFrom(g) >> grid;
        EXPECT_NEAR(grid.getResolution(), 0.1, 1e-6);
        std::size_t free = 0, occupied = 0;
        for (unsigned cy = 0; cy < grid.getSizeY(); ++cy)
        {
            for (unsigned cx = 0; cx < grid.getSizeX(); ++cx)
            {
                free += grid.getCell(cx, cy) > 0.9f;
                occupied += grid.getCell(cx, cy) < 0.1f;
            }
        }
        EXPECT_GT(free, 200U);
        EXPECT_GT(occupied, 20U);
        // The first camera's position (the map origin) was seen from: free.
        EXPECT_GT(grid.getPos(0.05f, 0.0f), 0.9f);
        const cv::Mat picture = cv::imread(out + "/map_grid.png", cv::IMREAD_GRAYSCALE);
        ASSERT_FALSE(picture.empty());
        EXPECT_EQ(picture.cols, static_cast<int>(grid.getSizeX()));
        EXPECT_EQ(picture.rows, static_cast<int>(grid.getSizeY()));
    }

    mrpt::io::CFileInputStream f(out + "/entropy_map.bin");
    auto obj = mrpt::serialization::archiveFrom(f).ReadObject();
    const auto map = std::dynamic_pointer_cast<emslam::CEntropyVoxelMap>(obj);
    ASSERT_TRUE(map);
    EXPECT_GT(map->energy(), 0.0);

    const std::string csv = readText(out + "/stats.csv");
    EXPECT_EQ(countLinesStartingWith(csv, "frame,"), 60U);
    EXPECT_GE(countLinesStartingWith(csv, "rectification,"), 2U);
    // The egomotion's deviations per step: empty for frame 0, then positive
    // and of the size of a step's error (millimetres to centimetres).
    EXPECT_NE(
        csv.find(",sigma_x_m,sigma_y_m,sigma_z_m,sigma_rx_deg,sigma_ry_deg,sigma_rz_deg\n"),
        std::string::npos);
    {
        std::istringstream lines(csv);
        std::string line;
        std::size_t checked = 0;
        while (std::getline(lines, line))
        {
            if (line.rfind("frame,", 0) != 0)
                continue;
            std::vector<std::string> cells;
            std::stringstream cs(line);
            for (std::string c; std::getline(cs, c, ',');)
                cells.push_back(c);
            while (cells.size() < 29)
                cells.emplace_back();  // trailing empty cells of frame 0
            ASSERT_EQ(cells.size(), 29U) << line;
            if (line.rfind("frame,0,", 0) == 0)
            {
                EXPECT_TRUE(cells[23].empty()) << line;
                continue;
            }
            const double sx = std::stod(cells[23]);
            const double sry = std::stod(cells[27]);
            EXPECT_GT(sx, 1e-5) << line;
            EXPECT_LT(sx, 0.2) << line;
            EXPECT_GT(sry, 1e-4) << line;
            EXPECT_LT(sry, 5.0) << line;
            ++checked;
        }
        EXPECT_EQ(checked, 59U);
    }

    const std::string json = readText(out + "/summary.json");
    for (const char* key :
         {"\"frames\": 60", "\"accepted_frames\"", "\"egomotion_failures\": 0", "\"ms_per_frame\"",
          "\"loop_gap_egomotion_m\"", "\"loop_gap_slam_m\"", "\"final_energy\"",
          "\"final_entropy\"", "\"slam_vs_gt\"", "\"interrupted\": false",
          "\"input_ended_early\": null"})
    {
        EXPECT_NE(json.find(key), std::string::npos) << key << "\n" << json;
    }
    EXPECT_EQ(json.find("nan"), std::string::npos);

    // --energy-scan: a 3DOF energy scans x, z and theta_y of a few actions.
    const std::string scan = readText(out + "/energy_scan.csv");
    EXPECT_EQ(scan.rfind("action,elements_moved,dimension,unit,step,energy_at_truth,", 0), 0U);
    EXPECT_EQ(countLinesStartingWith(scan, "1,"), 3U);  // a_1 along x, z, theta_y
    EXPECT_EQ(scan.find(",y,"), std::string::npos);
    EXPECT_NE(scan.find(",theta_y,deg,1,"), std::string::npos);
    for (const char* key :
         {"\"energy_scan\": {\"lines\": ", "\"energy_at_egomotion\"", "\"energy_at_slam\"",
          "\"fraction_at_truth\"", "\"theta_y\": {\"unit\": \"deg\""})
    {
        EXPECT_NE(json.find(key), std::string::npos) << key << "\n" << json;
    }

    const std::string report = readText(out + "/report.html");
    for (const char* id : {"plot-top", "plot-side", "plot-energy", "plot-time", "plot-attempts"})
    {
        EXPECT_NE(report.find(id), std::string::npos) << id;
    }

    // effective.ini runs again as a configuration, with the same values.
    MapperApp again;
    initApp(again, {out + "/effective.ini", rawlog, "--out", out + "/again", "-q"});
    again.run();
    EXPECT_EQ(again.mapper().slamPoses().size(), slam.size());
    // The serialized map holds the entropy; the energy adds the odometry prior.
    EXPECT_NEAR(again.mapper().finalEntropy(), map->energy(), 1e-9);
    EXPECT_GT(again.mapper().finalEnergy(), again.mapper().finalEntropy());
}

// Every frame gets a SLAM pose: keyframes their rectified pose, the others
// their keyframe's pose composed with the egomotion since it.
TEST(MapperApp, everyFrameHasASlamPoseAndTheKeyframesAreListed)
{
    const std::string rawlog = simulatedHall(60);
    const std::string out = emslam::test::makeTempDir("mapper_every_frame");
    MapperApp app;
    initApp(
        app, {config("3dof-low-structured"), rawlog, "--out", out, "-q", "--set",
              "Rectifier.rectify_every=10", "--trajectory-format", "both"});
    app.run();
    const auto& m = app.mapper();
    ASSERT_EQ(m.frameCount(), 60U);
    ASSERT_EQ(m.slamPoses().size(), 60U);
    ASSERT_EQ(m.keyframePoses().size(), m.acceptedCount());
    EXPECT_TRUE(m.hasEnergy());
    // At least one rectification moved the keyframes off the egomotion.
    ASSERT_GE(m.rectifications().size(), 2U);

    // The keyframes are exactly the accepted frames.
    std::vector<std::size_t> accepted;
    for (const auto& r : m.frames())
    {
        if (r.accepted)
        {
            accepted.push_back(r.index);
        }
    }
    EXPECT_EQ(m.keyframes(), accepted);
    std::vector<std::size_t> listed;
    {
        std::istringstream in(readText(out + "/keyframes.txt"));
        for (std::string line; std::getline(in, line);)
        {
            if (!line.empty() && line[0] != '#')
            {
                listed.push_back(std::stoul(line));
                // frame_index, then its timestamp as in the trajectory files.
                EXPECT_NE(line.find(" 1700000"), std::string::npos) << line;
            }
        }
    }
    EXPECT_EQ(listed, accepted);

    const auto& slam = m.slamPoses();
    const auto& ego = m.egomotionPoses();
    double max_keyframe_move = 0;
    for (std::size_t j = 0; j < accepted.size(); j++)
    {
        const std::size_t k = accepted[j];
        EXPECT_LT(
            emslam::test::maxPoseDifference(
                slam[k].T_world_frame, m.keyframePoses()[j].T_world_frame),
            1e-12)
            << k;
        EXPECT_DOUBLE_EQ(slam[k].timestamp, ego[k].timestamp);
        max_keyframe_move = std::max(
            max_keyframe_move,
            emslam::test::maxPoseDifference(slam[k].T_world_frame, ego[k].T_world_frame));
    }
    EXPECT_GT(max_keyframe_move, 1e-4);
    for (std::size_t i = 0; i < slam.size(); i++)
    {
        const auto kf = std::upper_bound(accepted.begin(), accepted.end(), i) - 1;
        const std::size_t k = *kf;
        // T_world_i = T_world_k(SLAM) + (T_world_k(ego)^-1 + T_world_i(ego))
        const auto expected = slam[k].T_world_frame + (ego[i].T_world_frame - ego[k].T_world_frame);
        EXPECT_LT(emslam::test::maxPoseDifference(slam[i].T_world_frame, expected), 1e-9) << i;
        EXPECT_DOUBLE_EQ(slam[i].timestamp, ego[i].timestamp);
    }

    // The files hold the same: TUM and KITTI, every frame.
    const auto tum = emslam::io::TumTrajectory::fromFile(out + "/trajectory_slam.tum");
    const auto kitti = emslam::io::loadTrajectory(out + "/trajectory_slam_kitti.txt");
    ASSERT_EQ(tum.size(), 60U);
    ASSERT_EQ(kitti.trajectory.size(), 60U);
    EXPECT_EQ(kitti.times_file, out + "/trajectory_slam_times.txt");
    for (std::size_t i = 0; i < slam.size(); i++)
    {
        EXPECT_NEAR(tum.poses[i].t, slam[i].timestamp, 1e-9);
        EXPECT_NEAR(kitti.trajectory.poses[i].t, slam[i].timestamp, 1e-9);
        EXPECT_LT(emslam::test::maxPoseDifference(tum.poses[i].pose, slam[i].T_world_frame), 1e-9);
        EXPECT_LT(
            emslam::test::maxPoseDifference(kitti.trajectory.poses[i].pose, slam[i].T_world_frame),
            1e-9);
    }
    EXPECT_TRUE(std::filesystem::exists(out + "/trajectory_egomotion_kitti.txt"));
    EXPECT_TRUE(std::filesystem::exists(out + "/trajectory_egomotion_times.txt"));
}

// A frame without texture: its egomotion fails (and the next one's, measured
// from it); such steps are predicted by constant velocity, in the egomotion
// and in the SLAM trajectory, and the run says it is unreliable.
TEST(MapperApp, egomotionFailureStepsRepeatThePreviousStep)
{
    const std::string dir = emslam::test::makeTempDir("mapper_failure");
    const std::string rawlog = dir + "/flat.rawlog";
    writeEditedHall(
        rawlog, 16,
        [](std::size_t i, mrpt::obs::CObservationStereoImages& stereo)
        {
            if (i == 8)
            {
                const auto w = stereo.imageLeft.getWidth();
                const auto h = stereo.imageLeft.getHeight();
                stereo.imageLeft = mrpt::img::CImage(w, h, mrpt::img::CH_GRAY);
                stereo.imageLeft.filledRectangle(
                    0, 0, w - 1, h - 1, mrpt::img::TColor(100, 100, 100));
                stereo.imageRight = stereo.imageLeft;
            }
        });
    const std::string out = emslam::test::makeTempDir("mapper_failure_out");
    MapperApp app;
    initApp(app, {config("3dof-low-structured"), rawlog, "--out", out, "-q"});
    app.run();
    const auto& m = app.mapper();
    ASSERT_EQ(m.frameCount(), 16U);
    EXPECT_GE(m.egomotionFailures(), 1U);
    EXPECT_FALSE(m.frames()[8].egomotion_ok);
    // 1 or 2 of 15 steps guessed: more than 2 %, the run says it is unreliable.
    const auto reasons = m.unreliableReasons();
    ASSERT_EQ(reasons.size(), 1U);
    EXPECT_EQ(reasons[0].rfind("egomotion: ", 0), 0U) << reasons[0];
    EXPECT_NE(
        readText(out + "/summary.json").find("\"unreliable\": [\"egomotion: "), std::string::npos);
    const auto& slam = m.slamPoses();
    const auto& ego = m.egomotionPoses();
    ASSERT_EQ(slam.size(), 16U);
    ASSERT_EQ(ego.size(), 16U);
    for (std::size_t i = 2; i < slam.size(); i++)
    {
        if (!m.frames()[i].egomotion_ok)
        {
            const mrpt::poses::CPose3D step = ego[i].T_world_frame - ego[i - 1].T_world_frame;
            const mrpt::poses::CPose3D before = ego[i - 1].T_world_frame - ego[i - 2].T_world_frame;
            EXPECT_GT(before.norm(), 0.01) << i;  // the robot moves: not the identity
            EXPECT_LT(emslam::test::maxPoseDifference(step, before), 1e-9) << i;
            if (!m.frames()[i].accepted)
            {
                EXPECT_LT(
                    emslam::test::maxPoseDifference(
                        slam[i].T_world_frame - slam[i - 1].T_world_frame, step),
                    1e-9)
                    << i;
            }
        }
    }
    EXPECT_EQ(emslam::io::TumTrajectory::fromFile(out + "/trajectory_slam.tum").size(), 16U);
}

// A run whose result is nonsense still writes every output, but says so and
// exits with its own status.
TEST(MapperApp, blackImagesGiveADegenerateRunWithExitStatus3)
{
    const std::string dir = emslam::test::makeTempDir("mapper_black");
    const std::string rawlog = dir + "/black.rawlog";
    writeEditedHall(
        rawlog, 8,
        [](std::size_t, mrpt::obs::CObservationStereoImages& stereo)
        {
            const auto w = stereo.imageLeft.getWidth();
            const auto h = stereo.imageLeft.getHeight();
            stereo.imageLeft = mrpt::img::CImage(w, h, mrpt::img::CH_GRAY);
            stereo.imageLeft.filledRectangle(0, 0, w - 1, h - 1, mrpt::img::TColor(0, 0, 0));
            stereo.imageRight = stereo.imageLeft;
        });
    const std::string out = dir + "/out";
    const std::vector<std::string> args = {
        "emslam-mapper", config("3dof-low-structured"), rawlog, "--out", out, "-q"};
    auto argv = argvOf(args);
    testing::internal::CaptureStderr();
    const int status = emslam::apps::appMain<MapperApp>(
        "emslam-mapper", static_cast<int>(argv.size()), const_cast<char**>(argv.data()));
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(status, emslam::apps::EXIT_DEGENERATE);
    EXPECT_EQ(status, 3);
    EXPECT_NE(
        err.find("emslam-mapper: warning: degenerate result: 7 of 7 egomotion steps failed "
                 "(100 %); the map has no point"),
        std::string::npos)
        << err;
    EXPECT_NE(err.find("exit status 3"), std::string::npos) << err;
    for (const char* f : {"trajectory_slam.tum", "map.ply", "summary.json", "report.html"})
    {
        EXPECT_TRUE(mrpt::system::fileExists(out + "/" + f)) << f;
    }
    EXPECT_NE(
        readText(out + "/summary.json").find("\"degenerate\": \"7 of 7 egomotion steps failed"),
        std::string::npos);

    // A usable run exits 0.
    MapperApp ok;
    initApp(ok, {config("3dof-low-structured"), simulatedHall(8), "--out", dir + "/ok", "-q"});
    ok.run();
    EXPECT_TRUE(ok.degenerateResult().empty()) << ok.degenerateResult();
    EXPECT_EQ(ok.exitCode(), 0);
    EXPECT_NE(readText(dir + "/ok/summary.json").find("\"degenerate\": null"), std::string::npos);
}

TEST(MapperApp, egomotionOnlyNeverRectifiesAndCreatesMissingParentFolders)
{
    // --out names a folder whose parents do not exist yet (mkdir -p).
    const std::string out = emslam::test::makeTempDir("mapper_ego") + "/runs/ego";
    MapperApp app;
    initApp(
        app,
        {config("3dof-low-structured"), simulatedHall(30), "--out", out, "-q", "--egomotion-only"});
    app.run();
    const std::string json = readText(out + "/summary.json");
    EXPECT_NE(json.find("\"calls\": 0"), std::string::npos) << json;
    EXPECT_NE(json.find("\"mode\": \"egomotion_only\""), std::string::npos);
}

TEST(MapperApp, truncatedRawlogMapsEveryCompleteFrame)
{
    const std::string full = simulatedHall(30);
    const std::string cut = emslam::test::makeTempDir("mapper_cut") + "/cut.rawlog";
    {
        // Cut the (uncompressed) rawlog in the middle of a record.
        const std::string text = readText(full);
        ASSERT_GT(text.size(), 1000U);
        std::ofstream(cut, std::ios::binary)
            .write(text.data(), static_cast<long>(text.size() * 6 / 10));
    }
    const std::string out = emslam::test::makeTempDir("mapper_cut_out");
    MapperApp app;
    initApp(app, {config("3dof-low-structured"), cut, "--out", out, "-q"});
    ASSERT_NO_THROW(app.run());
    const std::size_t frames = app.mapper().frameCount();
    EXPECT_GT(frames, 10U);
    EXPECT_LT(frames, 30U);
    EXPECT_FALSE(app.runInfo().input_ended_early.empty());
    const std::string json = readText(out + "/summary.json");
    EXPECT_NE(json.find("the file ends in the middle of the record"), std::string::npos) << json;
    EXPECT_EQ(
        emslam::io::TumTrajectory::fromFile(out + "/trajectory_egomotion.tum").size(), frames);
}

// A flipped byte in a gz rawlog: zlib's error is named (not MRPT's "cannot
// read object streaming version"), the frames read are written, and the run
// fails (exit 1), since some of them may hold damaged pixels.
TEST(MapperApp, flippedByteInAGzRawlogIsACorruptInputError)
{
    std::string bytes = readText(simulatedHall(30));
    ASSERT_GT(bytes.size(), 1000U);
    bytes[bytes.size() / 2] ^= 0x04;
    const std::string dir = emslam::test::makeTempDir("mapper_flip");
    const std::string rawlog = dir + "/flipped.rawlog";
    std::ofstream(rawlog, std::ios::binary).write(bytes.data(), static_cast<long>(bytes.size()));
    const std::string out = dir + "/out";
    MapperApp app;
    initApp(app, {config("3dof-low-structured"), rawlog, "--out", out, "-q"});
    testing::internal::CaptureStderr();
    try
    {
        app.run();
        ADD_FAILURE() << "a corrupt rawlog must fail the run";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(
            std::string(e.what()).find("the gz data is corrupt (zlib: incorrect data check)"),
            std::string::npos)
            << e.what();
    }
    testing::internal::GetCapturedStderr();
    const std::size_t frames = app.mapper().frameCount();
    EXPECT_GT(frames, 0U);
    EXPECT_LT(frames, 30U);
    const std::string json = readText(out + "/summary.json");
    EXPECT_NE(json.find("\"stopped_by_error\": \"record "), std::string::npos) << json;
    EXPECT_NE(json.find("the gz data is corrupt"), std::string::npos) << json;
    EXPECT_EQ(
        emslam::io::TumTrajectory::fromFile(out + "/trajectory_egomotion.tum").size(), frames);
}

TEST(MapperApp, badInputsFailWithAClearMessage)
{
    const std::string dir = emslam::test::makeTempDir("mapper_bad");
    const std::string rawlog = simulatedHall(8);
    const std::string cfg = config("3dof-low-structured");
    const auto initFails =
        [&](std::vector<std::string> args, std::initializer_list<std::string> parts)
    {
        MapperApp app;
        emslam::test::expectThrowContaining([&] { initApp(app, args); }, parts);
    };
    const auto runFails =
        [&](std::vector<std::string> args, std::initializer_list<std::string> parts)
    {
        MapperApp app;
        initApp(app, args);
        emslam::test::expectThrowContaining([&] { app.run(); }, parts);
    };
    initFails({cfg, dir + "/none.rawlog", "--out", dir}, {"none.rawlog", "does not exist"});
    initFails({dir + "/none.ini", rawlog, "--out", dir}, {"none.ini", "does not exist"});
    initFails(
        {cfg, rawlog, "--out", dir, "--set", "Rectifier.esp_xyz=0.1"},
        {"esp_xyz", "did you mean 'eps_xyz'"});
    initFails(
        {cfg, rawlog, "--out", dir, "--set", "Rectifer.eps_xyz=0.1"},
        {"Rectifer", "did you mean [Rectifier]"});
    initFails({cfg, rawlog, "--out", dir, "--set", "Rectifier.nc_max=0"}, {"nc_max"});
    initFails({cfg, rawlog, "--out", dir, "--set", "EntropyVoxelMap.energy=flat"}, {"flat"});
    // The ground truth is read before any work: missing, garbled, KITTI without times.
    initFails({cfg, rawlog, "--out", dir, "--gt", dir + "/no.tum"}, {"no.tum", "does not exist"});
    initFails({cfg, rawlog, "--out", dir, "--energy-scan"}, {"--energy-scan", "needs --gt"});
    emslam::test::writeFile(dir + "/seven.txt", "1 2 3 4 5 6 7\n");
    initFails({cfg, rawlog, "--out", dir, "--gt", dir + "/seven.txt"}, {"seven.txt:1"});
    emslam::test::writeFile(dir + "/poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n");
    initFails(
        {cfg, rawlog, "--out", dir, "--gt", dir + "/poses.txt"},
        {"poses.txt' has no times file", "--gt-times"});
    initFails(
        {cfg, rawlog, "--out", dir, "--gt", groundTruthOf(rawlog), "--gt-format", "kitti"},
        {".tum:1", "12 numbers"});
    initFails({cfg, rawlog, "--out", dir, "--trajectory-format", "g2o"}, {"g2o", "tum, kitti"});
    initFails(
        {cfg, rawlog, "--out", dir, "--max-frames", "-1"},
        {"--max-frames must be at least 0", "got -1"});

    emslam::test::writeFile(dir + "/text.rawlog", "this is not a rawlog\n");
    runFails(
        {cfg, dir + "/text.rawlog", "--out", dir + "/o1"},
        {"text.rawlog", "not a readable rawlog"});

    {
        // A valid rawlog with no stereo / RGB-D observation.
        mrpt::io::CFileGZOutputStream f(dir + "/odometry.rawlog");
        auto a = mrpt::serialization::archiveFrom(f);
        for (int i = 0; i < 3; ++i)
        {
            mrpt::obs::CObservationOdometry o;
            o.timestamp = mrpt::Clock::now();
            a << o;
        }
    }
    runFails(
        {cfg, dir + "/odometry.rawlog", "--out", dir + "/o2"},
        {"no usable stereo or RGB-D observation", "odometry.rawlog", "3 observations"});

    {
        // A stereo observation whose calibration is missing (all zero).
        mrpt::io::CFileGZOutputStream f(dir + "/nocalib.rawlog");
        auto a = mrpt::serialization::archiveFrom(f);
        mrpt::obs::CObservationStereoImages o;
        o.timestamp = mrpt::Clock::now();
        o.imageLeft = mrpt::img::CImage(64, 48, mrpt::img::CH_GRAY);
        o.imageRight = mrpt::img::CImage(64, 48, mrpt::img::CH_GRAY);
        o.hasImageRight = true;
        o.leftCamera.ncols = o.rightCamera.ncols = 0;
        o.leftCamera.nrows = o.rightCamera.nrows = 0;
        a << o;
    }
    runFails(
        {cfg, dir + "/nocalib.rawlog", "--out", dir + "/o3"},
        {"no usable stereo", "1 frame skipped (1 unusable)", "record 0", "calibration"});
    // A run that fails before writing leaves no output folder behind.
    EXPECT_FALSE(std::filesystem::exists(dir + "/o1"));
    EXPECT_FALSE(std::filesystem::exists(dir + "/o2"));
    EXPECT_FALSE(std::filesystem::exists(dir + "/o3"));
}

// Frame 20 with a 160x120 right image and frame 25 without calibration: both
// are skipped with a warning each, and every other frame is mapped.
// A config that repeats a section or a key is refused naming both lines
// (MRPT 2.5.8 would merge the sections and keep the last value silently).
TEST(MapperApp, repeatedConfigSectionOrKeyIsRefusedNamingBothLines)
{
    const std::string dir = emslam::test::makeTempDir("mapper_dup");
    const std::string rawlog = simulatedHall(8);
    std::ifstream in(config("3dof-low-structured"));
    const std::string text{std::istreambuf_iterator<char>(in), {}};
    // The line of the shipped file's [Rectifier] (from 1).
    const auto at = text.find("\n[Rectifier]\n");
    ASSERT_NE(at, std::string::npos);
    const auto rectifier_line =
        static_cast<std::size_t>(std::count(text.begin(), text.begin() + at + 1, '\n')) + 1;
    const auto lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
    emslam::test::writeFile(dir + "/dup.ini", text + "[Rectifier]\n");
    MapperApp a;
    emslam::test::expectThrowContaining(
        [&] {
            initApp(a, {dir + "/dup.ini", rawlog, "--out", dir});
        },
        {dir + "/dup.ini:" + std::to_string(lines + 1) +
         ": section [Rectifier] repeated (first at " + dir +
         "/dup.ini:" + std::to_string(rectifier_line) + ")"});

    emslam::test::writeFile(dir + "/key.ini", "[Rectifier]\nseed = 1\n; again\nSeed = 2\n");
    MapperApp b;
    emslam::test::expectThrowContaining(
        [&] {
            initApp(b, {dir + "/key.ini", rawlog, "--out", dir});
        },
        {dir + "/key.ini:4: key 'Seed' repeated in [Rectifier] (first at " + dir +
         "/key.ini:2 as 'seed'; names ignore case)"});
    EXPECT_FALSE(std::filesystem::exists(dir + "/summary.json"));
}

// A disk that fills up while the outputs are written: the small ones come
// first and survive; the error names the file and the OS reason. The full
// disk is real: map.3Dscene's `.partial` file is a link to /dev/full.
TEST(MapperApp, fullDiskKeepsTheSmallOutputsAndNamesTheFileAndReason)
{
    const std::string rawlog = simulatedHall(8);
    const std::string out = emslam::test::makeTempDir("mapper_full") + "/out";
    std::filesystem::create_directories(out);
    emslam::test::putOnFullDisk(out + "/map.3Dscene");
    MapperApp app;
    initApp(app, {config("3dof-low-structured"), rawlog, "--out", out, "-q"});
    emslam::test::expectThrowContaining(
        [&] { app.run(); }, {"cannot write '" + out + "/map.3Dscene': No space left on device"});
    for (const char* f :
         {"summary.json", "stats.csv", "effective.ini", "trajectory_slam.tum",
          "trajectory_egomotion.tum", "keyframes.txt"})
    {
        EXPECT_TRUE(std::filesystem::is_regular_file(out + "/" + f)) << f;
    }
    for (const char* f :
         {"map.3Dscene", "map_top.png", "map_grid.gridmap", "entropy_map.bin", "report.html"})
    {
        EXPECT_FALSE(std::filesystem::exists(out + "/" + f)) << f;
    }
}

TEST(MapperApp, unusableFramesAreSkippedAndTheOthersMapped)
{
    const std::string dir = emslam::test::makeTempDir("mapper_skip");
    const std::string rawlog = dir + "/bad_frames.rawlog";
    writeEditedHall(
        rawlog, 30,
        [](std::size_t i, mrpt::obs::CObservationStereoImages& stereo)
        {
            if (i == 20)
            {
                cv::Mat small;
                cv::resize(stereo.imageRight.asCvMatRef(), small, cv::Size(160, 120));
                stereo.imageRight = mrpt::img::CImage(small, mrpt::img::DEEP_COPY);
            }
            if (i == 25)
            {
                stereo.leftCamera.ncols = stereo.rightCamera.ncols = 0;
                stereo.leftCamera.nrows = stereo.rightCamera.nrows = 0;
            }
        });
    const std::string out = emslam::test::makeTempDir("mapper_skip_out");
    MapperApp app;
    initApp(app, {config("3dof-low-structured"), rawlog, "--out", out, "-q"});
    testing::internal::CaptureStderr();
    ASSERT_NO_THROW(app.run());
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(app.mapper().frameCount(), 28U);
    EXPECT_EQ(app.runInfo().skipped_observations, 2U);
    EXPECT_NE(err.find("warning: skipping unusable observation at record 20"), std::string::npos)
        << err;
    EXPECT_NE(err.find("right image is 160x120"), std::string::npos) << err;
    EXPECT_NE(err.find("record 25"), std::string::npos) << err;
    const std::string json = readText(out + "/summary.json");
    EXPECT_NE(json.find("\"skipped_observations\": 2,"), std::string::npos) << json;
    EXPECT_NE(json.find("\"skipped_reasons\": [\"record 20: "), std::string::npos) << json;
    EXPECT_NE(json.find("\"stopped_by_error\": null"), std::string::npos) << json;
    EXPECT_EQ(emslam::io::TumTrajectory::fromFile(out + "/trajectory_slam.tum").size(), 28U);
    EXPECT_NE(
        readText(out + "/report.html").find("unusable observations skipped"), std::string::npos);
}

/** Runs the mapper (egomotion only: the frames are the point) on `rawlog`
 * into `out`, its stderr returned. */
std::string mapCapturingStderr(MapperApp& app, const std::string& rawlog, const std::string& out)
{
    initApp(app, {config("3dof-low-structured"), rawlog, "--out", out, "-q", "--egomotion-only"});
    return emslam::test::capturingStderr([&] { app.run(); });
}

/** Every trajectory the mapper wrote has `n` poses, strictly increasing in time. */
void expectStrictlyIncreasingTrajectories(const std::string& out, std::size_t n)
{
    for (const char* name : {"trajectory_egomotion", "trajectory_slam", "trajectory_online"})
    {
        const auto t = emslam::test::trajectoryTimes(out + "/" + name + ".tum");
        EXPECT_EQ(t.size(), n) << name;
        for (std::size_t i = 1; i < t.size(); ++i)
        {
            EXPECT_GT(t[i], t[i - 1]) << name << " line " << i;
        }
    }
}

// Frame 10 repeats frame 9's stamp, frame 15 goes back 1 s, frame 20 has no
// stamp, frame 22 the one a NaN becomes: each is skipped and named, the
// trajectories are strictly increasing in time.
TEST(MapperApp, badTimestampsAreSkippedAndTheTrajectoriesIncrease)
{
    const std::string dir = emslam::test::makeTempDir("mapper_stamps");
    const std::string rawlog = dir + "/stamps.rawlog";
    mrpt::Clock::time_point previous;
    writeEditedHall(
        rawlog, 30,
        [&](std::size_t i, mrpt::obs::CObservationStereoImages& stereo)
        {
            const auto own = stereo.timestamp;
            if (i == 10)
            {
                stereo.timestamp = previous;
            }
            if (i == 15)
            {
                stereo.timestamp = own - std::chrono::seconds(1);
            }
            if (i == 20)
            {
                stereo.timestamp = INVALID_TIMESTAMP;
            }
            if (i == 22)
            {
                // What Clock::fromDouble(NaN) stores on x86-64 (year 31198).
                stereo.timestamp = mrpt::Clock::time_point(mrpt::Clock::duration(
                    std::numeric_limits<std::int64_t>::min() + 116444736000000000LL));
            }
            previous = own;
        });
    const std::string out = dir + "/out";
    MapperApp app;
    const std::string err = mapCapturingStderr(app, rawlog, out);
    EXPECT_EQ(app.mapper().frameCount(), 26U);
    EXPECT_EQ(app.runInfo().skipped_observations, 4U);
    EXPECT_EQ(app.runInfo().skipped_bad_stamps, 4U);
    for (const char* warning :
         {"emslam-mapper: warning: skipping frame at record 10: its timestamp 1700000001.800000000 "
          "is the same as record 9's (the last frame used)\n",
          "emslam-mapper: warning: skipping frame at record 15: its timestamp 1700000002.000000000 "
          "is 0.8 s before record 14's (the last frame used)\n",
          "emslam-mapper: warning: skipping frame at record 20: its timestamp is INVALID_TIMESTAMP "
          "(never set)\n",
          "emslam-mapper: warning: skipping frame at record 22: its timestamp 9.223372037e+11 s "
          "is after 2100\n"})
    {
        EXPECT_NE(err.find(warning), std::string::npos) << warning << "\nin:\n" << err;
    }
    const std::string json = readText(out + "/summary.json");
    EXPECT_NE(json.find("\"skipped_observations\": 4,"), std::string::npos) << json;
    EXPECT_NE(json.find("\"skipped_bad_stamps\": 4,"), std::string::npos) << json;
    EXPECT_NE(json.find("\"skipped_camera_changes\": 0,"), std::string::npos) << json;
    EXPECT_NE(json.find("\"camera_change\": null,"), std::string::npos) << json;
    EXPECT_NE(json.find("\"skipped_reasons\": [\"record 10: its timestamp"), std::string::npos);
    expectStrictlyIncreasingTrajectories(out, 26);
}

// Frames 8, 9 and 17 come from a 640x480 camera (a valid calibration of
// their own): skipped, and reported as a camera that came and went.
TEST(MapperApp, interleavedImageSizesAreSkipped)
{
    const std::string dir = emslam::test::makeTempDir("mapper_interleaved");
    const std::string rawlog = dir + "/interleaved.rawlog";
    writeEditedHall(
        rawlog, 30,
        [](std::size_t i, mrpt::obs::CObservationStereoImages& stereo)
        {
            if (i == 8 || i == 9 || i == 17)
            {
                emslam::test::resizeStereoFrame(stereo, 640, 480);
            }
        });
    const std::string out = dir + "/out";
    MapperApp app;
    const std::string err = mapCapturingStderr(app, rawlog, out);
    EXPECT_EQ(app.mapper().frameCount(), 27U);
    EXPECT_EQ(app.runInfo().skipped_camera_changes, 3U);
    EXPECT_EQ(app.exitCode(), 0);
    EXPECT_NE(
        err.find("emslam-mapper: warning: skipping frame at record 8: its camera 640x480 (fx 400, "
                 "fy 400, cx 319, cy 239, baseline 0.1 m) differs from the session's 320x240 "
                 "(fx 200, fy 200, cx 159.5, cy 119.5, baseline 0.1 m)\n"),
        std::string::npos)
        << err;
    EXPECT_NE(
        err.find("emslam-mapper: warning: 3 frames skipped: their camera differed from the "
                 "session's 320x240 (fx 200, fy 200, cx 159.5, cy 119.5, baseline 0.1 m) in 2 runs "
                 "(the first at record 8: 640x480"),
        std::string::npos)
        << err;
    const std::string json = readText(out + "/summary.json");
    EXPECT_NE(json.find("\"skipped_camera_changes\": 3,"), std::string::npos) << json;
    EXPECT_NE(json.find("\"camera_change\": {\"record\": 8, "), std::string::npos) << json;
    EXPECT_NE(json.find("\"for_good\": false, \"runs\": 2"), std::string::npos) << json;
    expectStrictlyIncreasingTrajectories(out, 27);
}

// From frame 15 on, another camera: the first 15 frames are mapped, the run
// ends with one warning saying where the camera changed, and exits 0 (not
// "degenerate": no egomotion step failed).
TEST(MapperApp, cameraChangedForGoodIsMappedAsFarAsTheFirstCameraGoes)
{
    const std::string dir = emslam::test::makeTempDir("mapper_camera_change");
    const std::string rawlog = dir + "/change.rawlog";
    writeEditedHall(
        rawlog, 30,
        [](std::size_t i, mrpt::obs::CObservationStereoImages& stereo)
        {
            if (i >= 15)
            {
                emslam::test::resizeStereoFrame(stereo, 640, 480);
            }
        });
    const std::string out = dir + "/out";
    MapperApp app;
    const std::string err = mapCapturingStderr(app, rawlog, out);
    EXPECT_EQ(app.mapper().frameCount(), 15U);
    EXPECT_EQ(app.runInfo().skipped_camera_changes, 15U);
    EXPECT_EQ(app.exitCode(), 0);
    EXPECT_EQ(err.find("degenerate"), std::string::npos) << err;
    const std::string end =
        "15 frames skipped: camera changed from 320x240 (fx 200, fy 200, cx 159.5, cy 119.5, "
        "baseline 0.1 m) to 640x480 (fx 400, fy 400, cx 319, cy 239, baseline 0.1 m) at "
        "record 15; only the 15 frames before it were used";
    EXPECT_NE(err.find("emslam-mapper: warning: " + end + "\n"), std::string::npos) << err;
    // The first 5 named, the others only counted.
    EXPECT_EQ(countLinesStartingWith(err, "emslam-mapper: warning: skipping frame at record"), 5U);
    const std::string json = readText(out + "/summary.json");
    EXPECT_NE(
        json.find("\"for_good\": true, \"runs\": 1, \"frames_before\": 15"), std::string::npos)
        << json;
    EXPECT_NE(json.find(end), std::string::npos) << json;
    EXPECT_NE(readText(out + "/report.html").find("camera change"), std::string::npos);
    expectStrictlyIncreasingTrajectories(out, 15);
}

// Every input and output is checked in initialize(), before any work, and a
// run that fails leaves no empty output folder.
TEST(MapperApp, configIsAFileOrAShippedNameGivenOnce)
{
    const std::string dir = emslam::test::makeTempDir("mapper_config_name");
    const std::string rawlog = simulatedHall(8);
    for (const std::vector<std::string>& given :
         {std::vector<std::string>{"3dof-low-structured"},
          {"-c", "3dof-low-structured.ini"},
          {"--config=3dof-low-structured"},
          {config("3dof-low-structured")}})
    {
        MapperApp app;
        std::vector<std::string> args = given;
        args.insert(args.end(), {rawlog, "--out", dir + "/o", "-q"});
        EXPECT_NO_THROW(initApp(app, args)) << given.back();
    }
    const auto initFails =
        [&](std::vector<std::string> args, std::initializer_list<std::string> parts)
    {
        MapperApp app;
        args.insert(args.begin(), {"--out", dir + "/o"});
        emslam::test::expectThrowContaining([&] { initApp(app, args); }, parts);
    };
    initFails({"--config=kiti", rawlog}, {"no mapper config 'kiti'", "euroc, kitti, paper in "});
    initFails({"-c", "kitti", config("kitti"), rawlog}, {"give the config once"});
    initFails({"-c", "kitti", "-c", "euroc", rawlog}, {"-c / --config given 2 times"});
    initFails({rawlog, "-c"}, {"-c needs a value"});
    initFails({"--config=", rawlog}, {"--config= needs a value"});
    initFails({"-c", "kitti"}, {"missing required argument <DATASET.rawlog>"});
}

TEST(MapperApp, badPathsFailBeforeAnyWork)
{
    const std::string dir = emslam::test::makeTempDir("mapper_paths");
    const std::string rawlog = simulatedHall(8);
    const std::string cfg = config("3dof-low-structured");
    const auto initFails =
        [&](std::vector<std::string> args, std::initializer_list<std::string> parts)
    {
        MapperApp app;
        emslam::test::expectThrowContaining([&] { initApp(app, args); }, parts);
    };
    initFails({"/dev/zero", rawlog, "--out", dir + "/o"}, {"'/dev/zero'", "character device"});
    initFails(
        {cfg, dir, "--out", dir + "/o"},
        {"'" + dir + "' is a folder but no dataset this program reads", "KITTI odometry sequence",
         "EuRoC MAV", "TUM RGB-D"});
    const std::string fifo = dir + "/pipe";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    initFails({cfg, rawlog, "--out", fifo}, {"pipe' is a FIFO", "not a folder"});
    initFails({cfg, fifo, "--out", dir + "/o"}, {"pipe' is not a regular file"});
    // Outputs inside --out that must not be replaced.
    std::filesystem::create_directory(dir + "/full");
    ASSERT_EQ(::mkfifo((dir + "/full/map.ply").c_str(), 0600), 0);
    initFails({cfg, rawlog, "--out", dir + "/full"}, {"full/map.ply' exists and is a FIFO"});
    std::filesystem::create_directory(dir + "/linked");
    std::filesystem::create_symlink(rawlog, dir + "/linked/report.html");
    initFails(
        {cfg, rawlog, "--out", dir + "/linked"}, {"linked/report.html' exists and is a symbolic"});
    // A folder nothing can be written into (root writes anywhere but in /proc).
    const std::string ro = ::geteuid() == 0 ? std::string("/proc") : dir + "/ro";
    if (ro != "/proc")
    {
        std::filesystem::create_directory(ro);
        std::filesystem::permissions(
            ro, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
    }
    initFails({cfg, rawlog, "--out", ro}, {"cannot write into folder '" + ro + "'"});
    initFails({cfg, rawlog, "--out", ro + "/new"}, {"cannot write into folder '" + ro + "'"});

    // An empty and a random rawlog: clear errors, and no output folder made.
    emslam::test::writeFile(dir + "/empty.rawlog", "");
    std::string noise(4096, '\0');
    for (std::size_t i = 0; i < noise.size(); ++i)
    {
        noise[i] = static_cast<char>((i * 2654435761U) >> 13);
    }
    emslam::test::writeFile(dir + "/noise.rawlog", noise);
    for (const char* name : {"empty", "noise"})
    {
        MapperApp app;
        const std::string out = dir + "/out_" + name + "/run";
        initApp(app, {cfg, dir + "/" + name + ".rawlog", "--out", out, "-q"});
        EXPECT_ANY_THROW(app.run()) << name;
        EXPECT_FALSE(std::filesystem::exists(dir + "/out_" + name)) << name;
    }
}

#ifdef EMSLAM_MAPPER_EXE
// Ctrl-C: the real executable stops after the current frame and still writes
// every output for the frames mapped so far, exit code 130 (128 + SIGINT).
TEST(MapperApp, sigintStopsAndWritesTheOutputs)
{
    const std::string rawlog = simulatedHall(300);
    const std::string out = emslam::test::makeTempDir("mapper_sigint");
    // Non-TTY progress prints one line per 10 %: interrupt after the first.
    const auto run = emslam::test::interruptedRun(
        EMSLAM_MAPPER_EXE, {config("3dof-low-structured"), rawlog, "--out", out}, "frame ", SIGINT);
    ASSERT_TRUE(run.exited) << run.stderr_text;
    EXPECT_EQ(run.exit_code, 130) << run.stderr_text;
    const std::string json = readText(out + "/summary.json");
    EXPECT_NE(json.find("\"interrupted\": true"), std::string::npos) << json;
    const auto ego = emslam::io::TumTrajectory::fromFile(out + "/trajectory_egomotion.tum");
    EXPECT_GT(ego.size(), 0U);
    EXPECT_LT(ego.size(), 300U);
    for (const char* f :
         {"trajectory_slam.tum", "map.ply", "map.3Dscene", "entropy_map.bin", "stats.csv",
          "effective.ini", "report.html"})
    {
        EXPECT_TRUE(mrpt::system::fileExists(out + "/" + f)) << f;
    }
}

// `emslam-mapper ... | true`: the console text is lost, the run is not (on
// 80c9fba SIGPIPE killed it: exit 141 although every output was complete).
TEST(MapperApp, aClosedStdoutPipeChangesNeitherTheRunNorItsExitCode)
{
    const std::string rawlog = simulatedHall(20);
    const std::string out = emslam::test::makeTempDir("mapper_sigpipe");
    EXPECT_EQ(
        emslam::test::runWithStdoutReaderGone(
            EMSLAM_MAPPER_EXE, {config("3dof-low-structured"), rawlog, "--out", out}),
        0);
    EXPECT_EQ(emslam::io::TumTrajectory::fromFile(out + "/trajectory_slam.tum").size(), 20U);
    EXPECT_NE(readText(out + "/summary.json").find("\"interrupted\": false"), std::string::npos);
}

// A signal after the last frame, while the rectifier finishes and the loop
// closer catches up and polishes: the run ends at once and still writes
// every output of every frame.
TEST(MapperApp, sigintAfterTheLastFrameEndsTheLoopClosingAndWritesTheOutputs)
{
    const std::string rawlog = simulatedHall(300);
    const std::string out = emslam::test::makeTempDir("mapper_sigint_end");
    const auto run = emslam::test::interruptedRun(
        EMSLAM_MAPPER_EXE, {config("3dof-low-structured"), rawlog, "--out", out}, "(100%)", SIGINT);
    std::printf("exit %d, %.2f s after the signal\n", run.exit_code, run.seconds_to_exit);
    ASSERT_TRUE(run.exited) << run.stderr_text;
    EXPECT_EQ(run.exit_code, 130) << run.stderr_text;
    // Loose: a loaded machine may take long to write the outputs.
    EXPECT_LT(run.seconds_to_exit, 60.0);
    const auto slam = emslam::io::TumTrajectory::fromFile(out + "/trajectory_slam.tum");
    EXPECT_EQ(slam.size(), 300U);
    const auto online = emslam::io::TumTrajectory::fromFile(out + "/trajectory_online.tum");
    EXPECT_EQ(online.size(), 300U);
    for (const char* f : {"map.ply", "map.3Dscene", "stats.csv", "summary.json", "report.html"})
    {
        EXPECT_TRUE(mrpt::system::fileExists(out + "/" + f)) << f;
    }
}
#endif

namespace
{
/** Runs `app` with `args` (which hold `--gt`) and returns the egomotion's
 * and SLAM's metrics against the ground truth. */
std::pair<emslam::eval::TrajectoryMetrics, emslam::eval::TrajectoryMetrics> mapWithGroundTruth(
    MapperApp& app, const std::vector<std::string>& args)
{
    initApp(app, args);
    app.run();
    const auto& info = app.runInfo();
    if (!info.egomotion_vs_gt || !info.slam_vs_gt)
    {
        throw std::runtime_error("the mapper gave no metrics against the ground truth");
    }
    return {*info.egomotion_vs_gt, *info.slam_vs_gt};
}

/** Renders config/sim/`world`.ini with `seed` (plus `sim_extra` arguments)
 * into `dir`, maps it with config/mapper/`mapper_config`.ini (plus `extra`
 * arguments) and prints and returns the egomotion's and SLAM's metrics
 * against the ground truth. */
std::pair<emslam::eval::TrajectoryMetrics, emslam::eval::TrajectoryMetrics> mapSimulatedWorld(
    const std::string& world,
    int seed,
    const std::string& mapper_config,
    const std::string& dir,
    const std::vector<std::string>& extra = {},
    const std::vector<std::string>& sim_extra = {})
{
    emslam::apps::SimApp sim;
    std::vector<std::string> sim_args = {
        "emslam-sim", emslam::test::sourceDir() + "/config/sim/" + world + ".ini",
        "--seed",     std::to_string(seed),
        "-o",         dir + "/world.rawlog",
        "--gt-out",   dir + "/world.tum",
        "--quiet"};
    sim_args.insert(sim_args.end(), sim_extra.begin(), sim_extra.end());
    auto argv = argvOf(sim_args);
    sim.initialize(static_cast<int>(argv.size()), argv.data());
    sim.run();
    MapperApp app;
    std::vector<std::string> args = {
        config(mapper_config),
        dir + "/world.rawlog",
        "--out",
        dir + "/map",
        "--gt",
        dir + "/world.tum",
        "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto [ego, slam] = mapWithGroundTruth(app, args);
    std::printf(
        "%s seed %d (%s): loop gap egomotion %.3f m, SLAM %.3f m; ATE egomotion %.3f m, SLAM "
        "%.3f m\n",
        world.c_str(), seed, mapper_config.c_str(), ego.loop_gap_m, slam.loop_gap_m, ego.ate_rmse_m,
        slam.ate_rmse_m);
    return {ego, slam};
}
}  // namespace

// The simulator's whole 3DOF hall double loop (104 m) with the shipped
// 3dof-low-structured configuration (rectifier seed 1, deterministic): the
// loop gap must fall to 1/5 of the egomotion's and to 0.5 % of the path, and
// the ATE must halve. Measured with loop closing and its local edges
// ([LoopCloser], on in every shipped config) and sparse stereo at the
// features: gap 0.407 -> 0.002 m, ATE 0.095 -> 0.023 m; seeds 1-10 in
// doc/notes/2026-12-04-loop-closing-local-edges-levelling.md.
TEST(MapperApp, hallDoubleLoopRectificationShrinksGapAndAte)
{
    const std::string dir = emslam::test::makeTempDir("mapper_hall");
    const auto [ego, slam] = mapSimulatedWorld("hall_double_loop", 1, "3dof-low-structured", dir);
    EXPECT_GT(ego.loop_gap_m, 0.2);  // the egomotion drifts: there is a loop to close
    EXPECT_LE(slam.loop_gap_m, 0.2 * ego.loop_gap_m);
    EXPECT_LE(slam.loop_gap_m, 0.005 * slam.path_length_m);
    EXPECT_LT(slam.ate_rmse_m, 0.5 * ego.ate_rmse_m);
}

// A 6DOF loop: a walker through the simulated Chancellor building with
// Exp. 10 (6dof-structured, serial mode so that the run repeats exactly, sim
// seed 1). The loop gap must fall to 1/5 of the egomotion's and to 0.5 % of
// the path, and the ATE must halve. Measured with loop closing: gap 2.312 ->
// 0.002 m, ATE 0.554 -> 0.112 m; other seeds in
// doc/notes/2026-12-04-loop-closing-local-edges-levelling.md.
TEST(MapperApp, chancellorLoop6dofRectificationShrinksGapAndAte)
{
    const std::string dir = emslam::test::makeTempDir("mapper_chancellor");
    const auto [ego, slam] = mapSimulatedWorld(
        "chancellor_zero_loop", 1, "6dof-structured", dir, {"--set", "Rectifier.mode=serial"});
    EXPECT_GT(ego.loop_gap_m, 1.0);  // the egomotion drifts: there is a loop to close
    EXPECT_LE(slam.loop_gap_m, 0.2 * ego.loop_gap_m);
    EXPECT_LE(slam.loop_gap_m, 0.005 * slam.path_length_m);
    EXPECT_LE(slam.ate_rmse_m, 0.5 * ego.ate_rmse_m);
}

// The paper's method alone ([LoopCloser] off, serial so that the run repeats
// exactly) on a hall seed the shipped tuning was not chosen on: the
// rectifier must close the 3DOF double loop to 0.1 % of the path and halve
// the ATE. Measured: gap 0.692 -> 0.024 m (0.023 % of 104 m), ATE 0.203 ->
// 0.039 m.
TEST(MapperApp, hallDoubleLoopRectifierAloneClosesTheLoop)
{
    const std::string dir = emslam::test::makeTempDir("mapper_hall_rectifier");
    const auto [ego, slam] = mapSimulatedWorld(
        "hall_double_loop", 7, "3dof-low-structured", dir,
        {"--set", "LoopCloser.enabled=false", "--set", "Rectifier.mode=serial"});
    EXPECT_GT(ego.loop_gap_m, 0.3);
    EXPECT_LE(slam.loop_gap_m, 0.001 * slam.path_length_m);
    EXPECT_LT(slam.ate_rmse_m, 0.5 * ego.ate_rmse_m);
}

// The paper's method alone on a 6DOF loop (Chancellor, Exp. 10, serial) must
// do no harm: SLAM ends no worse than the egomotion, loop gap and ATE.
// Measured: gap 1.191 -> 0.119 m, ATE 0.283 -> 0.107 m.
TEST(MapperApp, chancellorLoop6dofRectifierAloneDoesNoHarm)
{
    const std::string dir = emslam::test::makeTempDir("mapper_chancellor_rectifier");
    const auto [ego, slam] = mapSimulatedWorld(
        "chancellor_zero_loop", 1, "6dof-structured", dir,
        {"--set", "LoopCloser.enabled=false", "--set", "Rectifier.mode=serial"});
    EXPECT_LE(slam.ate_rmse_m, ego.ate_rmse_m);
    EXPECT_LE(slam.loop_gap_m, ego.loop_gap_m);
}

// A loop the egomotion's covariance does not foresee: 2 laps of a ring at
// 1.25 frames/s whose egomotion fails a few times in the corners (sim seed 21:
// loop gap 10.3 m, 35 degrees of heading lost in the first lap). Before place
// recognition and the drift of predicted steps, no candidate was within the
// gates at the first revisit (gap 5.7 m, ATE 4.15 -> 2.11 m). The loop must
// close to 0.1 % of the path and the ATE fall to a third. Measured: gap
// 0.011 m, ATE 4.146 -> 0.202 m.
TEST(MapperApp, largeDriftLoopClosesByPlaceRecognition)
{
    const std::string dir = emslam::test::makeTempDir("mapper_large_drift");
    const auto [ego, slam] = mapSimulatedWorld("large_drift_loop", 21, "3dof-low-structured", dir);
    EXPECT_GT(ego.loop_gap_m, 0.03 * ego.path_length_m);  // the drift this is about
    EXPECT_LE(slam.loop_gap_m, 0.001 * slam.path_length_m);
    EXPECT_LE(slam.ate_rmse_m, ego.ate_rmse_m / 3);
}

namespace
{
/** Checks every loop edge of `dir`/map/loop_closures.txt against the truth
 * `dir`/world.tum (its ends at most 1 m apart); returns how many there are. */
std::size_t checkLoopEdgesAgainstTruth(const std::string& dir)
{
    const auto truth = emslam::io::TumTrajectory::fromFile(dir + "/world.tum");
    std::ifstream edges(dir + "/map/loop_closures.txt");
    EXPECT_TRUE(edges.good());
    std::string line;
    std::size_t accepted = 0;
    while (std::getline(edges, line))
    {
        if (line.empty() || line[0] == '#')
        {
            continue;
        }
        std::istringstream in(line);
        std::size_t from = 0, to = 0;
        in >> from >> to;
        if (std::max(from, to) >= truth.size())
        {
            ADD_FAILURE() << "loop edge " << from << " -> " << to << " beyond the truth";
            continue;
        }
        const auto& a = truth.poses[from].pose;
        const auto& b = truth.poses[to].pose;
        EXPECT_LE(a.distanceTo(b), 1.0) << "loop edge " << from << " -> " << to;
        ++accepted;
    }
    return accepted;
}
}  // namespace

// Two identical floors stacked, walked one after the other and never
// revisited: every place of the upper floor looks like the one below, 3.2 m
// away. No accepted loop edge may join places truly more than 1 m apart,
// and SLAM must not end worse than the egomotion.
TEST(MapperApp, lookAlikeFloorsCloseNoFalseLoop)
{
    const std::string dir = emslam::test::makeTempDir("mapper_lookalike");
    const auto [ego, slam] = mapSimulatedWorld("lookalike_floors", 2, "6dof-structured", dir);
    const std::size_t accepted = checkLoopEdgesAgainstTruth(dir);
    std::printf("look-alike floors: %zu loop edges accepted\n", accepted);
    EXPECT_LE(slam.ate_rmse_m, ego.ate_rmse_m);
}

// The look-alike floors with periodic textures on every surface (no true
// revisit): the first 700 frames, the ground floor and most of the upper
// one. The loop closer registered the upper floor's places to the ones
// below (before issue 40: 162 loop edges over the whole walk, all 1.5-7.2 m
// off, SLAM ATE 2.54 m against the egomotion's 0.86 m). Now the solved graph
// contradicts them more than chance explains, the run says it is unreliable
// and no loop edge is kept. The rectifier runs only at the end (serial,
// rectify_every 0: the test is about the loops). Measured (sim seed 63): no
// loop edge (4 groups refused among 132 loop edges tested, all withdrawn),
// ATE egomotion 0.728 m, SLAM 0.756 m; 51 s, 31 s of CPU, on a loaded
// machine.
TEST(MapperApp, lookAlikePeriodicFloorsCloseNoFalseLoopAndSayItIsUnreliable)
{
    const std::string dir = emslam::test::makeTempDir("mapper_lookalike_periodic");
    const auto [ego, slam] = mapSimulatedWorld(
        "lookalike_periodic", 63, "6dof-structured", dir,
        {"--set", "Rectifier.mode=serial", "--set", "Rectifier.rectify_every=0"},
        {"--max-frames", "700"});
    const std::size_t accepted = checkLoopEdgesAgainstTruth(dir);
    const std::string summary = readText(dir + "/map/summary.json");
    std::printf("look-alike periodic floors: %zu loop edges accepted\n", accepted);
    EXPECT_NE(summary.find("\"unreliable\": [\"loop closing: "), std::string::npos);
    // Its loop edges withdrawn and unpolished, the SLAM estimate is the
    // egomotion's chain with the local edges (no rectification before the
    // end here): within 5 % of the egomotion. The whole walks with the
    // shipped rectifier end below it (doc/notes/2026-12-04-online-loop-closing.md, issue 40's
    // table).
    EXPECT_LE(slam.ate_rmse_m, 1.05 * ego.ate_rmse_m);
}

namespace
{
/** Imports the KITTI 06 excerpt of ../shared/data into `dir`/k06.rawlog (and
 * its ground truth k06.tum; `frames` is emslam-import's --frames, empty: all),
 * maps it with kitti.ini into `dir`/map and prints and returns the
 * egomotion's and SLAM's metrics against the ground truth. */
std::pair<emslam::eval::TrajectoryMetrics, emslam::eval::TrajectoryMetrics> mapKitti06(
    MapperApp& app,
    const std::string& seq,
    const std::string& poses,
    const std::string& dir,
    const std::string& frames)
{
    emslam::apps::ImportApp import;
    std::vector<std::string> args = {
        "emslam-import", "kitti",          seq,      "--gt", poses, "-o", dir + "/k06.rawlog",
        "--gt-out",      dir + "/k06.tum", "--quiet"};
    if (!frames.empty())
    {
        args.insert(args.end(), {"--frames", frames});
    }
    auto argv = argvOf(args);
    import.initialize(static_cast<int>(argv.size()), argv.data());
    import.run();
    const auto [ego, slam] = mapWithGroundTruth(
        app, {config("kitti"), dir + "/k06.rawlog", "--out", dir + "/map", "--gt", dir + "/k06.tum",
              "-q"});
    std::printf(
        "KITTI 06 (frames '%s'): ATE egomotion %.3f m, SLAM %.3f m; end error egomotion %.3f m, "
        "SLAM %.3f m\n",
        frames.c_str(), ego.ate_rmse_m, slam.ate_rmse_m, ego.end_error_m, slam.end_error_m);
    return {ego, slam};
}
}  // namespace

// Issue acceptance: on a straight drive (the KITTI 06 excerpt, 51 frames,
// 60 m) global rectification must do no harm.
TEST(MapperApp, kitti06RectificationDoesNoHarm)
{
    EMSLAM_REQUIRE_TEST_DATA(seq, "kitti-odometry/sequences/06");
    EMSLAM_REQUIRE_TEST_DATA(poses, "kitti-odometry/poses/06.txt");
    const std::string dir = emslam::test::makeTempDir("mapper_kitti06");
    MapperApp app;
    const auto [ego, slam] = mapKitti06(app, seq, poses, dir, "");
    ASSERT_EQ(slam.matched_poses, 51U);
    EXPECT_LE(slam.ate_rmse_m, ego.ate_rmse_m + 1e-6);
    EXPECT_LE(slam.end_error_m, ego.end_error_m + 1e-6);
    // kitti.ini matches guided, with sparse stereo at the features: every
    // step after the first has a prediction. Measured ATE 0.095 m, end error
    // 0.36 m with the reprojection refinement (without: 0.085 / 0.15 m;
    // dense SGBM: 0.045 / 0.28 m; the paper's full search 0.095 / 0.38 m).
    EXPECT_GE(app.mapper().guidedSteps(), 45U);
    EXPECT_LT(ego.ate_rmse_m, 0.12);
    EXPECT_LT(ego.end_error_m, 0.45);
    EXPECT_NE(readText(dir + "/map/summary.json").find("\"guided_steps\": "), std::string::npos);
}

// The KITTI 06 pseudo-loop: the excerpt's frames forward, then back
// (--frames 0:50:2,49:1:-2), so the last pose should meet the first. The
// egomotion ends 0.8 m away; kitti.ini (rectifier seed 1, serial,
// deterministic) must bring the end within 0.15 m and to 1/5 of that, and
// halve the ATE. Measured: end 0.798 -> 0.052 m, ATE 0.243 -> 0.087 m;
// rectifier seeds 1-12 end at 0.033-0.067 m
// (doc/notes/2026-12-03-egomotion-turns-and-reprojection.md).
TEST(MapperApp, kitti06PseudoLoopRectificationCloses)
{
    EMSLAM_REQUIRE_TEST_DATA(seq, "kitti-odometry/sequences/06");
    EMSLAM_REQUIRE_TEST_DATA(poses, "kitti-odometry/poses/06.txt");
    const std::string dir = emslam::test::makeTempDir("mapper_kitti06_loop");
    MapperApp app;
    const auto [ego, slam] = mapKitti06(app, seq, poses, dir, "0:50:2,49:1:-2");
    ASSERT_EQ(slam.matched_poses, 51U);
    EXPECT_GT(ego.end_error_m, 0.5);  // there is a misclosure to remove
    EXPECT_LE(slam.end_error_m, 0.15);
    EXPECT_LE(slam.end_error_m, 0.2 * ego.end_error_m);
    EXPECT_LE(slam.ate_rmse_m, 0.5 * ego.ate_rmse_m);
}

// First contact: the KITTI dataset folder itself (no import), the config by
// its shipped name, the ground truth found in the folder. The same run as the
// imported rawlog's (kitti06RectificationDoesNoHarm): measured ATE egomotion
// 0.095 m, SLAM 0.088 m; end error 0.355 / 0.271 m, both ways.
TEST(MapperApp, kitti06FolderIsMappedByConfigNameWithItsOwnGroundTruth)
{
    EMSLAM_REQUIRE_TEST_DATA(root, "kitti-odometry");
    const std::string dir = emslam::test::makeTempDir("mapper_kitti06_folder");
    MapperApp app;
    initApp(app, {"-c", "kitti", root, "--out", dir + "/map", "-q"});
    app.run();
    const auto& info = app.runInfo();
    ASSERT_TRUE(info.egomotion_vs_gt && info.slam_vs_gt);
    const auto& ego = *info.egomotion_vs_gt;
    const auto& slam = *info.slam_vs_gt;
    ASSERT_EQ(slam.matched_poses, 51U);
    EXPECT_LT(ego.ate_rmse_m, 0.12);
    EXPECT_LT(ego.end_error_m, 0.45);
    EXPECT_LE(slam.ate_rmse_m, ego.ate_rmse_m + 1e-6);
    EXPECT_LE(slam.end_error_m, ego.end_error_m + 1e-6);
    EXPECT_NE(
        readText(dir + "/map/summary.json").find("/config/mapper/kitti.ini\""), std::string::npos);
}

// The EuRoC excerpt's folder (raw, distorted images: the calibrated path),
// mapped by config name with the left camera's ground truth found beside
// mav0: the camera is at rest (under 3 mm of motion), so an honest run ends
// where it started. Measured: ATE 0.001 m, start-to-end 0.002 m.
TEST(MapperApp, eurocFolderIsMappedByConfigNameWithItsOwnGroundTruth)
{
    EMSLAM_REQUIRE_TEST_DATA(root, "euroc-v101-rest");
    const std::string dir = emslam::test::makeTempDir("mapper_euroc_folder");
    MapperApp app;
    initApp(app, {"euroc.ini", root, "--out", dir + "/map", "-q"});
    app.run();
    const auto& info = app.runInfo();
    ASSERT_TRUE(info.egomotion_vs_gt && info.slam_vs_gt);
    EXPECT_EQ(info.slam_vs_gt->matched_poses, 40U);
    EXPECT_EQ(app.mapper().egomotionFailures(), 0U);
    EXPECT_LT(info.egomotion_vs_gt->ate_rmse_m, 0.01);
    EXPECT_LT(info.slam_vs_gt->ate_rmse_m, 0.01);
    EXPECT_LT(info.slam_vs_gt->end_error_m, 0.02);
}

// The largest (or smallest) value each dangerous key accepts is safe: the
// check refuses the next one, and a tiny run with it ends (clean result or a
// clean exception), no crash, no overflow.
TEST(MapperApp, extremeAcceptedValuesOfDangerousKeysRunSafely)
{
    struct Extreme
    {
        std::string key, accepted, refused;
    };
    const std::vector<Extreme> extremes = {
        {"StereoMatcher.block_size", "255", "257"},
        {"StereoMatcher.lr_max_diff", "1024", "1025"},
        {"StereoMatcher.min_disparity", "1000", "1001"},
        {"StereoMatcher.min_disparity", "-1000", "-1001"},
        {"StereoMatcher.num_disparities", "1024", "1025"},
        {"EntropyVoxelMap.cell_size", "0.01", "0.009"},
        {"EgomotionEstimator.window_size", "128", "129"},
        {"EgomotionEstimator.lp_num_rings", "64", "65"},
        {"EgomotionEstimator.lp_radius", "256", "256.5"},
    };
    const std::string rawlog = simulatedHall(3);
    const std::string text = readText(config("3dof-low-structured"));
    for (const auto& e : extremes)
    {
        SCOPED_TRACE(e.key + " = " + e.accepted);
        const auto dot = e.key.find('.');
        const auto withValue = [&](const std::string& v)
        {
            mrpt::config::CConfigFileMemory c(text);
            c.write(e.key.substr(0, dot), e.key.substr(dot + 1), v);
            return mrpt::config::CConfigFileMemory(c.getContent());
        };
        EXPECT_NO_THROW(MapperApp::checkConfig(withValue(e.accepted)));
        emslam::test::expectThrowContaining(
            [&] { MapperApp::checkConfig(withValue(e.refused)); }, {e.key.substr(dot + 1)});

        MapperApp app;
        initApp(
            app,
            {config("3dof-low-structured"), rawlog, "--out",
             emslam::test::makeTempDir("mapper_extreme"), "-q", "--set", e.key + "=" + e.accepted});
        try
        {
            testing::internal::CaptureStderr();
            app.run();
            (void)testing::internal::GetCapturedStderr();
            EXPECT_EQ(app.mapper().frameCount(), 3U);
        }
        catch (const std::exception& ex)
        {
            (void)testing::internal::GetCapturedStderr();
            std::printf("%s = %s: %s\n", e.key.c_str(), e.accepted.c_str(), ex.what());
        }
    }
}
