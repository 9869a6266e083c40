// SPDX-License-Identifier: BSD-3-Clause
// Rawlog outputs on a full disk, for real and without root: the `.partial`
// file a writer goes through is made a symbolic link to /dev/full (ENOSPC on
// every write); the outputs themselves are ordinary paths, as the apps see
// them. Each error names the output and the OS reason, and leaves nothing
// under the output's name.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/RawlogOutput.h>

#include <mrpt/obs/CObservationOdometry.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using emslam::test::expectThrowContaining;

TEST(RawlogOutput, fullDiskNamesTheRawlogAndTheReason)
{
    const std::string file = emslam::test::fileOnFullDisk("rawlog_full", "sim.rawlog");
    {
        emslam::io::RawlogOutput out(file, 1);
        out.archive() << mrpt::obs::CObservationOdometry();
        expectThrowContaining(
            [&] { out.commit(); }, {"cannot write '" + file + "': No space left on device"});
    }
    EXPECT_FALSE(fs::exists(file));
}
