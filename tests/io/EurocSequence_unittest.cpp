// SPDX-License-Identifier: BSD-3-Clause
#include "PngWithSize.h"
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/DatasetStamps.h>
#include <emslam/io/EurocSequence.h>
#include <emslam/stereo/StereoCalibration.h>

#include <mrpt/core/Clock.h>
#include <mrpt/poses/CPose3D.h>

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

using emslam::io::EurocSequence;
namespace fs = std::filesystem;

using emslam::test::expectThrowContaining;
using emslam::test::writeFile;

namespace
{
constexpr int W = 32;
constexpr int H = 20;
constexpr std::int64_t T0 = 1403715274312143104;  // EuRoC-like ns timestamps
constexpr std::int64_t DT = 50'000'000;           // 20 Hz

/** A sensor.yaml in the ASL layout; cam1 sits 0.11 m along the body y axis. */
std::string sensorYaml(int cam, int w, int h)
{
    const std::string ty = cam == 0 ? "0.0" : "0.11";
    return "%YAML:1.0\n"
           "sensor_type: camera\n"
           "comment: synthetic cam" +
           std::to_string(cam) +
           "\n"
           "T_BS:\n"
           "  cols: 4\n"
           "  rows: 4\n"
           "  data: [0.0, -1.0, 0.0, 0.0,\n"
           "         1.0, 0.0, 0.0, " +
           ty +
           ",\n"
           "         0.0, 0.0, 1.0, 0.0,\n"
           "         0.0, 0.0, 0.0, 1.0]\n"
           "rate_hz: 20\n"
           "resolution: [" +
           std::to_string(w) + ", " + std::to_string(h) +
           "]\n"
           "camera_model: pinhole\n"
           "intrinsics: [30.0, 31.0, 16.0, 10.0] #fu, fv, cu, cv\n"
           "distortion_model: radial-tangential\n"
           "distortion_coefficients: [-0.2, 0.05, 0.001, -0.0005]\n";
}

std::string imagePath(const std::string& mav0, int cam, int i)
{
    return mav0 + "/cam" + std::to_string(cam) + "/data/" + std::to_string(T0 + i * DT) + ".png";
}

/** The data.csv lines of the images `frames` of a writeSequence() sequence. */
std::string dataRows(std::initializer_list<int> frames)
{
    std::string rows;
    for (const int i : frames)
    {
        const std::string ts = std::to_string(T0 + i * DT);
        rows += ts + "," + ts + ".png\n";
    }
    return rows;
}

/** dataRows() after the header line of data.csv. */
std::string dataCsv(std::initializer_list<int> frames)
{
    return "#timestamp [ns],filename\n" + dataRows(frames);
}

/** A synthetic EuRoC sequence with `n` stereo pairs in `root/mav0`, and a
 * ground-truth CSV `root/gt.csv` whose row i is 1 ms after image i and moves
 * x by 0.01 m per frame. */
std::string writeSequence(const std::string& root, int n)
{
    std::string mav0 = root + "/mav0";
    for (int cam = 0; cam < 2; cam++)
    {
        const std::string dir = mav0 + "/cam" + std::to_string(cam);
        fs::create_directories(dir + "/data");
        writeFile(dir + "/sensor.yaml", sensorYaml(cam, W, H));
        std::string csv = "#timestamp [ns],filename\r\n";  // CRLF as in the ASL files
        for (int i = 0; i < n; i++)
        {
            const std::string ts = std::to_string(T0 + i * DT);
            csv += ts + "," + ts + ".png\r\n";
            cv::imwrite(imagePath(mav0, cam, i), cv::Mat(H, W, CV_8UC1, cv::Scalar(10 * i + cam)));
        }
        writeFile(dir + "/data.csv", csv);
    }
    std::string gt = "#timestamp_ns,x,y,z,qx,qy,qz,qw\n";
    for (int i = 0; i < n; i++)
    {
        gt += std::to_string(T0 + i * DT + 1'000'000) + ".0000000000," + std::to_string(0.01 * i) +
              ",2,3,0,0,0.7071067811865476,0.7071067811865476\n";
    }
    writeFile(root + "/gt.csv", gt);
    return mav0;
}
}  // namespace

TEST(EurocSequence, readsRealV101Excerpt)
{
    EMSLAM_REQUIRE_TEST_DATA(mav0, "euroc-v101-rest/mav0");
    EMSLAM_REQUIRE_TEST_DATA(gt, "euroc-v101-rest/groundtruth_left_cam.csv");
    EurocSequence s(mav0, gt);
    ASSERT_EQ(s.size(), 40U);
    EXPECT_EQ(s.unpairedCount(), 0U);
    EXPECT_EQ(s.imageWidth(), 752U);
    EXPECT_EQ(s.imageHeight(), 480U);
    EXPECT_NEAR(emslam::stereo::baselineOf(s.calibration()), 0.110, 0.002);
    EXPECT_EQ(s.timestampNs(0), 1403715274312143104);
    ASSERT_TRUE(s.hasGroundTruth());
    EXPECT_EQ(s.framesWithoutGroundTruth(), 0U);
    const auto T0_gt = s.groundTruth(0);
    ASSERT_TRUE(T0_gt.has_value());
    EXPECT_NEAR(T0_gt->x(), 0.8687393558, 1e-9);
    // The camera is at rest: under 3 mm of motion over the excerpt.
    EXPECT_LT((*s.groundTruth(39) - *T0_gt).translation().norm(), 0.003);

    const auto f = s.frame(39);
    EXPECT_TRUE(f.obs->hasImageRight);
    EXPECT_EQ(f.obs->imageLeft.getWidth(), 752U);
    EXPECT_EQ(f.obs->imageRight.getHeight(), 480U);
    EXPECT_FALSE(f.obs->areImagesRectified());  // raw, distorted images
    EXPECT_NEAR(f.obs->leftCamera.fx(), 458.654, 1e-9);
    EXPECT_NE(f.obs->leftCamera.dist[0], 0.0);
    EXPECT_DOUBLE_EQ(f.t, 1e-9 * static_cast<double>(s.timestampNs(39)));
    ASSERT_TRUE(f.ground_truth.has_value());

    // mav0's parent folder works too.
    EurocSequence p(fs::path(mav0).parent_path().string());
    EXPECT_EQ(p.size(), 40U);
    EXPECT_FALSE(p.hasGroundTruth());
    EXPECT_FALSE(p.frame(0).ground_truth.has_value());
}

TEST(EurocSequence, readsSyntheticSequenceWithExactTimestamps)
{
    const std::string root = emslam::test::makeTempDir("euroc_ok");
    const std::string mav0 = writeSequence(root, 4);
    EurocSequence s;
    s.sensor_label = "VI";
    s.open(mav0, root + "/gt.csv");
    ASSERT_EQ(s.size(), 4U);
    EXPECT_NEAR(emslam::stereo::baselineOf(s.calibration()), 0.11, 1e-9);
    const auto f = s.frame(2);
    EXPECT_EQ(f.obs->sensorLabel, "VI");
    EXPECT_TRUE(f.obs->hasImageRight);
    EXPECT_EQ(
        f.obs->imageLeft.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY).at<std::uint8_t>(3, 4), 20);
    EXPECT_EQ(
        f.obs->imageRight.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY).at<std::uint8_t>(3, 4), 21);
    // Exact conversion to MRPT's 100 ns ticks (a double would be off).
    const auto ticks = (f.obs->timestamp - mrpt::Clock::fromDouble(0.0)).count();
    EXPECT_EQ(ticks, (T0 + 2 * DT + 50) / 100);
    // GT 1 ms away from the image: associated; quaternion (qx,qy,qz,qw) order.
    ASSERT_TRUE(f.ground_truth.has_value());
    EXPECT_NEAR(f.ground_truth->x(), 0.02, 1e-12);
    EXPECT_NEAR(f.ground_truth->yaw(), M_PI / 2, 1e-9);
    EXPECT_EQ(s.framesWithoutGroundTruth(), 0U);
}

TEST(EurocSequence, groundTruthAssociationTolerance)
{
    const std::string root = emslam::test::makeTempDir("euroc_gt");
    const std::string mav0 = writeSequence(root, 4);
    // Rows: frame 0 exact, frame 1 +4.9 ms, frame 2 -6 ms (too far), frame 3 none.
    const std::string q = ",0,0,0,0,0,0,1\n";
    writeFile(
        root + "/gt2.csv", std::to_string(T0) + q + std::to_string(T0 + DT + 4'900'000) + q +
                               std::to_string(T0 + 2 * DT - 6'000'000) + q);
    EurocSequence s(mav0, root + "/gt2.csv");
    EXPECT_TRUE(s.groundTruth(0).has_value());
    EXPECT_TRUE(s.groundTruth(1).has_value());
    EXPECT_FALSE(s.groundTruth(2).has_value());
    EXPECT_FALSE(s.groundTruth(3).has_value());
    EXPECT_EQ(s.framesWithoutGroundTruth(), 2U);

    EurocSequence wide;
    wide.gt_max_dt = 0.007;
    wide.open(mav0, root + "/gt2.csv");
    EXPECT_EQ(wide.framesWithoutGroundTruth(), 1U);
}

TEST(EurocSequence, unpairedLeftImagesAreDropped)
{
    const std::string root = emslam::test::makeTempDir("euroc_unpaired");
    const std::string mav0 = writeSequence(root, 4);
    writeFile(mav0 + "/cam1/data.csv", dataCsv({0, 1, 3}));
    EurocSequence s(mav0);
    EXPECT_EQ(s.size(), 3U);
    EXPECT_EQ(s.unpairedCount(), 1U);
    EXPECT_EQ(s.timestampNs(2), T0 + 3 * DT);
}

// Pairing is by equal stamps in both directions: a right image without a left
// partner is dropped and counted too (it was not counted), and each image is
// paired with its own partner, not a neighbour's.
TEST(EurocSequence, camerasWithDifferentStampsArePairedByStamp)
{
    const std::string root = emslam::test::makeTempDir("euroc_mismatch");
    const std::string mav0 = writeSequence(root, 6);
    writeFile(mav0 + "/cam0/data.csv", dataCsv({0, 1, 2, 4, 5}));
    writeFile(mav0 + "/cam1/data.csv", dataCsv({1, 2, 3, 4}));
    EurocSequence s(mav0);
    ASSERT_EQ(s.size(), 3U);           // frames 1, 2, 4
    EXPECT_EQ(s.unpairedCount(), 3U);  // left 0 and 5, right 3
    for (std::size_t k = 0; k < 3; k++)
    {
        const int i = std::array{1, 2, 4}[k];
        EXPECT_EQ(s.timestampNs(k), T0 + i * DT);
        EXPECT_EQ(s.leftImageFile(k), imagePath(mav0, 0, i));
        EXPECT_EQ(s.rightImageFile(k), imagePath(mav0, 1, i));
    }
    EXPECT_EQ(
        s.frame(2).obs->imageRight.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY).at<std::uint8_t>(0, 0),
        41);
}

// A repeated stamp in cam0 paired that line's left image with cam1's image of
// the first occurrence, and time went backwards in the rawlog.
TEST(EurocSequence, repeatedStampIsRefused)
{
    const std::string root = emslam::test::makeTempDir("euroc_dup");
    const std::string mav0 = writeSequence(root, 4);
    const std::string csv = mav0 + "/cam0/data.csv";
    writeFile(csv, dataCsv({0, 1, 2}) + std::to_string(T0 + 2 * DT) + ",x.png\n");
    expectThrowContaining(
        [&] { EurocSequence s(mav0); },
        {csv + ":5: timestamp '" + std::to_string(T0 + 2 * DT) +
         "' repeats the previous one (line 4): timestamps must increase strictly"});
    // In cam1 as well (the last one used to win silently).
    writeFile(csv, dataCsv({0, 1, 2, 3}));
    writeFile(mav0 + "/cam1/data.csv", dataCsv({0, 0, 1}));
    expectThrowContaining(
        [&] { EurocSequence s(mav0); }, {mav0 + "/cam1/data.csv:3:", "repeats the previous one"});
}

TEST(EurocSequence, stampGoingBackwardsIsRefused)
{
    const std::string root = emslam::test::makeTempDir("euroc_back");
    const std::string mav0 = writeSequence(root, 4);
    const std::string csv = mav0 + "/cam0/data.csv";
    // Frame 0 again after frame 2 (and a comment line in between).
    writeFile(csv, dataCsv({0, 1, 2}) + "# resumed\n" + std::to_string(T0) + ",y.png\n");
    expectThrowContaining(
        [&] { EurocSequence s(mav0); },
        {csv + ":6: timestamp '" + std::to_string(T0) + "' is before the previous one '" +
         std::to_string(T0 + 2 * DT) + "' (line 4): timestamps must increase strictly"});
}

TEST(EurocSequence, zeroOrAbsurdStampInTheMiddleIsRefused)
{
    const std::string root = emslam::test::makeTempDir("euroc_absurd");
    const std::string mav0 = writeSequence(root, 4);
    const std::string csv = mav0 + "/cam0/data.csv";
    const std::string range =
        "is not a plausible time: expected nanoseconds since 1970-01-01 UTC in [100, "
        "4102444800000000000] (MRPT reads 0 as \"no time\"; the upper bound is 2100-01-01)";
    for (const std::string bad :
         {"0", "0.000", "99", "9223372036854775807", "4102444800000000001", "9223372036854775808",
          "-1"})
    {
        writeFile(csv, dataCsv({0, 1}) + bad + ",z.png\n" + dataRows({3}));
        expectThrowContaining(
            [&] { EurocSequence s(mav0); }, {csv + ":4: timestamp '" + bad + "' " + range});
    }
    // The bounds themselves are plausible.
    writeFile(csv, "100,a.png\n4102444800000000000,b.png\n");
    writeFile(mav0 + "/cam1/data.csv", "100,a.png\n4102444800000000000,b.png\n");
    expectThrowContaining([&] { EurocSequence s(mav0); }, {mav0 + "/cam0/data/a.png", "missing"});
}

// 1403636579763555584.5 was truncated to ...584 without a word.
TEST(EurocSequence, fractionalNanosecondIsRefused)
{
    const std::string root = emslam::test::makeTempDir("euroc_fraction");
    const std::string mav0 = writeSequence(root, 4);
    const std::string csv = mav0 + "/cam0/data.csv";
    writeFile(csv, dataCsv({0}) + "1403715274362143104.5,a.png\n");
    expectThrowContaining(
        [&] { EurocSequence s(mav0); },
        {csv + ":3: timestamp '1403715274362143104.5' has a fraction of a nanosecond: expected "
               "whole nanoseconds (a '.000' fraction is allowed)"});
    writeFile(csv, dataCsv({0}) + "1403715274362143104.0000000001,a.png\n");
    expectThrowContaining([&] { EurocSequence s(mav0); }, {csv + ":3:", "fraction"});
    // A fraction of zeros is allowed (the ASL ground-truth files write one).
    writeFile(csv, std::to_string(T0) + ".0000000000," + std::to_string(T0) + ".png\n");
    EurocSequence s(mav0);
    EXPECT_EQ(s.size(), 1U);
    EXPECT_EQ(s.timestampNs(0), T0);
    // Garbage after the dot is not a number at all.
    writeFile(csv, std::to_string(T0) + ".5x,a.png\n");
    expectThrowContaining(
        [&] { EurocSequence t(mav0); }, {csv + ":1: timestamp '" + std::to_string(T0) +
                                         ".5x' is not an integer number of nanoseconds"});
}

TEST(EurocSequence, missingFolderThrows)
{
    const std::string root = emslam::test::makeTempDir("euroc_missing");
    expectThrowContaining([&] { EurocSequence s(root + "/nope"); }, {root + "/nope"});
    const std::string mav0 = writeSequence(root, 2);
    fs::remove_all(mav0 + "/cam1");
    expectThrowContaining([&] { EurocSequence s(mav0); }, {"cam1"});
}

TEST(EurocSequence, badCalibrationThrows)
{
    const std::string root = emslam::test::makeTempDir("euroc_calib");
    const std::string mav0 = writeSequence(root, 2);
    const std::string yaml = mav0 + "/cam1/sensor.yaml";
    std::string text = sensorYaml(1, W, H);
    writeFile(yaml, text.substr(0, text.find("intrinsics:")));  // key missing
    expectThrowContaining([&] { EurocSequence s(mav0); }, {yaml, "intrinsics"});
    writeFile(yaml, text.replace(text.find("[30.0"), 5, "[abc"));  // garbled number
    expectThrowContaining([&] { EurocSequence s(mav0); }, {yaml});
    // Image size differs from the calibration's resolution.
    writeFile(mav0 + "/cam0/sensor.yaml", sensorYaml(0, W + 8, H));
    writeFile(yaml, sensorYaml(1, W + 8, H));
    expectThrowContaining([&] { EurocSequence s(mav0); }, {"resolution", imagePath(mav0, 0, 0)});
}

TEST(EurocSequence, badImagesThrow)
{
    const std::string root = emslam::test::makeTempDir("euroc_images");
    const std::string mav0 = writeSequence(root, 3);
    cv::imwrite(imagePath(mav0, 1, 2), cv::Mat(H - 1, W, CV_8UC1, cv::Scalar(1)));
    writeFile(imagePath(mav0, 0, 1), "garbage, not a png");
    EurocSequence s(mav0);
    expectThrowContaining([&] { s.frame(1); }, {imagePath(mav0, 0, 1), "Cannot read"});
    expectThrowContaining([&] { s.frame(2); }, {imagePath(mav0, 1, 2), "mismatch"});
    // First pair of different sizes: open() fails.
    cv::imwrite(imagePath(mav0, 1, 0), cv::Mat(H, W - 2, CV_8UC1, cv::Scalar(1)));
    expectThrowContaining([&] { EurocSequence t(mav0); }, {"mismatch", imagePath(mav0, 1, 0)});
    fs::remove(imagePath(mav0, 1, 0));
    expectThrowContaining([&] { EurocSequence t(mav0); }, {imagePath(mav0, 1, 0), "missing"});
}

// The first pair is checked against the calibration from the headers: a huge
// image is not decoded (it was, 900 MB for this one, before the size check).
TEST(EurocSequence, hugeImageIsRefusedFromItsHeader)
{
    const std::string root = emslam::test::makeTempDir("euroc_huge");
    const std::string mav0 = writeSequence(root, 2);
    emslam::test::writePngDeclaring(imagePath(mav0, 1, 0), 30000, 30000);
    expectThrowContaining(
        [&] { EurocSequence s(mav0); },
        {"Image '" + imagePath(mav0, 1, 0) +
         "' is 30000x30000 (PNG header): over the limit of 67108864 pixels (8192x8192) and "
         "65535 per side; not decoded"});
    emslam::test::writePngDeclaring(imagePath(mav0, 1, 0), 4000, 3000);
    emslam::test::writePngDeclaring(imagePath(mav0, 0, 0), 4000, 3000);
    expectThrowContaining(
        [&] { EurocSequence s(mav0); }, {"Image size 4000x3000", "calibration's resolution 32x20"});
}

TEST(EurocSequence, badListsThrow)
{
    const std::string root = emslam::test::makeTempDir("euroc_lists");
    const std::string mav0 = writeSequence(root, 2);
    writeFile(mav0 + "/cam0/data.csv", "#timestamp [ns],filename\n12x4,a.png\n");
    expectThrowContaining([&] { EurocSequence s(mav0); }, {mav0 + "/cam0/data.csv:2"});
    writeFile(mav0 + "/cam0/data.csv", "#timestamp [ns],filename\n");
    expectThrowContaining([&] { EurocSequence s(mav0); }, {"no image"});
    writeFile(mav0 + "/cam0/data.csv", std::to_string(T0 + 1) + ",1.png\n");
    expectThrowContaining([&] { EurocSequence s(mav0); }, {"cam1/data.csv"});
}

TEST(EurocSequence, badGroundTruthThrows)
{
    const std::string root = emslam::test::makeTempDir("euroc_badgt");
    const std::string mav0 = writeSequence(root, 2);
    const std::string gt = root + "/bad.csv";
    writeFile(gt, std::to_string(T0) + ",1,2,3,0,0,0\n");
    expectThrowContaining([&] { EurocSequence s(mav0, gt); }, {gt + ":1", "8 fields"});
    writeFile(gt, "# header\n" + std::to_string(T0) + ",1,2,x,0,0,0,1\n");
    expectThrowContaining([&] { EurocSequence s(mav0, gt); }, {gt + ":2"});
    writeFile(gt, std::to_string(T0) + ",0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0\n");
    expectThrowContaining([&] { EurocSequence s(mav0, gt); }, {"state_groundtruth_estimate0"});
    writeFile(gt, std::to_string(T0) + ",0,0,0,0,0,0,0\n");
    expectThrowContaining([&] { EurocSequence s(mav0, gt); }, {"zero quaternion"});
    expectThrowContaining([&] { EurocSequence s(mav0, root + "/none.csv"); }, {"none.csv"});
}

// INT64_MIN stamps made fromNs() and |t_image - t_gt| overflow (undefined
// behaviour, garbage times, exit 0): now they are refused, naming file and line.
TEST(EurocSequence, timestampsOutsideTheNanosecondRangeAreRefused)
{
    const std::string root = emslam::test::makeTempDir("euroc_int64");
    const std::string mav0 = writeSequence(root, 2);
    const std::string csv = mav0 + "/cam0/data.csv";
    const std::string png = std::to_string(T0) + ".png";
    for (const std::string bad : {"-9223372036854775808", "-1", "9223372036854775808"})
    {
        writeFile(csv, "#timestamp [ns],filename\n" + bad + "," + png + "\n");
        expectThrowContaining(
            [&] { EurocSequence s(mav0); }, {csv + ":2", "'" + bad + "'", "nanoseconds"});
    }
    const std::string gt = root + "/bad_gt.csv";
    writeFile(gt, "-9223372036854775808,1,2,3,0,0,0,1\n");
    writeSequence(root, 2);
    expectThrowContaining(
        [&] { EurocSequence s(mav0, gt); }, {gt + ":1", "'-9223372036854775808'", "nanoseconds"});
}

// The latest plausible stamp (2100-01-01) is converted exactly; ground-truth
// rows at both ends of the int64 range cause no overflow.
TEST(EurocSequence, latestPlausibleTimestampIsConvertedExactly)
{
    constexpr std::int64_t MAX_NS = std::numeric_limits<std::int64_t>::max();
    const std::string root = emslam::test::makeTempDir("euroc_max_stamp");
    const std::string mav0 = writeSequence(root, 2);
    for (int cam = 0; cam < 2; cam++)
    {
        writeFile(
            mav0 + "/cam" + std::to_string(cam) + "/data.csv",
            std::to_string(T0) + "," + std::to_string(T0) + ".png\n" +
                std::to_string(emslam::io::MAX_STAMP_NS) + "," + std::to_string(T0 + DT) +
                ".png\n");
    }
    // Ground truth at both ends of the range: neither is within 5 ms of an image.
    const std::string gt = root + "/far_gt.csv";
    writeFile(gt, "0,1,2,3,0,0,0,1\n" + std::to_string(MAX_NS - 10'000'000) + ",1,2,3,0,0,0,1\n");
    EurocSequence s(mav0, gt);
    ASSERT_EQ(s.size(), 2U);
    EXPECT_EQ(s.timestampNs(1), 4'102'444'800'000'000'000);
    EXPECT_EQ(s.framesWithoutGroundTruth(), 2U);
    const auto f = s.frame(1);
    EXPECT_EQ((f.obs->timestamp - mrpt::Clock::fromDouble(0.0)).count(), 41'024'448'000'000'000);
}
