// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/GzOutputStream.h>

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace emslam::io
{
GzOutputStream::GzOutputStream(const std::string& file, int gz_level, const std::string& name)
    : m_name(name.empty() ? file : name)
{
    if (gz_level < 0 || gz_level > 9)
    {
        throw std::invalid_argument(
            "gzip level must be 0..9, got " + std::to_string(gz_level) + " for '" + m_name + "'");
    }
    const std::string mode = "wb" + std::to_string(gz_level);
    errno = 0;
    m_gz = gzopen(file.c_str(), mode.c_str());
    if (m_gz == nullptr)
    {
        fail(errno);
    }
}

GzOutputStream::~GzOutputStream()
{
    if (m_gz != nullptr)
    {
        gzclose(static_cast<gzFile>(m_gz));
    }
}

void GzOutputStream::fail(int err) const
{
    std::string reason = err != 0 ? std::strerror(err) : std::string();
    if (err == 0 && m_gz != nullptr)
    {
        int zerr = Z_OK;
        reason = gzerror(static_cast<gzFile>(m_gz), &zerr);
    }
    throw std::runtime_error(
        "cannot write '" + m_name + "': " + (reason.empty() ? "unknown error" : reason));
}

size_t GzOutputStream::Write(const void* buffer, size_t count)
{
    if (m_gz == nullptr)
    {
        throw std::logic_error("'" + m_name + "' is closed");
    }
    const auto* p = static_cast<const char*>(buffer);
    size_t left = count;
    while (left > 0)
    {
        // gzwrite() takes an unsigned int count.
        const auto chunk =
            static_cast<unsigned>(std::min<size_t>(left, std::numeric_limits<int>::max()));
        errno = 0;
        if (gzwrite(static_cast<gzFile>(m_gz), p, chunk) != static_cast<int>(chunk))
        {
            fail(errno);
        }
        p += chunk;
        left -= chunk;
    }
    m_written += count;
    return count;
}

void GzOutputStream::close()
{
    if (m_gz == nullptr)
    {
        return;
    }
    auto* gz = static_cast<gzFile>(m_gz);
    m_gz = nullptr;
    errno = 0;
    const int r = gzclose(gz);
    const int err = errno;
    if (r != Z_OK)
    {
        throw std::runtime_error(
            "cannot write '" + m_name +
            "': " + (err != 0 ? std::strerror(err) : "zlib error " + std::to_string(r)));
    }
}

size_t GzOutputStream::Read(void*, size_t)
{
    throw std::logic_error("'" + m_name + "' is an output stream");
}

uint64_t GzOutputStream::Seek(int64_t, CStream::TSeekOrigin)
{
    throw std::logic_error("'" + m_name + "' cannot seek");
}

}  // namespace emslam::io
