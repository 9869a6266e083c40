// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/InputFileChecks.h>
#include <emslam/io/OutputPathChecks.h>

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace fs = std::filesystem;

namespace emslam::io
{
namespace
{
/** Linux's own limit of links followed in one path. */
constexpr int MAX_LINK_HOPS = 40;

/** `p` with every symbolic link at its end replaced by its target. */
fs::path followLinks(const fs::path& p, const std::string& name)
{
    fs::path cur = p;
    for (int hop = 0; hop < MAX_LINK_HOPS; ++hop)
    {
        std::error_code ec;
        if (!fs::is_symlink(fs::symlink_status(cur, ec)))
        {
            return cur;
        }
        const fs::path target = fs::read_symlink(cur, ec);
        if (ec)
        {
            throw std::runtime_error("cannot follow the " + name + ": " + ec.message());
        }
        cur = target.is_absolute() ? target : cur.parent_path() / target;
    }
    throw std::runtime_error("the " + name + " is a loop of symbolic links");
}

/** Creates and removes a probe file in `folder` ("" = the current one). */
void requireWritable(const fs::path& folder, const std::string& name)
{
    static std::atomic<unsigned> counter{0};
    const fs::path probe =
        (folder.empty() ? fs::path(".") : folder) /
        (".emslam-write-probe-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0)
    {
        const int err = errno;
        throw std::runtime_error(
            "cannot write into folder '" + folder.string() + "' of the " + name + ": " +
            std::strerror(err));
    }
    ::close(fd);
    ::unlink(probe.c_str());
}
}  // namespace

std::string requireOutputFile(const std::string& file, const std::string& what)
{
    const std::string name = what + " '" + file + "'";
    if (file.empty())
    {
        throw std::runtime_error("no " + what + " given");
    }
    const fs::path target = followLinks(file, name);
    std::error_code ec;
    const fs::file_type type = fs::symlink_status(target, ec).type();
    if (type != fs::file_type::not_found && type != fs::file_type::regular)
    {
        throw std::runtime_error(
            "the " + name + " exists and is " + fileTypeName(type) +
            ", not a regular file; give a file path");
    }
    const fs::path folder = target.parent_path();
    if (!folder.empty() && !fs::is_directory(folder, ec))
    {
        throw std::runtime_error(
            "Folder '" + folder.string() + "' of the " + name + " does not exist");
    }
    requireWritable(folder, name);
    return target.string();
}

void requireOutputFolder(const std::string& folder, const std::string& what)
{
    const std::string name = what + " '" + folder + "'";
    if (folder.empty())
    {
        throw std::runtime_error("no " + what + " given");
    }
    // The folder itself, or else its nearest existing ancestor, must take files.
    fs::path p = folder;
    std::error_code ec;
    while (!p.empty() && fs::symlink_status(p, ec).type() == fs::file_type::not_found)
    {
        p = p.parent_path();
    }
    if (!p.empty() && !fs::is_directory(p, ec))
    {
        throw std::runtime_error(
            "cannot use the " + name + ": '" + p.string() + "' is " +
            fileTypeName(fs::status(p, ec).type()) + ", not a folder");
    }
    requireWritable(p, name);
}

void requireReplaceableFiles(const std::string& folder, const std::vector<std::string>& names)
{
    for (const auto& n : names)
    {
        const fs::path p = fs::path(folder) / n;
        std::error_code ec;
        const fs::file_type type = fs::symlink_status(p, ec).type();
        if (type != fs::file_type::not_found && type != fs::file_type::regular)
        {
            throw std::runtime_error(
                "output '" + p.string() + "' exists and is " + fileTypeName(type) +
                ", not a regular file; remove it or choose another output folder");
        }
    }
}

void createOutputFolder(const std::string& folder)
{
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec || !fs::is_directory(folder))
    {
        throw std::runtime_error(
            "cannot create output folder '" + folder + "'" + (ec ? ": " + ec.message() : ""));
    }
}

}  // namespace emslam::io
