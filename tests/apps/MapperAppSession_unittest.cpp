// SPDX-License-Identifier: BSD-3-Clause
// emslam-mapper's sessions end to end (--save-session, --load-session,
// --localize) on the simulated hall cut in two rawlogs: the second continues
// the first and the outputs hold both; a third run is localized in the saved
// session and leaves the file as it was; bad sessions and options are refused.
#include "SimulatedHall.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/TumTrajectory.h>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

// Runs the built emslam-mapper: not in builds without the apps (the sanitizer build).
#ifdef EMSLAM_MAPPER_EXE
namespace
{
using emslam::test::runProgram;

std::string readBytes(const std::string& file)
{
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/** RMSE of the positions of `est` against `truth`, matched by timestamp
 * (within 1 ms), without alignment [m]. */
double unalignedRmse(const emslam::io::TumTrajectory& est, const emslam::io::TumTrajectory& truth)
{
    double s = 0;
    std::size_t n = 0;
    for (const auto& p : est.poses)
    {
        for (const auto& t : truth.poses)
        {
            if (std::abs(t.t - p.t) < 1e-3)
            {
                s += std::pow(p.pose.distanceTo(t.pose), 2);
                ++n;
                break;
            }
        }
    }
    return n == est.size() ? std::sqrt(s / static_cast<double>(n)) : INFINITY;
}
}  // namespace

TEST(MapperAppSession, mapsInTwoSessionsAndLocalizesInTheSavedOne)
{
    constexpr std::size_t FIRST = 120, SECOND = 80;
    const std::string dir = emslam::test::makeTempDir("mapper_session");
    const std::string part1 = dir + "/part1.rawlog", part2 = dir + "/part2.rawlog";
    emslam::test::writeHallFrames(part1, 0, FIRST);
    emslam::test::writeHallFrames(part2, FIRST, SECOND);
    const std::string hall = emslam::test::simulatedHall(FIRST + SECOND);
    const std::string gt = hall.substr(0, hall.size() - 7) + ".tum";
    const std::string config = emslam::test::sourceDir() + "/config/mapper/3dof-low-structured.ini";
    const std::string s1 = dir + "/first.session", s2 = dir + "/both.session";

    const auto first = runProgram(
        EMSLAM_MAPPER_EXE, {config, part1, "-o", dir + "/out1", "-q", "--save-session", s1});
    ASSERT_EQ(first.exit_code, 0) << first.stderr_text;
    EXPECT_NE(first.stdout_text.find("session written to '" + s1 + "'"), std::string::npos);

    // Continued: every frame of both in the outputs, the session saved anew.
    const auto second = runProgram(
        EMSLAM_MAPPER_EXE, {config, part2, "-o", dir + "/out2", "-q", "--load-session", s1,
                            "--save-session", s2, "--gt", gt});
    ASSERT_EQ(second.exit_code, 0) << second.stderr_text;
    EXPECT_NE(second.stdout_text.find("session: continued"), std::string::npos)
        << second.stdout_text;
    const auto slam2 = emslam::io::TumTrajectory::fromFile(dir + "/out2/trajectory_slam.tum");
    EXPECT_EQ(slam2.size(), FIRST + SECOND);
    const std::string summary2 = readBytes(dir + "/out2/summary.json");
    EXPECT_NE(summary2.find("\"use\": \"continue\""), std::string::npos) << summary2;
    EXPECT_NE(summary2.find("\"session_frames\": 120"), std::string::npos) << summary2;
    const double ate2 = unalignedRmse(slam2, emslam::io::TumTrajectory::fromFile(gt));
    std::printf("continued: %zu frames, unaligned RMSE %.3f m\n", slam2.size(), ate2);
    EXPECT_LT(ate2, 0.15);

    // Localized in it: this input's frames only, near the truth, the file unchanged.
    const std::string before = readBytes(s2);
    const auto third = runProgram(
        EMSLAM_MAPPER_EXE,
        {config, part1, "-o", dir + "/out3", "-q", "--load-session", s2, "--localize"});
    ASSERT_EQ(third.exit_code, 0) << third.stderr_text;
    EXPECT_NE(third.stdout_text.find("session: localized in"), std::string::npos);
    const auto slam3 = emslam::io::TumTrajectory::fromFile(dir + "/out3/trajectory_slam.tum");
    EXPECT_EQ(slam3.size(), FIRST);
    const double ate3 = unalignedRmse(slam3, emslam::io::TumTrajectory::fromFile(gt));
    std::printf("localized: %zu frames, unaligned RMSE %.3f m\n", slam3.size(), ate3);
    EXPECT_LT(ate3, 0.15);
    EXPECT_NE(
        readBytes(dir + "/out3/summary.json").find("\"use\": \"localize\""), std::string::npos);
    EXPECT_EQ(readBytes(s2), before);

    // A corrupt session, and options that do not go together.
    const std::string corrupt = dir + "/corrupt.session";
    emslam::test::writeFile(corrupt, before.substr(0, before.size() / 3));
    const auto bad = runProgram(
        EMSLAM_MAPPER_EXE, {config, part2, "-o", dir + "/out4", "-q", "--load-session", corrupt});
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_NE(bad.stderr_text.find("corrupt.session"), std::string::npos) << bad.stderr_text;
    const auto no_session =
        runProgram(EMSLAM_MAPPER_EXE, {config, part2, "-o", dir + "/out5", "--localize"});
    EXPECT_NE(no_session.exit_code, 0);
    EXPECT_NE(no_session.stderr_text.find("--localize needs --load-session"), std::string::npos)
        << no_session.stderr_text;
    const auto save_too = runProgram(
        EMSLAM_MAPPER_EXE, {config, part2, "-o", dir + "/out6", "--load-session", s2, "--localize",
                            "--save-session", dir + "/x.session"});
    EXPECT_NE(save_too.exit_code, 0);
    EXPECT_NE(save_too.stderr_text.find("does not change the session"), std::string::npos);
}
#endif  // EMSLAM_MAPPER_EXE
