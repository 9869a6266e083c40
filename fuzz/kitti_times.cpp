// SPDX-License-Identifier: BSD-3-Clause
// KITTI times.txt: KittiTrajectory::readTimes() on arbitrary text.
#include "FuzzFile.h"

#include <emslam/io/KittiTrajectory.h>

#include <cstddef>
#include <cstdint>
#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto& folder = emslam::fuzz::FuzzFolder::instance();
    const std::string file = folder.write("times.txt", emslam::fuzz::asText(data, size));
    try
    {
        emslam::io::KittiTrajectory::readTimes(file);
    }
    catch (const std::exception&)
    {
        // A clean error is the expected outcome of a bad file.
    }
    return 0;
}
