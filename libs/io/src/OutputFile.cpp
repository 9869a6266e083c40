// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/OutputFile.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <streambuf>

namespace emslam::io
{
namespace
{
constexpr std::size_t BUFFER_BYTES = std::size_t{1} << 16;
}

/** Unbuffered: each insertion goes to OutputFile::put(), which buffers. */
class OutputFile::TextBuffer : public std::streambuf
{
public:
    explicit TextBuffer(OutputFile& f) : m_f(f) {}

protected:
    int_type overflow(int_type c) override
    {
        if (traits_type::eq_int_type(c, traits_type::eof()))
        {
            return traits_type::not_eof(c);
        }
        const char ch = traits_type::to_char_type(c);
        return m_f.put(&ch, 1) ? c : traits_type::eof();
    }
    std::streamsize xsputn(const char* s, std::streamsize n) override
    {
        return m_f.put(s, static_cast<size_t>(n)) ? n : 0;
    }

private:
    OutputFile& m_f;
};

OutputFile::OutputFile(const std::string& file, const std::string& name)
    : m_name(name.empty() ? file : name),
      m_text_buffer(std::make_unique<TextBuffer>(*this)),
      m_text(std::make_unique<std::ostream>(m_text_buffer.get()))
{
    m_fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (m_fd < 0)
    {
        m_errno = errno;
        fail();
    }
    m_buffer.reserve(BUFFER_BYTES);
}

OutputFile::~OutputFile()
{
    if (m_fd >= 0)
    {
        ::close(m_fd);
    }
}

void OutputFile::fail() const
{
    throw std::runtime_error("cannot write '" + m_name + "': " + std::strerror(m_errno));
}

bool OutputFile::flushBuffer() noexcept
{
    const char* p = m_buffer.data();
    std::size_t left = m_buffer.size();
    while (left > 0)
    {
        const ssize_t n = ::write(m_fd, p, left);
        if (n < 0 && errno == EINTR)
        {
            continue;
        }
        if (n <= 0)
        {
            m_errno = n < 0 ? errno : EIO;
            return false;
        }
        p += n;
        left -= static_cast<std::size_t>(n);
    }
    m_buffer.clear();
    return true;
}

bool OutputFile::put(const void* buffer, size_t count) noexcept
{
    if (m_errno != 0 || m_fd < 0)
    {
        return false;
    }
    if (m_buffer.size() + count > BUFFER_BYTES && !flushBuffer())
    {
        return false;
    }
    const auto* p = static_cast<const char*>(buffer);
    if (count >= BUFFER_BYTES)
    {
        // Large blocks go straight to the file.
        m_buffer.assign(p, p + count);
        if (!flushBuffer())
        {
            return false;
        }
    }
    else
    {
        m_buffer.insert(m_buffer.end(), p, p + count);
    }
    m_written += count;
    return true;
}

size_t OutputFile::Write(const void* buffer, size_t count)
{
    if (!put(buffer, count))
    {
        if (m_errno == 0)
        {
            throw std::logic_error("'" + m_name + "' is closed");
        }
        fail();
    }
    return count;
}

void OutputFile::close()
{
    if (m_fd < 0)
    {
        return;
    }
    const bool flushed = m_errno == 0 && flushBuffer();
    const int fd = m_fd;
    m_fd = -1;
    if (::close(fd) != 0 && m_errno == 0)
    {
        m_errno = errno;
    }
    if (!flushed || m_errno != 0)
    {
        fail();
    }
}

size_t OutputFile::Read(void*, size_t)
{
    throw std::logic_error("'" + m_name + "' is an output file");
}

uint64_t OutputFile::Seek(int64_t, CStream::TSeekOrigin)
{
    throw std::logic_error("'" + m_name + "' cannot seek");
}

}  // namespace emslam::io
