// SPDX-License-Identifier: BSD-3-Clause
#include "TestHelpers.h"

#include "TestData.h"

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

std::string fileOnFullDisk(const std::string& tag, const std::string& name)
{
    const std::string file = makeTempDir(tag) + "/" + name;
    putOnFullDisk(file);
    return file;
}

std::string capturingStderr(const std::function<void()>& fn)
{
    testing::internal::CaptureStderr();
    try
    {
        fn();
    }
    catch (...)
    {
        testing::internal::GetCapturedStderr();
        throw;
    }
    return testing::internal::GetCapturedStderr();
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

namespace
{
/** A private temporary file (for a child's stdout or stderr). */
struct CapturedFile
{
    std::string name;
    int fd{-1};
    CapturedFile()
    {
        char name_template[] = "/tmp/emslam_captured_XXXXXX";
        fd = ::mkstemp(name_template);
        name = name_template;
    }
    ~CapturedFile() { std::remove(name.c_str()); }
    std::string text() const
    {
        std::ifstream f(name);
        std::stringstream s;
        s << f.rdbuf();
        return s.str();
    }
};

/** Starts `exe args` with stdout on `out_fd` and stderr on `err_fd`. */
pid_t spawn(const std::string& exe, const std::vector<std::string>& args, int out_fd, int err_fd)
{
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(exe.c_str()));
    for (const auto& a : args)
    {
        argv.push_back(const_cast<char*>(a.c_str()));
    }
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0)
    {
        ::dup2(out_fd, 1);
        ::dup2(err_fd, 2);
        ::execv(exe.c_str(), argv.data());
        ::_exit(127);
    }
    return pid;
}

/** The exit code of `status`, or 128 + the signal that killed the process. */
int exitCodeOf(int status)
{
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}
}  // namespace

InterruptedRun interruptedRun(
    const std::string& exe,
    const std::vector<std::string>& args,
    const std::string& wait_for,
    int signum)
{
    const CapturedFile out, err;
    InterruptedRun r;
    const pid_t pid = spawn(exe, args, out.fd, err.fd);
    if (pid < 0)
    {
        ADD_FAILURE() << "fork failed";
        return r;
    }
    ::close(out.fd);
    ::close(err.fd);
    const auto t0 = std::chrono::steady_clock::now();
    while (err.text().find(wait_for) == std::string::npos &&
           out.text().find(wait_for) == std::string::npos &&
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
    r.stderr_text = err.text();
    r.stdout_text = out.text();
    return r;
}

ProgramRun runProgram(const std::string& exe, const std::vector<std::string>& args)
{
    const CapturedFile out, err;
    ProgramRun r;
    const pid_t pid = spawn(exe, args, out.fd, err.fd);
    ::close(out.fd);
    ::close(err.fd);
    int status = 0;
    ::waitpid(pid, &status, 0);
    r.exit_code = exitCodeOf(status);
    r.stdout_text = out.text();
    r.stderr_text = err.text();
    return r;
}

int runWithStdoutReaderGone(const std::string& exe, const std::vector<std::string>& args)
{
    int fds[2];
    if (::pipe(fds) != 0)
    {
        ADD_FAILURE() << "pipe failed";
        return -1;
    }
    ::close(fds[0]);  // the reader is gone before the first write, as with `| true`
    const CapturedFile err;
    const pid_t pid = spawn(exe, args, fds[1], err.fd);
    ::close(fds[1]);
    ::close(err.fd);
    int status = 0;
    ::waitpid(pid, &status, 0);
    return exitCodeOf(status);
}

}  // namespace emslam::test
