// SPDX-License-Identifier: BSD-3-Clause
// An output never overwrites an input, whatever name or link leads to it.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/InputOutputClash.h>

#include <gtest/gtest.h>

#include <filesystem>

namespace fs = std::filesystem;
using emslam::io::filesOfOutputFolder;
using emslam::io::requireOutputsAreNotInputs;
using emslam::test::expectThrowContaining;

TEST(InputOutputClash, sameNameIsRefusedNamingBoth)
{
    const std::string dir = emslam::test::makeTempDir("clash_same");
    emslam::test::writeFile(dir + "/W.ini", "[World]\n");
    expectThrowContaining(
        [&]
        {
            requireOutputsAreNotInputs(
                {{"output rawlog", dir + "/W.ini"}}, {{"the world file", dir + "/W.ini"}});
        },
        {"output rawlog '" + dir + "/W.ini' is the world file '" + dir + "/W.ini'",
         "refusing to overwrite an input"});
}

TEST(InputOutputClash, otherSpellingsLinksAndHardLinksAreTheSameFile)
{
    const std::string dir = emslam::test::makeTempDir("clash_links");
    emslam::test::writeFile(dir + "/gt.tum", "0 0 0 0 0 0 0 1\n");
    fs::create_directory(dir + "/sub");
    fs::create_symlink(dir + "/gt.tum", dir + "/link.tum");
    fs::create_hard_link(dir + "/gt.tum", dir + "/hard.tum");
    const std::vector<emslam::io::RolePath> in{{"ground truth", dir + "/gt.tum"}};
    for (const std::string& out :
         {dir + "/sub/../gt.tum", dir + "/./gt.tum", dir + "/link.tum", dir + "/hard.tum"})
    {
        EXPECT_THROW(requireOutputsAreNotInputs({{"--gt-out", out}}, in), std::invalid_argument)
            << out;
    }
}

TEST(InputOutputClash, distinctFilesAndEmptyPathsPass)
{
    const std::string dir = emslam::test::makeTempDir("clash_ok");
    emslam::test::writeFile(dir + "/a.tum", "x\n");
    emslam::test::writeFile(dir + "/b.tum", "x\n");  // same content, other file
    EXPECT_NO_THROW(requireOutputsAreNotInputs(
        {{"output", dir + "/b.tum"}, {"new output", dir + "/c.tum"}, {"unused", ""}},
        {{"input", dir + "/a.tum"}, {"no input", ""}}));
}

TEST(InputOutputClash, filesOfAnOutputFolderAreCheckedOneByOne)
{
    const std::string dir = emslam::test::makeTempDir("clash_folder");
    emslam::test::writeFile(dir + "/trajectory.tum", "x\n");
    const auto outs = filesOfOutputFolder(dir, {"summary.json", "trajectory.tum"}, "output");
    ASSERT_EQ(outs.size(), 2u);
    EXPECT_EQ(outs[1].path, dir + "/trajectory.tum");
    expectThrowContaining(
        [&] {
            requireOutputsAreNotInputs(
                outs, {{"the ground truth (--gt)", dir + "/trajectory.tum"}});
        },
        {"output '" + dir + "/trajectory.tum' is the ground truth (--gt)"});
}
