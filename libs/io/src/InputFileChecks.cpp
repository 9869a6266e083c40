// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/InputFileChecks.h>

#include <cstdio>
#include <stdexcept>
#include <system_error>

namespace fs = std::filesystem;

namespace emslam::io
{
namespace
{
std::string mebibytes(std::uintmax_t bytes)
{
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
    return buf;
}
}  // namespace

std::string fileTypeName(fs::file_type t)
{
    switch (t)
    {
        case fs::file_type::regular:
            return "a regular file";
        case fs::file_type::directory:
            return "a folder";
        case fs::file_type::symlink:
            return "a symbolic link";
        case fs::file_type::block:
            return "a block device";
        case fs::file_type::character:
            return "a character device";
        case fs::file_type::fifo:
            return "a FIFO (named pipe)";
        case fs::file_type::socket:
            return "a socket";
        case fs::file_type::not_found:
            return "missing (a broken symbolic link?)";
        default:
            return "not a regular file";
    }
}

void requireInputFile(const std::string& file, const std::string& what, std::uintmax_t max_bytes)
{
    const std::string name = what + " '" + file + "'";
    std::error_code ec;
    const fs::file_status st = fs::status(file, ec);  // follows symbolic links
    if (st.type() == fs::file_type::not_found)
    {
        throw std::runtime_error(name + " does not exist");
    }
    if (ec)
    {
        throw std::runtime_error("cannot read " + name + ": " + ec.message());
    }
    if (st.type() == fs::file_type::directory)
    {
        throw std::runtime_error(name + " is a folder, not a file");
    }
    if (st.type() != fs::file_type::regular)
    {
        throw std::runtime_error(
            name + " is not a regular file (it is " + fileTypeName(st.type()) + ")");
    }
    const std::uintmax_t size = fs::file_size(file, ec);
    if (ec)
    {
        throw std::runtime_error("cannot read " + name + ": " + ec.message());
    }
    if (size > max_bytes)
    {
        throw std::runtime_error(
            name + " is " + mebibytes(size) + "; a " + what + " has at most " +
            mebibytes(max_bytes));
    }
}

}  // namespace emslam::io
