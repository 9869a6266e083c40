// SPDX-License-Identifier: BSD-3-Clause
// io::DatasetFolder: which dataset a folder holds, from its files, and the
// ground truth that comes with it.
#include "SyntheticKitti.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/DatasetFolder.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

using emslam::io::DatasetFolder;
using emslam::test::expectThrowContaining;
using emslam::test::writeFile;
namespace fs = std::filesystem;

namespace
{
/** `p` absolute, normalized, without a trailing '/'. */
std::string normal(const std::string& p)
{
    const fs::path n = fs::absolute(p).lexically_normal();
    return (n.has_filename() ? n : n.parent_path()).string();
}

/** A EuRoC `mav0` folder's lists in `root/mav0` (no image: detection only). */
void writeEurocLists(const std::string& root)
{
    for (const char* cam : {"cam0", "cam1"})
    {
        fs::create_directories(root + "/mav0/" + cam + "/data");
        writeFile(root + "/mav0/" + cam + "/data.csv", "#timestamp [ns],filename\n");
    }
}
}  // namespace

TEST(DatasetFolder, kittiSequenceAndTheDatasetFolderAboveIt)
{
    const std::string root = emslam::test::makeTempDir("dataset_folder_kitti");
    // The official layout: sequences/NN and poses/NN.txt.
    fs::rename(emslam::test::writeKittiSequence(root + "/sequences", 2), root + "/sequences/07");

    auto f = DatasetFolder::detect(root + "/sequences/07");
    EXPECT_EQ(f.format, DatasetFolder::Format::Kitti);
    EXPECT_EQ(f.formatName(), "KITTI odometry");
    EXPECT_EQ(f.sequence_dir, root + "/sequences/07");
    EXPECT_EQ(f.ground_truth_file, "");  // no poses/07.txt

    fs::create_directories(root + "/poses");
    fs::rename(root + "/sequences/poses.txt", root + "/poses/07.txt");
    for (const std::string& given : {root + "/sequences/07", root + "/sequences/07/", root})
    {
        f = DatasetFolder::detect(given);
        EXPECT_EQ(normal(f.sequence_dir), normal(root + "/sequences/07")) << given;
        EXPECT_EQ(f.ground_truth_file, normal(root + "/poses/07.txt")) << given;
        const auto s = f.open();
        EXPECT_EQ(s->size(), 2U);
        EXPECT_TRUE(s->hasGroundTruth());
    }

    // Two sequences: the user must choose.
    fs::copy(root + "/sequences/07", root + "/sequences/08", fs::copy_options::recursive);
    expectThrowContaining(
        [&] { DatasetFolder::detect(root); }, {"holds 2 KITTI sequences; give one of them: ",
                                               root + "/sequences/07, ", root + "/sequences/08"});
}

TEST(DatasetFolder, eurocMav0OrItsParentWithTheLeftCameraGroundTruth)
{
    const std::string root = emslam::test::makeTempDir("dataset_folder_euroc");
    writeEurocLists(root);
    for (const std::string& given : {root, root + "/mav0"})
    {
        const auto f = DatasetFolder::detect(given);
        EXPECT_EQ(f.format, DatasetFolder::Format::Euroc);
        EXPECT_EQ(f.sequence_dir, root + "/mav0");
        EXPECT_EQ(f.ground_truth_file, "");
    }
    // The body's ground truth is not the camera's: not picked up.
    fs::create_directories(root + "/mav0/state_groundtruth_estimate0");
    writeFile(root + "/mav0/state_groundtruth_estimate0/data.csv", "#t\n");
    EXPECT_EQ(DatasetFolder::detect(root).ground_truth_file, "");
    writeFile(root + "/groundtruth_left_cam.csv", "#t\n");
    EXPECT_EQ(
        DatasetFolder::detect(root + "/mav0").ground_truth_file,
        normal(root + "/groundtruth_left_cam.csv"));
}

TEST(DatasetFolder, tumRgbdFolder)
{
    const std::string root = emslam::test::makeTempDir("dataset_folder_tum");
    writeFile(root + "/rgb.txt", "# colour\n");
    writeFile(root + "/depth.txt", "# depth\n");
    const auto f = DatasetFolder::detect(root);
    EXPECT_EQ(f.format, DatasetFolder::Format::TumRgbd);
    EXPECT_EQ(f.formatName(), "TUM RGB-D");
    EXPECT_EQ(f.sequence_dir, root);
    // Detected, but an empty list is no sequence: the reader says why.
    EXPECT_ANY_THROW(f.open());
}

TEST(DatasetFolder, anyOtherFolderIsRefusedNamingTheLayoutsExpected)
{
    const std::string root = emslam::test::makeTempDir("dataset_folder_none");
    EXPECT_TRUE(DatasetFolder::isFolder(root));
    EXPECT_FALSE(DatasetFolder::isFolder(root + "/missing"));
    writeFile(root + "/calib.txt", "P0: 1\n");  // half a KITTI sequence
    EXPECT_FALSE(DatasetFolder::isFolder(root + "/calib.txt"));
    expectThrowContaining(
        [&] { DatasetFolder::detect(root); },
        {"'" + root + "' is a folder but no dataset", "KITTI odometry sequence (calib.txt",
         "EuRoC MAV 'mav0'", "TUM RGB-D folder (rgb.txt, depth.txt)"});
}

TEST(DatasetFolder, sharedKittiExcerptWithItsGroundTruth)
{
    EMSLAM_REQUIRE_TEST_DATA(root, "kitti-odometry");
    const auto f = DatasetFolder::detect(root);
    EXPECT_EQ(normal(f.sequence_dir), normal(root + "/sequences/06"));
    EXPECT_EQ(f.ground_truth_file, normal(root + "/poses/06.txt"));
    const auto s = f.open();
    ASSERT_EQ(s->size(), 51U);
    const auto gt = s->groundTruthTrajectory();
    ASSERT_EQ(gt.size(), 51U);
    EXPECT_DOUBLE_EQ(gt.poses.front().t, s->timestamp(0));
    EXPECT_EQ(gt.poses.front().pose, mrpt::poses::CPose3D());
    // README: an almost straight 59.9 m drive.
    EXPECT_NEAR(gt.poses.back().pose.norm(), 59.9, 0.05);
}
