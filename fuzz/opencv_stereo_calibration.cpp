// SPDX-License-Identifier: BSD-3-Clause
// OpenCV stereo calibration files (cv::FileStorage YAML, XML or JSON): the
// pre-checks that keep OpenCV's parser away from what makes it recurse or
// hang, then the reader, with the input as one file and as the second
// (extrinsics) file of a valid first one.
#include "FuzzFile.h"

#include <emslam/io/OpenCvStereoCalibration.h>
#include <emslam/stereo/StereoCalibration.h>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

namespace
{
const char* const INTRINSICS =
    "%YAML:1.0\nM1: [400, 0, 320, 0, 400, 240, 0, 0, 1]\nM2: [400, 0, 320, 0, 400, 240, 0, 0, "
    "1]\nD1: []\nD2: []\n";

void load(const std::string& file, const std::string& extrinsics)
{
    try
    {
        const auto cam = emslam::io::loadOpenCvStereoCalibration(file, extrinsics, 1.0);
        if (cam.leftCamera.ncols > 0)
        {
            emslam::stereo::validateStereoCamera(cam, "fuzz");
        }
    }
    catch (const std::exception&)
    {
        // A clean error is the expected outcome of a bad file.
    }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto text = emslam::fuzz::asText(data, size);
    const auto& folder = emslam::fuzz::FuzzFolder::instance();
    // The extension picks cv::FileStorage's parser: YAML, then XML and JSON.
    for (const char* name : {"calib.yml", "calib.xml", "calib.json"})
    {
        load(folder.write(name, text), "");
    }
    load(folder.write("intrinsics.yml", INTRINSICS), folder.write("calib.yml", text));
    return 0;
}
