// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/EurocSensorYaml.h>

#include <gtest/gtest.h>

#include <cmath>
#include <exception>
#include <filesystem>
#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

using emslam::io::EurocSensorYaml;
using emslam::test::expectThrowContaining;
using emslam::test::writeFile;

namespace
{
// The layout of an ASL sensor.yaml: comments, a map with a list over 4 lines.
const std::string SENSOR_YAML = R"(%YAML:1.0
# General sensor definitions.
sensor_type: camera
comment: VI-Sensor cam0 (MT9M034)

T_BS:
  cols: 4
  rows: 4
  data: [0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,
         0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,
        -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,
         0.0, 0.0, 0.0, 1.0]

rate_hz: 20
resolution: [752, 480]
camera_model: pinhole
intrinsics: [458.654, 457.296, 367.215, 248.375] #fu, fv, cu, cv
distortion_model: radial-tangential
distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
)";

std::function<void()> parsing(const std::string& text)
{
    return [text]() { EurocSensorYaml::parse(text, "x/sensor.yaml"); };
}
}  // namespace

TEST(EurocSensorYaml, readsTheAslLayout)
{
    const auto y = EurocSensorYaml::parse(SENSOR_YAML, "cam0/sensor.yaml");
    EXPECT_EQ(y.text("sensor_type"), "camera");
    EXPECT_EQ(y.text("comment"), "VI-Sensor cam0 (MT9M034)");
    EXPECT_EQ(y.text("camera_model"), "pinhole");
    EXPECT_EQ(y.text("distortion_model"), "radial-tangential");
    EXPECT_EQ(y.number("rate_hz"), 20.0);
    EXPECT_TRUE(y.isMap("T_BS"));
    EXPECT_EQ(y.number("T_BS.cols"), 4.0);
    EXPECT_EQ(y.number("T_BS.rows"), 4.0);
    const auto m = y.numbers("T_BS.data", {16});
    EXPECT_EQ(m[0], 0.0148655429818);
    EXPECT_EQ(m[8], -0.0257744366974);
    EXPECT_EQ(m[15], 1.0);
    EXPECT_EQ(y.lineOf("T_BS.data"), 9u);
    EXPECT_EQ(y.numbers("resolution", {2}), (std::vector<double>{752, 480}));
    EXPECT_EQ(
        y.numbers("intrinsics", {4}), (std::vector<double>{458.654, 457.296, 367.215, 248.375}));
    EXPECT_EQ(y.numbers("distortion_coefficients", {4, 5})[3], 1.76187114e-05);
    EXPECT_FALSE(y.has("T_BS.nope"));
    EXPECT_FALSE(y.has("cols"));  // map entries only under their map's name
}

TEST(EurocSensorYaml, toleratesCrlfQuotesAndNoDirective)
{
    const auto y = EurocSensorYaml::parse(
        "sensor_type: \"camera\"\r\nresolution: [ 752 ,480 ]  # w, h\r\nempty: []\r\n", "f");
    EXPECT_EQ(y.text("sensor_type"), "camera");
    EXPECT_EQ(y.numbers("resolution", {2}), (std::vector<double>{752, 480}));
    EXPECT_TRUE(y.numbers("empty", {0}).empty());
}

// The real files give bit-identical numbers to OpenCV's YAML reader, which the
// calibration used before: the imported calibration is unchanged.
TEST(EurocSensorYaml, sameNumbersAsOpenCvOnTheRealFiles)
{
    EMSLAM_REQUIRE_TEST_DATA(cam0, "euroc-v101-rest/mav0/cam0/sensor.yaml");
    EMSLAM_REQUIRE_TEST_DATA(cam1, "euroc-v101-rest/mav0/cam1/sensor.yaml");
    for (const auto& file : {cam0, cam1})
    {
        const auto y = EurocSensorYaml::load(file);
        const cv::FileStorage fs(file, cv::FileStorage::READ);
        ASSERT_TRUE(fs.isOpened()) << file;
        const auto expectSame = [&](const cv::FileNode& node, const std::string& key, std::size_t n)
        {
            const auto ours = y.numbers(key, {n});
            ASSERT_EQ(node.size(), n) << key;
            for (std::size_t i = 0; i < n; ++i)
            {
                EXPECT_EQ(ours[i], node[static_cast<int>(i)].real()) << file << " " << key << i;
            }
        };
        expectSame(fs["resolution"], "resolution", 2);
        expectSame(fs["intrinsics"], "intrinsics", 4);
        expectSame(fs["distortion_coefficients"], "distortion_coefficients", 4);
        expectSame(fs["T_BS"]["data"], "T_BS.data", 16);
        EXPECT_EQ(y.text("distortion_model"), fs["distortion_model"].string());
        EXPECT_EQ(y.text("camera_model"), fs["camera_model"].string());
        EXPECT_EQ(y.text("sensor_type"), fs["sensor_type"].string());
    }
}

// OpenCV 4.6 never returns from this 24-byte file; here it is an error at line 3.
TEST(EurocSensorYaml, openCvHangReproducerIsAnError)
{
    const std::string dir = emslam::test::makeTempDir("yaml_hang");
    writeFile(dir + "/sensor.yaml", "%YAML:1.0\n\n a: 8\nra -1]\n");
    expectThrowContaining(
        [&]() { EurocSensorYaml::load(dir + "/sensor.yaml"); },
        {dir + "/sensor.yaml", "line 3", "'a'", "indented key outside a map"});
    expectThrowContaining(
        parsing("%YAML:1.0\na: 8\nra -1]\n"), {"line 3", "expected 'key: value'"});
}

// 100,000 nested '[' overflow OpenCV's recursive parser; here: one line, one error.
TEST(EurocSensorYaml, deepNestingIsAnErrorNotAStackOverflow)
{
    const std::string dir = emslam::test::makeTempDir("yaml_nesting");
    writeFile(dir + "/sensor.yaml", "%YAML:1.0\ndata: " + std::string(100000, '[') + "\n");
    expectThrowContaining(
        [&]() { EurocSensorYaml::load(dir + "/sensor.yaml"); },
        {dir + "/sensor.yaml", "line 2", "'data'", "nested"});
    writeFile(dir + "/bare.yaml", std::string(100000, '['));
    expectThrowContaining(
        [&]() { EurocSensorYaml::load(dir + "/bare.yaml"); }, {"line 1", "expected 'key: value'"});
}

TEST(EurocSensorYaml, malformedTextNamesLineAndKey)
{
    expectThrowContaining(
        parsing("a: 1\nb: [1, 2\nc: 3\n"), {"x/sensor.yaml", "line 2", "'b'", "not closed"});
    expectThrowContaining(
        parsing("a: [1,\n 2\nc: 3\n"), {"line 1", "'a'", "not closed", "before line 3"});
    expectThrowContaining(parsing("a: [1,\n 2\n"), {"line 1", "'a'", "end of the file"});
    expectThrowContaining(parsing("a: 1\na: 2\n"), {"line 2", "'a'", "duplicate", "line 1"});
    expectThrowContaining(parsing("m:\n  n:\n    o: 1\n"), {"line 2", "'m.n'", "deeper"});
    expectThrowContaining(parsing("a: [1, 2] x\n"), {"line 1", "'a'", "after ']'"});
    expectThrowContaining(parsing("a: [1, , 2]\n"), {"line 1", "'a'", "empty list element"});
    expectThrowContaining(parsing("a: [[1]]\n"), {"line 1", "'a'", "nested"});
    expectThrowContaining(parsing("a: {b: 1}\n"), {"line 1", "'a'", "unsupported"});
    expectThrowContaining(parsing("m:\n\tb: 1\n"), {"line 2", "tab"});
    expectThrowContaining(parsing("a:1\n"), {"line 1", "expected 'key: value'"});
    expectThrowContaining(parsing("a: 1\n\x01\x02\xff garbage\n"), {"line 2", "control character"});
    expectThrowContaining(parsing(std::string("a: 1\0b", 6)), {"line 1", "control character"});
    expectThrowContaining(parsing("# only a comment\n\n"), {"x/sensor.yaml", "no 'key: value'"});
}

// A 100,000-character line was echoed whole into the message; now its first
// 60 bytes, "…" and its length.
TEST(EurocSensorYaml, longLinesAreCutInMessages)
{
    const std::string filler(100000, 'x');
    const std::string cut = std::string(60, 'x') + "\u2026'";
    const auto expectShort =
        [](const std::function<void()>& fn, std::initializer_list<std::string> parts)
    {
        expectThrowContaining(fn, parts);
        try
        {
            fn();
        }
        catch (const std::exception& e)
        {
            EXPECT_LT(std::string(e.what()).size(), 200U) << e.what();
        }
    };
    expectShort(
        parsing("a: 1\n" + filler + "\n"),
        {"line 2", "expected 'key: value', got '" + cut + " (100000 bytes)"});
    expectShort(
        parsing("comment: {" + filler + "\n"),
        {"line 1", "unsupported YAML value '{" + std::string(59, 'x') + "\u2026' (100001 bytes)"});
    expectShort(parsing("a: [1] " + filler + "\n"), {"line 1", "unexpected '" + cut});
    expectShort(
        parsing(filler + ": 1\n" + filler + ": 2\n"), {"line 2", "key '" + cut, "duplicate"});
    const auto y = EurocSensorYaml::parse("a: [" + filler + "]\nb: " + filler + "\n", "f.yaml");
    expectShort([&]() { y.numbers("a", {1}); }, {"line 1", "element 0 '" + cut, "not a number"});
    expectShort([&]() { y.number("b"); }, {"line 2", "'" + cut, "not a finite number"});
}

TEST(EurocSensorYaml, valuesOfTheWrongKindNameLineAndKey)
{
    const auto y = EurocSensorYaml::parse(
        "a: [1, x]\nb: [1, inf]\nc: [1, 2, 3]\nd: abc\nm:\n  k: 1\n", "f.yaml");
    expectThrowContaining(
        [&]() { y.numbers("a", {2}); }, {"f.yaml", "line 1", "'a'", "'x' is not a number"});
    expectThrowContaining([&]() { y.numbers("b", {2}); }, {"line 2", "'b'", "not finite"});
    expectThrowContaining(
        [&]() {
            y.numbers("c", {2, 4});
        },
        {"line 3", "'c'", "3 numbers, expected 2 or 4"});
    expectThrowContaining([&]() { y.numbers("d", {1}); }, {"line 4", "'d'", "not a list"});
    expectThrowContaining([&]() { y.number("d"); }, {"line 4", "'d'", "not a finite number"});
    expectThrowContaining([&]() { y.text("a"); }, {"line 1", "'a'", "a list"});
    expectThrowContaining([&]() { y.text("m"); }, {"line 5", "'m'", "a map"});
    expectThrowContaining([&]() { y.text("zz"); }, {"f.yaml", "missing key 'zz'"});
    EXPECT_EQ(y.number("m.k"), 1.0);
}

TEST(EurocSensorYaml, refusesFilesThatAreNotSmallRegularFiles)
{
    const std::string dir = emslam::test::makeTempDir("yaml_files");
    expectThrowContaining(
        [&]() { EurocSensorYaml::load(dir + "/none.yaml"); }, {dir + "/none.yaml", "not found"});
    expectThrowContaining([&]() { EurocSensorYaml::load(dir); }, {dir, "not a regular file"});
    if (std::filesystem::exists("/dev/zero"))
    {
        expectThrowContaining(
            []() { EurocSensorYaml::load("/dev/zero"); }, {"/dev/zero", "not a regular file"});
    }
    writeFile(dir + "/empty.yaml", "");
    expectThrowContaining(
        [&]() { EurocSensorYaml::load(dir + "/empty.yaml"); }, {"empty.yaml", "empty file"});
    // Comment lines only, just over the limit: refused for its size, not parsed.
    std::string big;
    while (big.size() <= EurocSensorYaml::MAX_FILE_BYTES)
    {
        big += "# padding padding padding padding padding padding padding padding\n";
    }
    writeFile(dir + "/big.yaml", "a: 1\n" + big);
    expectThrowContaining(
        [&]() { EurocSensorYaml::load(dir + "/big.yaml"); }, {"big.yaml", "larger than"});
    writeFile(dir + "/ok.yaml", SENSOR_YAML);
    EXPECT_EQ(EurocSensorYaml::load(dir + "/ok.yaml").fileName(), dir + "/ok.yaml");
}
