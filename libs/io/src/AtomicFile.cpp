// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/AtomicFile.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace emslam::io
{
std::string partialFileFor(const std::string& file, bool keep_extension)
{
    if (!keep_extension)
    {
        return file + ".partial";
    }
    return file + ".partial" + std::filesystem::path(file).extension().string();
}

void commitPartialFile(const std::string& partial, const std::string& file)
{
    std::error_code ec;
    std::filesystem::rename(partial, file, ec);
    if (ec)
    {
        throw std::runtime_error(
            "cannot rename '" + partial + "' to '" + file + "': " + ec.message());
    }
}

void writeFileAtomically(
    const std::string& file,
    const std::function<bool(const std::string& partial)>& write,
    bool keep_extension)
{
    const std::string partial = partialFileFor(file, keep_extension);
    try
    {
        // A writer that only says false leaves its reason in errno, at best.
        errno = 0;
        if (!write(partial))
        {
            const int err = errno;
            throw std::runtime_error(
                "cannot write '" + file +
                "': " + (err != 0 ? std::strerror(err) : "the writer gave no reason"));
        }
        commitPartialFile(partial, file);
    }
    catch (...)
    {
        std::error_code ignored;
        std::filesystem::remove(partial, ignored);
        throw;
    }
}

}  // namespace emslam::io
