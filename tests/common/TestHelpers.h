// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

namespace emslam::test
{
/** Writes `text` to `path` as is (binary mode: a CRLF stays CRLF), replacing
 * any previous content. */
void writeFile(const std::string& path, const std::string& text);

/** Makes the `.partial` file through which emslam writes `file` (see
 * emslam::io::partialFileFor()) a symbolic link to /dev/full, whose every
 * write fails with ENOSPC: `file` is then written as on a full disk, for
 * real and without root, while `file` itself stays an ordinary path. */
void putOnFullDisk(const std::string& file);

/** `name` in a new temporary folder tagged `tag`, put on a full disk
 * (putOnFullDisk()). */
std::string fileOnFullDisk(const std::string& tag, const std::string& name);

/** Runs `fn` with stderr captured and returns what it printed (the capture
 * ends also when `fn` throws, and the exception goes on). */
std::string capturingStderr(const std::function<void()>& fn);

/** Expects `fn` to throw a `std::exception` whose what() contains every one of
 * `parts`; adds a GoogleTest failure (naming the missing part and the full
 * message) otherwise, or if `fn` does not throw at all. */
void expectThrowContaining(
    const std::function<void()>& fn, std::initializer_list<std::string> parts);

/** The largest difference between two poses: the distance between their
 * positions or the largest difference of a rotation matrix entry. */
double maxPoseDifference(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b);

/** `args` as a main() receives them (the strings must outlive the result). */
std::vector<const char*> argvOf(const std::vector<std::string>& args);

/** How a program run by interruptedRun() ended. */
struct InterruptedRun
{
    bool exited{false};  //!< exited normally (not killed by the signal)
    int exit_code{-1};
    std::string stderr_text;
    std::string stdout_text;
    double seconds_to_exit{0};  //!< from the signal to the end of the process
};

/** Runs the program `exe` with `args`, waits until its stderr or stdout
 * contains `wait_for` (or 120 s pass), sends it `signum` and waits for it to
 * end. For the apps' Ctrl-C behaviour. */
InterruptedRun interruptedRun(
    const std::string& exe,
    const std::vector<std::string>& args,
    const std::string& wait_for,
    int signum);

/** How a program run by runProgram() ended. */
struct ProgramRun
{
    int exit_code{-1};  //!< 128 + the signal if one killed it
    std::string stdout_text;
    std::string stderr_text;
};

/** Runs `exe args` to its end and returns its exit code, stdout and stderr. */
ProgramRun runProgram(const std::string& exe, const std::vector<std::string>& args);

/** Runs `exe args` with stdout a pipe whose reader is already gone (as in
 * `exe args | true`) and returns its exit code, 128 + the signal if one
 * killed it (141: SIGPIPE). */
int runWithStdoutReaderGone(const std::string& exe, const std::vector<std::string>& args);

}  // namespace emslam::test
