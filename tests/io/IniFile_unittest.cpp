// SPDX-License-Identifier: BSD-3-Clause
// INI files: a repeated section or key is refused naming both lines, the
// size cap holds, and "the same" is what MRPT reads as the same.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/io/IniFile.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace io = emslam::io;
namespace fs = std::filesystem;

namespace
{
/** The message requireUniqueIniEntries() throws for `text` ("" if none). */
std::string problemsOf(const std::string& text)
{
    try
    {
        io::requireUniqueIniEntries(text, "f.ini");
    }
    catch (const std::invalid_argument& e)
    {
        return e.what();
    }
    return {};
}
}  // namespace

TEST(IniFile, duplicateKeyNamesBothLines)
{
    EXPECT_EQ(
        problemsOf("[Simulation]\nfps = 10\nmax_step = 1\nfps = 20\n"),
        "f.ini:4: key 'fps' repeated in [Simulation] (first at f.ini:2)");
    // Case and blanks do not make a key different (SimpleIni's SI_NoCase).
    EXPECT_EQ(
        problemsOf("[S]\n  fps\t= 10\nFPS=20\n"),
        "f.ini:3: key 'FPS' repeated in [S] (first at f.ini:2 as 'fps'; names ignore case)");
    // Keys before any section header.
    EXPECT_EQ(
        problemsOf("a = 1\na = 2\n[S]\na = 3\n"),
        "f.ini:2: key 'a' repeated in the section before any [section] (first at f.ini:1)");
}

TEST(IniFile, repeatedSectionNamesBothLines)
{
    EXPECT_EQ(
        problemsOf("[Camera]\nfx = 1\n[World]\nseed = 2\n[ Camera ] ; again\nfy = 3\n"),
        "f.ini:5: section [Camera] repeated (first at f.ini:1)");
    // Every repetition, one per line; a key of the merged section too.
    EXPECT_EQ(
        problemsOf("[A]\nx = 1\n[a]\nx = 2\n"),
        "f.ini:3: section [a] repeated (first at f.ini:1 as [A]; names ignore case)\n"
        "f.ini:4: key 'x' repeated in [A] (first at f.ini:2)");
}

TEST(IniFile, sameKeyInOtherSectionsCommentsAndKeylessLinesAreFine)
{
    EXPECT_EQ(problemsOf("; x = 1\n# x = 1\n[A]\nx = 1\n  ; x = 2\n[B]\nx = 2\nx\n= 3\n= 4\n"), "");
    EXPECT_EQ(problemsOf(""), "");
    EXPECT_EQ(problemsOf("\xEF\xBB\xBF[A]\nx = 1\n"), "");
}

TEST(IniFile, lineNumbersAreThoseOfTheFileBeforePreprocessing)
{
    // A `\` at a line's end joins the next line; @define lines are dropped;
    // CRLF and lone CR end lines as in SimpleIni.
    EXPECT_EQ(
        problemsOf("@define N 3\n[A]\nv = [1 2 \\\n 3]\nk = ${N}\r\nk = 4\n"),
        "f.ini:6: key 'k' repeated in [A] (first at f.ini:5)");
    EXPECT_EQ(
        problemsOf("[A]\rx = 1\rx = 2\n"), "f.ini:1: key 'x' repeated in [A] (first at f.ini:1)");
    // A key produced by the preprocessor is the key MRPT sees.
    EXPECT_EQ(
        problemsOf("@define K speed\n[T]\n${K} = 1\nspeed = 2\n"),
        "f.ini:4: key 'speed' repeated in [T] (first at f.ini:3)");
}

TEST(IniFile, whatMrptMergesIsWhatIsRefused)
{
    // The oracle: MRPT keeps the last value of a repeated key.
    const std::string text = "[A]\nx = 1\n[B]\ny = 0\n[a]\nX = 2\n";
    const mrpt::config::CConfigFileMemory cfg(text);
    EXPECT_EQ(cfg.read_int("A", "x", 0), 2);
    EXPECT_NE(problemsOf(text), "");
}

TEST(IniFile, unclosedSectionAndNulByteAreRefused)
{
    EXPECT_EQ(
        problemsOf("[A]\nx = 1\n[B\nx = 2\n"),
        "f.ini:3: '[B' has no closing ']' (MRPT would file the keys after it under a garbled "
        "section name)");
    EXPECT_EQ(
        problemsOf(std::string("[A]\nx = 1\n\0\n", 11)),
        "f.ini:3: a NUL byte: not a text file (MRPT would stop reading there)");
    emslam::test::expectThrowContaining(
        [] { io::requireUniqueIniEntries("[A]\nx = ${NOPE}\n", "f.ini"); }, {"f.ini: ", "NOPE"});
}

TEST(IniFile, readIniFileChecksSizeAndEntries)
{
    const std::string dir = emslam::test::makeTempDir("ini_file");
    emslam::test::writeFile(dir + "/ok.ini", "[A]\nx = 1\n");
    EXPECT_EQ(io::readIniFile(dir + "/ok.ini", "config file"), "[A]\nx = 1\n");

    emslam::test::writeFile(dir + "/dup.ini", "[A]\nx = 1\n\nx = 2\n");
    emslam::test::expectThrowContaining(
        [&] { io::readIniFile(dir + "/dup.ini", "config file"); },
        {dir + "/dup.ini:4: key 'x' repeated in [A] (first at " + dir + "/dup.ini:2)"});

    // A sparse 2 GiB file is refused at once, before a byte is read.
    {
        std::ofstream(dir + "/huge.ini");
    }
    fs::resize_file(dir + "/huge.ini", std::uintmax_t{2} << 30);
    const auto t0 = std::chrono::steady_clock::now();
    emslam::test::expectThrowContaining(
        [&] { io::readIniFile(dir + "/huge.ini", "experiment set"); },
        {"experiment set '" + dir + "/huge.ini' is 2048.0 MiB", "at most 16.0 MiB"});
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1));
    fs::remove(dir + "/huge.ini");

    emslam::test::expectThrowContaining(
        [&] { io::readIniFile("/dev/zero", "world file"); },
        {"world file '/dev/zero'", "character device"});
    if (::geteuid() != 0)
    {
        emslam::test::writeFile(dir + "/locked.ini", "[A]\n");
        fs::permissions(dir + "/locked.ini", fs::perms::none);
        emslam::test::expectThrowContaining(
            [&] { io::readIniFile(dir + "/locked.ini", "config file"); },
            {"cannot read config file '" + dir + "/locked.ini': Permission denied"});
    }
}
