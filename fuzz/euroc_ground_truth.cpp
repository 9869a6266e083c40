// SPDX-License-Identifier: BSD-3-Clause
// EuRoC ground-truth CSV: EurocSequence::readGroundTruthCsv() and the
// evaluation's EurocTrajectory::load() on arbitrary text.
#include "FuzzFile.h"

#include <emslam/io/EurocSequence.h>
#include <emslam/io/EurocTrajectory.h>

#include <cstddef>
#include <cstdint>
#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto& folder = emslam::fuzz::FuzzFolder::instance();
    const std::string file = folder.write("data.csv", emslam::fuzz::asText(data, size));
    try
    {
        emslam::io::EurocSequence::readGroundTruthCsv(file);
    }
    catch (const std::exception&)
    {
        // A clean error is the expected outcome of a bad file.
    }
    try
    {
        emslam::io::EurocTrajectory::load(file);
    }
    catch (const std::exception&)
    {
    }
    return 0;
}
