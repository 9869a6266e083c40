// SPDX-License-Identifier: BSD-3-Clause
// writeFileAtomically() on a full disk, for real and without root: the `.partial`
// file a writer goes through is made a symbolic link to /dev/full (ENOSPC on
// every write); the outputs themselves are ordinary paths, as the apps see
// them. Each error names the output and the OS reason, and leaves nothing
// under the output's name.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/AtomicFile.h>

#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using emslam::test::expectThrowContaining;

TEST(AtomicFile, aWriterThatSaysOnlyFalseGetsErrnoAsTheReason)
{
    const std::string file = emslam::test::fileOnFullDisk("atomic_full", "map_top.png");
    expectThrowContaining(
        [&]
        {
            emslam::io::writeFileAtomically(
                file,
                [](const std::string& partial)
                {
                    const int fd = ::open(partial.c_str(), O_WRONLY | O_TRUNC);
                    const bool ok = fd >= 0 && ::write(fd, "png", 3) == 3;
                    const int err = errno;
                    ::close(fd);
                    errno = err;
                    return ok;
                });
        },
        {"cannot write '" + file + "': No space left on device"});
    EXPECT_FALSE(fs::exists(file));
}
