// SPDX-License-Identifier: BSD-3-Clause
#include "TestHelpers.h"

#include <emslam/io/AtomicFile.h>

#include <gtest/gtest.h>

#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace emslam::test
{
void putOnFullDisk(const std::string& file)
{
    std::filesystem::create_symlink("/dev/full", emslam::io::partialFileFor(file));
}

void writeFile(const std::string& path, const std::string& text)
{
    std::ofstream f(path, std::ios::binary);  // binary: keep CRLF as written
    f << text;
}

void expectThrowContaining(
    const std::function<void()>& fn, std::initializer_list<std::string> parts)
{
    try
    {
        fn();
        ADD_FAILURE() << "no exception thrown";
    }
    catch (const std::exception& e)
    {
        const std::string msg = e.what();
        for (const auto& p : parts)
        {
            EXPECT_NE(msg.find(p), std::string::npos) << "message lacks '" << p << "': " << msg;
        }
    }
}

std::vector<const char*> argvOf(const std::vector<std::string>& args)
{
    std::vector<const char*> argv;
    argv.reserve(args.size());
    for (const auto& a : args)
    {
        argv.push_back(a.c_str());
    }
    return argv;
}

double maxPoseDifference(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b)
{
    double d = (a.translation() - b.translation()).norm();
    const auto& A = a.getRotationMatrix();
    const auto& B = b.getRotationMatrix();
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 3; ++c)
        {
            d = std::max(d, std::abs(A(r, c) - B(r, c)));
        }
    }
    return d;
}

InterruptedRun interruptedRun(
    const std::string& exe,
    const std::vector<std::string>& args,
    const std::string& wait_for,
    int signum)
{
    char err_template[] = "/tmp/emslam_interrupted_XXXXXX";
    const int err_fd = ::mkstemp(err_template);
    const std::string err_file = err_template;
    const auto readErr = [&]
    {
        std::ifstream f(err_file);
        std::stringstream s;
        s << f.rdbuf();
        return s.str();
    };
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(exe.c_str()));
    for (const auto& a : args)
    {
        argv.push_back(const_cast<char*>(a.c_str()));
    }
    argv.push_back(nullptr);
    InterruptedRun r;
    const pid_t pid = ::fork();
    if (pid < 0)
    {
        ADD_FAILURE() << "fork failed";
        return r;
    }
    if (pid == 0)
    {
        ::dup2(err_fd, 2);
        std::freopen("/dev/null", "w", stdout);
        ::execv(exe.c_str(), argv.data());
        ::_exit(127);
    }
    ::close(err_fd);
    const auto t0 = std::chrono::steady_clock::now();
    while (readErr().find(wait_for) == std::string::npos &&
           std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120))
    {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ::kill(pid, signum);
    const auto t_signal = std::chrono::steady_clock::now();
    int status = 0;
    ::waitpid(pid, &status, 0);
    r.seconds_to_exit =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_signal).count();
    r.exited = WIFEXITED(status);
    r.exit_code = r.exited ? WEXITSTATUS(status) : -1;
    r.stderr_text = readErr();
    std::remove(err_file.c_str());
    return r;
}

}  // namespace emslam::test
