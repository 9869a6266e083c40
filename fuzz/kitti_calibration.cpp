// SPDX-License-Identifier: BSD-3-Clause
// KITTI odometry calib.txt: loadKittiCalibration() on arbitrary text.
#include "FuzzFile.h"

#include <emslam/io/CalibrationFiles.h>
#include <emslam/stereo/StereoCalibration.h>

#include <cstddef>
#include <cstdint>
#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto& folder = emslam::fuzz::FuzzFolder::instance();
    const std::string file = folder.write("calib.txt", emslam::fuzz::asText(data, size));
    try
    {
        const auto cam = emslam::io::loadKittiCalibration(file, 1241, 376);
        emslam::stereo::validateStereoCamera(cam, file);
    }
    catch (const std::exception&)
    {
        // A clean error is the expected outcome of a bad file.
    }
    return 0;
}
