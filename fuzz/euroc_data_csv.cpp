// SPDX-License-Identifier: BSD-3-Clause
// EuRoC sequence image lists: EurocSequence::open() on a folder whose
// cam0/data.csv and cam1/data.csv are the input, split at a line "---"
// (without it, both cameras get the whole input): the timestamp checks
// (plausible, strictly increasing) and the pairing of the two lists by stamp,
// which run before any image is looked for.
#include "FuzzFile.h"

#include <emslam/io/EurocSequence.h>

#include <cstddef>
#include <cstdint>
#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto text = emslam::fuzz::asText(data, size);
    auto [left, right] = emslam::fuzz::splitAtLine(text, "---");
    if (right.empty())
    {
        right = left;
    }
    const auto& folder = emslam::fuzz::FuzzFolder::instance();
    folder.write("mav0/cam0/data.csv", left);
    folder.write("mav0/cam1/data.csv", right);
    try
    {
        emslam::io::EurocSequence sequence(folder.path("mav0"));
    }
    catch (const std::exception&)
    {
        // No image or sensor.yaml exists: every input ends in a clean error.
    }
    return 0;
}
