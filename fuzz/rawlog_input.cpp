// SPDX-License-Identifier: BSD-3-Clause
// Rawlogs, plain or gz (mutated real ones, or any bytes): RawlogInput reads
// them record by record to the end or to a clean early end, and every
// observation goes through FrameStreamGuard::check() as in the apps (its
// camera: images decoded, calibration checked).
#include "FuzzFile.h"

#include <emslam/io/FrameStreamGuard.h>
#include <emslam/io/RawlogInput.h>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto& folder = emslam::fuzz::FuzzFolder::instance();
    const std::string file = folder.write("input.rawlog", emslam::fuzz::asText(data, size));
    try
    {
        emslam::io::RawlogInput in(file);
        emslam::io::FrameStreamGuard guard;
        std::vector<mrpt::obs::CObservation::Ptr> batch;
        while (in.next(batch))
        {
            for (const auto& o : batch)
            {
                if (guard.check(*o, in.recordsRead() - 1).verdict ==
                    emslam::io::FrameStreamGuard::Verdict::Use)
                {
                    guard.accept();
                }
            }
            (void)in.fractionRead();
        }
        (void)guard.cameraChangeWarning();
        (void)guard.skippedText();
    }
    catch (const std::exception&)
    {
        // A clean error is the expected outcome of a bad file.
    }
    return 0;
}
