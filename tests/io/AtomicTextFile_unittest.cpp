// SPDX-License-Identifier: BSD-3-Clause
// Atomic outputs on a full disk, for real and without root: the `.partial`
// file a writer goes through is made a symbolic link to /dev/full (ENOSPC on
// every write); the outputs themselves are ordinary paths, as the apps see
// them. Each error names the output and the OS reason, and leaves nothing
// under the output's name.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/AtomicFile.h>
#include <emslam/io/AtomicTextFile.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using emslam::test::expectThrowContaining;

TEST(AtomicTextFile, fullDiskNamesTheFileAndTheReason)
{
    const std::string file = emslam::test::fileOnFullDisk("atomic_text_full", "summary.json");
    {
        emslam::io::AtomicTextFile f(file);
        f.stream() << "{\"frames\": 60}\n";
        expectThrowContaining(
            [&] { f.commit(); }, {"cannot write '" + file + "': No space left on device"});
    }
    EXPECT_FALSE(fs::exists(file));
    EXPECT_FALSE(fs::is_symlink(emslam::io::partialFileFor(file)));
}
