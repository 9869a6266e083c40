// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/AppMain.h>
#include <emslam/apps/EvalApp.h>
#include <emslam/apps/PlyFile.h>
#include <emslam/io/EurocTrajectory.h>
#include <emslam/io/GzOutputStream.h>
#include <emslam/io/KittiSequence.h>
#include <emslam/io/KittiTrajectory.h>
#include <emslam/io/TumTrajectory.h>

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using emslam::io::TumTrajectory;
using mrpt::poses::CPose3D;

namespace
{
struct EvalRun
{
    int exit_code;
    std::string out, err;
};

/** Runs the whole emslam-eval main body (appMain) in-process: exit code and output. */
EvalRun runEval(std::vector<std::string> args)
{
    args.insert(args.begin(), "emslam-eval");
    std::vector<char*> argv;
    argv.reserve(args.size());
    for (auto& a : args)
    {
        argv.push_back(a.data());
    }
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    const int rc = emslam::apps::appMain<emslam::apps::EvalApp>(
        "emslam-eval", static_cast<int>(argv.size()), argv.data());
    EvalRun r{rc, testing::internal::GetCapturedStdout(), testing::internal::GetCapturedStderr()};
    return r;
}

/** The number after `"key": ` in a flat JSON object (NaN if absent or null). */
double jsonValue(const std::string& json, const std::string& key)
{
    const auto pos = json.find("\"" + key + "\": ");
    if (pos == std::string::npos || json.compare(pos + key.size() + 4, 4, "null") == 0)
    {
        return std::nan("");
    }
    return std::strtod(json.c_str() + pos + key.size() + 4, nullptr);
}

std::string readFile(const std::string& path)
{
    std::ifstream f(path);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

/** A 40 m line, one pose per metre at 10 Hz; `stretch` scales the positions. */
TumTrajectory line(double stretch, double t_offset = 0.0)
{
    TumTrajectory t;
    for (int i = 0; i <= 40; ++i)
    {
        t.add(1000.0 + 0.1 * i + t_offset, CPose3D(stretch * i, 0, 0, 0, 0, 0));
    }
    return t;
}

void expectFailure(const std::vector<std::string>& args, std::initializer_list<std::string> parts)
{
    const EvalRun r = runEval(args);
    EXPECT_NE(r.exit_code, 0);
    for (const auto& p : parts)
    {
        EXPECT_NE(r.err.find(p), std::string::npos) << "stderr lacks '" << p << "': " << r.err;
    }
}
}  // namespace

TEST(EvalApp, helpExitsZero)
{
    const EvalRun r = runEval({"--help"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("--align"), std::string::npos);
}

// A 2 % scale drift on a 40 m line, estimate stamps 5 ms late.
TEST(EvalApp, writesJsonWithKnownValues)
{
    const std::string dir = emslam::test::makeTempDir("eval_app");
    line(1.0).saveToFile(dir + "/gt.tum");
    line(1.02, 0.005).saveToFile(dir + "/est.tum");
    const EvalRun r = runEval({dir + "/gt.tum", dir + "/est.tum", "--json", dir + "/m.json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("ATE RMSE"), std::string::npos) << r.out;
    const std::string json = readFile(dir + "/m.json");
    EXPECT_EQ(jsonValue(json, "matched_poses"), 41.0) << json;
    EXPECT_DOUBLE_EQ(jsonValue(json, "path_length_m"), 40.0);
    EXPECT_NEAR(jsonValue(json, "loop_gap_m"), 40.8, 1e-9);
    EXPECT_NEAR(jsonValue(json, "end_error_m"), 0.8, 1e-9);
    // See TrajectoryMetrics.constantScaleDriftShortPath.
    EXPECT_NEAR(jsonValue(json, "t_rel_percent"), 2.0 * 18.0375 / 16.0, 1e-9);
    EXPECT_NEAR(jsonValue(json, "r_rel_deg_per_m"), 0.0, 1e-12);
    // Rigid fit of x_gt = 1.02 x_est + c: residual RMSE = 0.02 * std(x) = 0.02 * sqrt(140).
    EXPECT_NEAR(jsonValue(json, "ate_rmse_m"), 0.02 * std::sqrt(140.0), 1e-9);

    const EvalRun sim =
        runEval({dir + "/gt.tum", dir + "/est.tum", "--align", "sim3", "--json", dir + "/s.json"});
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const std::string sj = readFile(dir + "/s.json");
    EXPECT_NEAR(jsonValue(sj, "scale"), 1.0 / 1.02, 1e-12);
    EXPECT_LT(jsonValue(sj, "ate_rmse_m"), 1e-9);
    EXPECT_LT(jsonValue(sj, "t_rel_percent"), 1e-9);
}

namespace
{
/** The unit square z = 0 sampled every 2 cm (normal +z, seen from 2 m). */
emslam::eval::ReferenceSurface floorSquare()
{
    emslam::eval::ReferenceSurface r;
    r.spacing = 0.02;
    for (int i = 0; i < 50; ++i)
    {
        for (int j = 0; j < 50; ++j)
        {
            r.points.emplace_back(
                static_cast<float>((i + 0.5) * 0.02), static_cast<float>((j + 0.5) * 0.02), 0.0F);
            r.normals.emplace_back(0.0F, 0.0F, 1.0F);
            r.seen_range.push_back(2.0F);
        }
    }
    return r;
}

/** A free 2 x 2 m grid of 10 cm cells with the cells of `occupied` (x, y) set. */
void writeGrid(const std::string& file, const std::vector<std::pair<double, double>>& occupied)
{
    mrpt::maps::COccupancyGridMap2D g;
    g.setSize(0.0F, 2.0F, 0.0F, 2.0F, 0.1F, 1.0F);
    for (const auto& [x, y] : occupied)
    {
        g.setCell(g.x2idx(x), g.y2idx(y), 0.0F);
    }
    emslam::io::GzOutputStream f(file, 1, file);
    mrpt::serialization::archiveFrom(f) << g;
    f.close();
}
}  // namespace

// The map is the left half of the floor square, 3 cm above it; the grid has
// one of its two walls' cells right and one false cell.
TEST(EvalApp, measuresAMapAndAGridAgainstTheTruth)
{
    const std::string dir = emslam::test::makeTempDir("eval_app_map");
    const auto truth = floorSquare();
    emslam::apps::saveReferencePly(truth, dir + "/ref.ply");
    emslam::slam::IntensityCloud map;
    for (const auto& p : truth.points)
    {
        if (p.x < 0.5F)
        {
            map.points.emplace_back(p.x, p.y, 0.03F);
            map.intensity.push_back(128);
        }
    }
    emslam::apps::savePly(map, dir + "/map.ply");
    writeGrid(dir + "/plan.gridmap", {{0.55, 0.55}, {1.55, 1.55}});
    writeGrid(dir + "/grid.gridmap", {{0.65, 0.55}, {1.05, 0.25}});

    const EvalRun r = runEval(
        {"--map", dir + "/map.ply", "--map-gt", dir + "/ref.ply", "--grid", dir + "/grid.gridmap",
         "--grid-gt", dir + "/plan.gridmap", "--json", dir + "/m.json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("map accuracy       median 0.0300 m"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("grid occupied      precision 0.500, recall 0.500"), std::string::npos)
        << r.out;
    EXPECT_EQ(r.out.find("ATE"), std::string::npos) << "no trajectory was given";
    const std::string json = readFile(dir + "/m.json");
    EXPECT_NEAR(jsonValue(json, "accuracy_median_m"), 0.03, 1e-6) << json;
    EXPECT_NEAR(jsonValue(json, "accuracy_p90_m"), 0.03, 1e-6);
    // Columns x < 0.5 (25 of 50), and x = 0.51, 0.53 within 5 cm of them.
    EXPECT_DOUBLE_EQ(jsonValue(json, "completeness"), 27.0 / 50.0);
    EXPECT_DOUBLE_EQ(jsonValue(json, "f1"), 0.5);

    // With trajectories too: their keys stay at the top level.
    line(1.0).saveToFile(dir + "/gt.tum");
    const EvalRun both = runEval(
        {dir + "/gt.tum", dir + "/gt.tum", "--map", dir + "/map.ply", "--map-gt", dir + "/ref.ply",
         "--json", dir + "/b.json"});
    ASSERT_EQ(both.exit_code, 0) << both.err;
    const std::string bj = readFile(dir + "/b.json");
    EXPECT_EQ(jsonValue(bj, "matched_poses"), 41.0) << bj;
    EXPECT_NE(bj.find("\"map_accuracy\": {"), std::string::npos) << bj;
    EXPECT_NEAR(jsonValue(bj, "accuracy_median_m"), 0.03, 1e-6);

    // A map in the estimate's frame (here 0.2 m above the truth's, as its
    // trajectory) is moved by the trajectory's alignment before measuring.
    TumTrajectory gt_square, est_square;
    for (int i = 0; i < 40; ++i)
    {
        const double x = i < 10 ? i : (i < 20 ? 10 : (i < 30 ? 30 - i : 0));
        const double y = i < 10 ? 0 : (i < 20 ? i - 10 : (i < 30 ? 10 : 40 - i));
        gt_square.add(1000.0 + 0.1 * i, CPose3D(x, y, 0, 0, 0, 0));
        est_square.add(1000.0 + 0.1 * i, CPose3D(x, y, 0.2, 0, 0, 0));
    }
    gt_square.saveToFile(dir + "/gt_square.tum");
    est_square.saveToFile(dir + "/est_square.tum");
    emslam::slam::IntensityCloud raised = map;
    for (auto& p : raised.points)
    {
        p.z += 0.2F;
    }
    emslam::apps::savePly(raised, dir + "/raised.ply");
    const EvalRun aligned = runEval(
        {dir + "/gt_square.tum", dir + "/est_square.tum", "--map", dir + "/raised.ply", "--map-gt",
         dir + "/ref.ply", "--json", dir + "/a.json"});
    ASSERT_EQ(aligned.exit_code, 0) << aligned.err;
    EXPECT_NE(aligned.out.find("map alignment      the trajectory's (se3)"), std::string::npos)
        << aligned.out;
    EXPECT_NEAR(jsonValue(readFile(dir + "/a.json"), "accuracy_median_m"), 0.03, 1e-5);
    EXPECT_NE(readFile(dir + "/a.json").find("\"map_alignment\": \"se3\""), std::string::npos);
    const EvalRun as_is = runEval(
        {dir + "/gt_square.tum", dir + "/est_square.tum", "--map", dir + "/raised.ply", "--map-gt",
         dir + "/ref.ply", "--align", "none", "--json", dir + "/n.json"});
    ASSERT_EQ(as_is.exit_code, 0) << as_is.err;
    EXPECT_NE(as_is.out.find("map alignment      none"), std::string::npos) << as_is.out;
    EXPECT_NEAR(jsonValue(readFile(dir + "/n.json"), "accuracy_median_m"), 0.23, 1e-5);

    expectFailure({"--map", dir + "/map.ply"}, {"--map and --map-gt go together"});
    expectFailure({"--grid-gt", dir + "/plan.gridmap"}, {"--grid and --grid-gt go together"});
    expectFailure(
        {"--map", dir + "/ref.ply", "--map-gt", dir + "/none.ply"}, {"none.ply", "true surfaces"});
    expectFailure(
        {"--grid", dir + "/map.ply", "--grid-gt", dir + "/plan.gridmap"},
        {"map.ply' is not an MRPT occupancy grid"});
    expectFailure(
        {"--map", dir + "/map.ply", "--map-gt", dir + "/ref.ply", "--completeness-distance", "0"},
        {"--completeness-distance"});
}

#if defined(EMSLAM_SIM_EXE) && defined(EMSLAM_MAPPER_EXE) && defined(EMSLAM_EVAL_EXE)
// End to end (label e2e): the simulator's truth, the mapper's map and grid of
// the first 60 frames of the hall, and emslam-eval's figures for them.
TEST(EvalApp, endToEndSimMapperEvalMeasuresTheMap)
{
    const std::string dir = emslam::test::makeTempDir("eval_app_e2e");
    const std::string src = emslam::test::sourceDir();
    const std::string mapper_ini = src + "/config/mapper/3dof-low-structured.ini";
    const auto sim = emslam::test::runProgram(
        EMSLAM_SIM_EXE,
        {src + "/config/sim/hall_double_loop.ini", "-o", dir + "/h.rawlog", "--gt-out",
         dir + "/h.tum", "--max-frames", "60", "--map-gt-out", dir + "/ref.ply", "--grid-gt-out",
         dir + "/plan.gridmap", "--grid-config", mapper_ini, "-q"});
    ASSERT_EQ(sim.exit_code, 0) << sim.stderr_text;
    const auto mapper = emslam::test::runProgram(
        EMSLAM_MAPPER_EXE, {mapper_ini, dir + "/h.rawlog", "--out", dir + "/map", "-q"});
    ASSERT_EQ(mapper.exit_code, 0) << mapper.stderr_text;
    const auto eval = emslam::test::runProgram(
        EMSLAM_EVAL_EXE,
        {dir + "/h.tum", dir + "/map/trajectory_slam.tum", "--map", dir + "/map/map.ply",
         "--map-gt", dir + "/ref.ply", "--grid", dir + "/map/map_grid.gridmap", "--grid-gt",
         dir + "/plan.gridmap", "--json", dir + "/eval.json"});
    ASSERT_EQ(eval.exit_code, 0) << eval.stderr_text;
    EXPECT_NE(eval.stdout_text.find("map accuracy       median"), std::string::npos)
        << eval.stdout_text;
    EXPECT_NE(eval.stdout_text.find("grid occupied      precision"), std::string::npos);
    const std::string json = readFile(dir + "/eval.json");
    // Stereo at 320 x 240 with a 10 cm baseline, fused per keyframe and
    // moved by the poses' alignment (a straight path: the positions alone
    // left its turn free, 1.05 m): median 0.013 m, p90 0.04 m, 36 % of the
    // near surfaces covered, grid F1 0.87 measured.
    EXPECT_GT(jsonValue(json, "accuracy_median_m"), 0.005) << json;
    EXPECT_LT(jsonValue(json, "accuracy_median_m"), 0.05);
    EXPECT_LT(jsonValue(json, "accuracy_p90_m"), 0.2);
    EXPECT_GT(jsonValue(json, "completeness_near"), 0.2);
    EXPECT_GT(jsonValue(json, "true_occupied"), 50.0);
    EXPECT_GT(jsonValue(json, "f1"), 0.6);
}
#endif

TEST(EvalApp, badInputFailsWithMessage)
{
    const std::string dir = emslam::test::makeTempDir("eval_app_bad");
    const std::string gt = dir + "/gt.tum", est = dir + "/est.tum";
    line(1.0).saveToFile(gt);
    line(1.0).saveToFile(est);
    emslam::test::writeFile(dir + "/empty.tum", "# no poses\n");
    emslam::test::writeFile(dir + "/garbled.tum", "1000.0 1 2 3\n");
    line(1.0, 60.0).saveToFile(dir + "/late.tum");

    expectFailure({dir + "/nope.tum", est}, {"ground-truth", "nope.tum", "exist"});
    expectFailure({gt, dir + "/nope.tum"}, {"estimate", "nope.tum", "exist"});
    expectFailure({gt, dir}, {"estimate", "directory"});
    expectFailure({gt, dir + "/garbled.tum"}, {"estimate", "garbled.tum:1"});
    expectFailure({dir + "/empty.tum", est}, {"ground-truth", "no poses"});
    expectFailure({gt, dir + "/empty.tum"}, {"estimate", "no poses"});
    expectFailure({gt, dir + "/late.tum"}, {"no timestamp", "late.tum"});
    expectFailure({gt, est, "--align", "affine"}, {"--align", "'affine'"});
    expectFailure({gt, est, "--max-dt", "0"}, {"--max-dt"});
    expectFailure(
        {gt, est, "--segment-step", "-1"}, {"--segment-step must be at least 1", "got -1"});
    expectFailure({gt, est, "--segment-step", "0"}, {"--segment-step must be at least 1"});
    expectFailure({}, {"missing required arguments <GT>, <EST>"});
    expectFailure({gt}, {"missing required argument <EST>"});
    expectFailure({gt, est, "--json", dir + "/no/such/dir/m.json"}, {"m.json"});
    // Unreadable (permissions): root reads anyway, so only checked as a user.
    if (::geteuid() != 0)
    {
        const std::string locked = dir + "/locked.tum";
        line(1.0).saveToFile(locked);
        std::filesystem::permissions(locked, std::filesystem::perms::none);
        expectFailure({gt, locked}, {"cannot read estimate", "locked.tum"});
    }
    // A wider tolerance lets the shifted estimate match.
    EXPECT_EQ(runEval({gt, dir + "/late.tum", "--max-dt", "61"}).exit_code, 0);
}

// Found on 80c9fba: an estimate with 1e300 coordinates gave "ATE n/a", JSON
// null and exit 0; the no-overlap message rounded stamps to 6 digits.
TEST(EvalApp, absurdCoordinatesAndExactNumbersInMessages)
{
    const std::string dir = emslam::test::makeTempDir("eval_app_absurd");
    const std::string gt = dir + "/gt.tum";
    line(1.0).saveToFile(gt);
    emslam::test::writeFile(
        dir + "/huge.tum", "0 0 0 0 0 0 0 1\n0.1 1e300 0 0 0 0 0 1\n0.2 0.2 0 0 0 0 0 1\n");
    expectFailure(
        {gt, dir + "/huge.tum"}, {"estimate file", "huge.tum", "pose 2 (t = 0.1 s)",
                                  "lies at (1e+300, 0, 0) m", "beyond 1e+09 m"});
    expectFailure({dir + "/huge.tum", gt}, {"ground-truth file", "pose 2"});
    emslam::test::writeFile(
        dir + "/late.tum", "2317340800.123456 0 0 0 0 0 0 1\n2317340801.5 1 0 0 0 0 0 1\n");
    expectFailure(
        {gt, dir + "/late.tum", "--max-dt", "0.0001"},
        {"max_dt = 0.0001 s", "estimate [2317340800.123456, 2317340801.5] s"});
    // The output may not be one of the inputs.
    expectFailure({gt, gt, "--json", gt}, {"--json", "is the ground truth"});
}

// KITTI 06 frames 0-50 (59.9 m): the ground truth against itself and against a
// copy scaled by 1.01.
TEST(EvalApp, kitti06GroundTruth)
{
    EMSLAM_REQUIRE_TEST_DATA(seq_dir, "kitti-odometry/sequences/06");
    EMSLAM_REQUIRE_TEST_DATA(poses, "kitti-odometry/poses/06.txt");
    const emslam::io::KittiSequence seq(seq_dir, poses);
    TumTrajectory gt, est;
    for (std::size_t i = 0; i < seq.size(); ++i)
    {
        const CPose3D& p = seq.groundTruth(i);
        gt.add(seq.timestamp(i), p);
        CPose3D s = p;
        s.x(1.01 * p.x());
        s.y(1.01 * p.y());
        s.z(1.01 * p.z());
        est.add(seq.timestamp(i), s);
    }
    const std::string dir = emslam::test::makeTempDir("eval_app_kitti");
    gt.saveToFile(dir + "/gt.tum");
    est.saveToFile(dir + "/est.tum");

    ASSERT_EQ(
        runEval({dir + "/gt.tum", dir + "/gt.tum", "--json", dir + "/self.json"}).exit_code, 0);
    const std::string self = readFile(dir + "/self.json");
    EXPECT_EQ(jsonValue(self, "matched_poses"), 51.0);
    EXPECT_NEAR(jsonValue(self, "path_length_m"), 59.9, 0.05);
    EXPECT_LT(jsonValue(self, "ate_rmse_m"), 1e-9);
    EXPECT_LT(jsonValue(self, "t_rel_percent"), 1e-9);
    // Straight drive: the loop gap is about the path length.
    EXPECT_NEAR(jsonValue(self, "loop_gap_m"), 59.9, 1.0);

    const EvalRun r = runEval(
        {dir + "/gt.tum", dir + "/est.tum", "--align", "sim3", "--json", dir + "/sim.json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string sim = readFile(dir + "/sim.json");
    EXPECT_NEAR(jsonValue(sim, "scale"), 1.0 / 1.01, 1e-9);
    EXPECT_LT(jsonValue(sim, "ate_rmse_m"), 1e-6);
    ASSERT_EQ(
        runEval({dir + "/gt.tum", dir + "/est.tum", "--json", dir + "/se3.json"}).exit_code, 0);
    // 1 % longer steps: 1 % drift, a little more as segments end past their
    // nominal length (frames are ~1.2 m apart, the shortest segment 6 m).
    const double t_rel = jsonValue(readFile(dir + "/se3.json"), "t_rel_percent");
    EXPECT_GE(t_rel, 1.0);
    EXPECT_LT(t_rel, 1.25);
}

// The same 40 m line as KITTI poses in the KITTI layout (times.txt in
// sequence time) and as a EuRoC CSV: each is read against a TUM estimate.
TEST(EvalApp, readsKittiAndEurocGroundTruth)
{
    const std::string dir = emslam::test::makeTempDir("eval_app_formats");
    const TumTrajectory gt = line(1.0);
    const TumTrajectory est = line(1.02);
    std::filesystem::create_directories(dir + "/poses");
    std::filesystem::create_directories(dir + "/sequences/00");
    std::string poses, times, csv;
    for (const auto& p : gt.poses)
    {
        poses += emslam::io::KittiTrajectory::formatLine(p.pose) + "\n";
        times += std::to_string(p.t - 1000.0) + "\n";  // seconds from the start
        csv += std::to_string(static_cast<long long>(std::llround(p.t * 1e9))) + "," +
               std::to_string(p.pose.x()) + ",0,0,1,0,0,0\n";  // w first (header)
    }
    emslam::test::writeFile(dir + "/poses/00.txt", poses);
    emslam::test::writeFile(dir + "/sequences/00/times.txt", times);
    emslam::test::writeFile(
        dir + "/gt.csv",
        "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], "
        "q_RS_z []\n" +
            csv);
    est.saveToFile(dir + "/est.tum");

    // KITTI: the times are found in sequences/00 and shifted to the estimate's clock.
    const EvalRun k = runEval(
        {"--gt", dir + "/poses/00.txt", "--est", dir + "/est.tum", "--kitti-time-offset", "1000",
         "--json", dir + "/k.json"});
    ASSERT_EQ(k.exit_code, 0) << k.err;
    EXPECT_NE(k.out.find("ground truth kitti, estimate tum"), std::string::npos) << k.out;
    const EvalRun e =
        runEval({"--gt", dir + "/gt.csv", "--est", dir + "/est.tum", "--json", dir + "/e.json"});
    ASSERT_EQ(e.exit_code, 0) << e.err;
    EXPECT_NE(e.out.find("ground truth euroc"), std::string::npos) << e.out;
    for (const char* json : {"/k.json", "/e.json"})
    {
        SCOPED_TRACE(json);
        const std::string j = readFile(dir + json);
        EXPECT_EQ(jsonValue(j, "matched_poses"), 41.0) << j;
        EXPECT_NEAR(jsonValue(j, "path_length_m"), 40.0, 1e-6);
        // As writesJsonWithKnownValues: a 2 % scale error.
        EXPECT_NEAR(jsonValue(j, "ate_rmse_m"), 0.02 * std::sqrt(140.0), 1e-6);
    }

    // Without the offset the sequence times (0..4 s) meet no estimated stamp.
    expectFailure(
        {"--gt", dir + "/poses/00.txt", "--est", dir + "/est.tum"}, {"no timestamp", "00.txt"});
    // Forced formats that do not fit the content name the file and line.
    expectFailure(
        {"--gt", dir + "/poses/00.txt", "--gt-format", "tum", "--est", dir + "/est.tum"},
        {"ground-truth", "00.txt:1", "8 numbers"});
    expectFailure(
        {"--gt", dir + "/gt.csv", "--est", dir + "/est.tum", "--est-format", "kitti"},
        {"estimate", "est.tum:1", "12 numbers"});
    expectFailure(
        {"--gt", dir + "/gt.csv", "--est", dir + "/est.tum", "--gt-format", "ply"},
        {"--gt-format", "'ply'"});
}

// KITTI poses without times: an error against a timed estimate, paired line
// by line against KITTI poses without times.
TEST(EvalApp, kittiWithoutTimes)
{
    const std::string dir = emslam::test::makeTempDir("eval_app_untimed");
    std::string gt, est;
    for (const auto& p : line(1.0).poses)
    {
        gt += emslam::io::KittiTrajectory::formatLine(p.pose) + "\n";
    }
    for (const auto& p : line(1.02).poses)
    {
        est += emslam::io::KittiTrajectory::formatLine(p.pose) + "\n";
    }
    emslam::test::writeFile(dir + "/gt.txt", gt);
    emslam::test::writeFile(dir + "/est.txt", est);
    line(1.02).saveToFile(dir + "/est.tum");
    expectFailure(
        {"--gt", dir + "/gt.txt", "--est", dir + "/est.tum"},
        {"ground truth", "gt.txt' has no times file", dir + "/gt_times.txt", "--gt-times"});
    expectFailure(
        {"--gt", dir + "/est.tum", "--est", dir + "/est.txt"},
        {"estimate", "est.txt' has no times file", "--est-times"});
    const EvalRun r =
        runEval({"--gt", dir + "/gt.txt", "--est", dir + "/est.txt", "--json", dir + "/m.json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("paired line by line"), std::string::npos) << r.out;
    const std::string j = readFile(dir + "/m.json");
    EXPECT_EQ(jsonValue(j, "matched_poses"), 41.0);
    EXPECT_NEAR(jsonValue(j, "ate_rmse_m"), 0.02 * std::sqrt(140.0), 1e-6);
}

// The real files as a user has them: poses/06.txt (times from
// sequences/06/times.txt) and EuRoC's CSV, each against itself in TUM.
TEST(EvalApp, realKittiAndEurocGroundTruthFiles)
{
    EMSLAM_REQUIRE_TEST_DATA(poses, "kitti-odometry/poses/06.txt");
    EMSLAM_REQUIRE_TEST_DATA(seq_dir, "kitti-odometry/sequences/06");
    EMSLAM_REQUIRE_TEST_DATA(euroc, "euroc-v101-rest/groundtruth_left_cam.csv");
    const std::string dir = emslam::test::makeTempDir("eval_app_real");
    // As emslam-import kitti writes it (--gt-out): UNIX times.
    const emslam::io::KittiSequence seq(seq_dir, poses);
    TumTrajectory k;
    for (std::size_t i = 0; i < seq.size(); ++i)
    {
        k.add(seq.timestamp(i), seq.groundTruth(i));
    }
    k.saveToFile(dir + "/k06.tum");
    emslam::io::EurocTrajectory::load(euroc).saveToFile(dir + "/euroc.tum");

    const EvalRun kr =
        runEval({"--gt", poses, "--est", dir + "/k06.tum", "--json", dir + "/k.json"});
    ASSERT_EQ(kr.exit_code, 0) << kr.err;
    const std::string kj = readFile(dir + "/k.json");
    EXPECT_EQ(jsonValue(kj, "matched_poses"), 51.0);
    EXPECT_NEAR(jsonValue(kj, "path_length_m"), 59.9, 0.05);
    EXPECT_LT(jsonValue(kj, "ate_rmse_m"), 1e-6);

    const EvalRun er =
        runEval({"--gt", euroc, "--est", dir + "/euroc.tum", "--json", dir + "/e.json"});
    ASSERT_EQ(er.exit_code, 0) << er.err;
    const std::string ej = readFile(dir + "/e.json");
    EXPECT_EQ(jsonValue(ej, "matched_poses"), 40.0);
    EXPECT_LT(jsonValue(ej, "ate_rmse_m"), 1e-6);
}
