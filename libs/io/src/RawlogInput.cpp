// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/InputFileChecks.h>
#include <emslam/io/RawlogInput.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/img/CImage.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CSerializable.h>
#include <mrpt/system/filesystem.h>

#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace emslam::io
{
/** The rawlog file read through zlib (plain files pass through unchanged),
 * counting the uncompressed bytes handed out: a record whose read hits the
 * end of the file after consuming bytes is a cut record, one that consumes
 * none is the clean end. zlib's own error is kept, so a damaged gz file (a
 * deflate error, a CRC or length mismatch at its end) is told from a cut one:
 * MRPT's CFileGZInputStream reports both as a short read. */
class RawlogInput::CountingStream : public mrpt::io::CStream
{
public:
    std::uint64_t consumed{0};
    bool short_read{false};  //!< a read got fewer bytes than asked: the file ended
    int zlib_error{Z_OK};    //!< zlib's error code once a read failed
    std::string zlib_message;

    ~CountingStream() override
    {
        if (m_gz != nullptr)
        {
            gzclose_r(m_gz);
        }
    }

    bool open(const std::string& file)
    {
        m_path = file;
        m_gz = gzopen(file.c_str(), "rb");
        if (m_gz != nullptr)
        {
            gzbuffer(m_gz, 1U << 17);  // 128 KiB: fewer system calls than the 8 KiB default
        }
        return m_gz != nullptr;
    }

    size_t Read(void* buffer, size_t count) override
    {
        auto* out = static_cast<unsigned char*>(buffer);
        size_t got = 0;
        while (got < count && zlib_error == Z_OK)
        {
            const auto chunk = static_cast<unsigned>(std::min<size_t>(count - got, 1U << 30));
            const int n = gzread(m_gz, out + got, chunk);
            if (n < 0)
            {
                const char* message = gzerror(m_gz, &zlib_error);
                zlib_message = message != nullptr ? message : "";
                // zlib prefixes the path, which the caller names already.
                if (zlib_message.rfind(m_path + ": ", 0) == 0)
                {
                    zlib_message.erase(0, m_path.size() + 2);
                }
                zlib_error = zlib_error == Z_OK ? Z_ERRNO : zlib_error;
            }
            if (n <= 0)
            {
                break;
            }
            got += static_cast<size_t>(n);
        }
        consumed += got;
        short_read = short_read || got < count;
        return got;
    }
    size_t Write(const void* /*buffer*/, size_t /*count*/) override
    {
        throw std::logic_error("RawlogInput is read-only");
    }
    uint64_t Seek(int64_t /*offset*/, TSeekOrigin /*origin*/) override
    {
        throw std::logic_error("RawlogInput cannot seek");
    }
    uint64_t getTotalBytesCount() const override { return 0; }
    uint64_t getPosition() const override { return consumed; }

private:
    gzFile m_gz{nullptr};
    std::string m_path;
};

namespace
{
/** The ISIZE field of a gz file (its last 4 bytes, little-endian), or empty
 * if the file does not start with the gzip magic bytes. */
std::optional<std::uint32_t> gzipTrailerSize(const std::string& file, std::uint64_t& file_size)
{
    std::ifstream f(file, std::ios::binary | std::ios::ate);
    if (!f)
    {
        return std::nullopt;
    }
    file_size = static_cast<std::uint64_t>(f.tellg());
    unsigned char magic[2] = {0, 0}, trailer[4] = {0, 0, 0, 0};
    f.seekg(0);
    f.read(reinterpret_cast<char*>(magic), 2);
    if (!f || magic[0] != 0x1f || magic[1] != 0x8b || file_size < 18)
    {
        return std::nullopt;
    }
    f.seekg(static_cast<std::streamoff>(file_size - 4));
    f.read(reinterpret_cast<char*>(trailer), 4);
    if (!f)
    {
        return std::nullopt;
    }
    return static_cast<std::uint32_t>(trailer[0]) | (static_cast<std::uint32_t>(trailer[1]) << 8) |
           (static_cast<std::uint32_t>(trailer[2]) << 16) |
           (static_cast<std::uint32_t>(trailer[3]) << 24);
}
}  // namespace

RawlogInput::RawlogInput(const std::string& file)
    : m_file(file), m_stream(std::make_unique<CountingStream>())
{
    requireInputFile(file, "rawlog");
    if (!m_stream->open(file))
    {
        throw std::runtime_error("cannot open rawlog '" + file + "'");
    }
    m_isize = gzipTrailerSize(file, m_file_size);
    mrpt::img::CImage::setImagesPathBase(mrpt::obs::CRawlog::detectImagesDirectory(file));
    m_archive =
        std::make_unique<mrpt::serialization::CArchiveStreamBase<CountingStream>>(*m_stream);
}

RawlogInput::~RawlogInput() = default;

bool RawlogInput::next(std::vector<mrpt::obs::CObservation::Ptr>& batch)
{
    batch.clear();
    if (m_ended)
    {
        return false;
    }
    const std::uint64_t start = m_stream->consumed;
    mrpt::serialization::CSerializable::Ptr obj;
    try
    {
        obj = m_archive->ReadObject();
    }
    catch (const std::exception& e)
    {
        m_ended = true;
        // MRPT wraps an EOF met inside an object into a generic exception:
        // whether the file ended, or zlib failed, is known from the stream.
        const bool cut = m_stream->short_read;
        if (m_stream->zlib_error == Z_OK && cut && m_stream->consumed == start)
        {
            return false;  // the clean end of the file
        }
        m_ended_early = true;
        const bool unparsable = m_stream->zlib_error == Z_OK && !cut;
        if (unparsable)
        {
            // A record MRPT cannot parse: damaged bytes inside a gz file whose
            // check comes at its end? Read on to that end to know.
            std::vector<unsigned char> rest(1U << 16);
            const std::uint64_t at = m_stream->consumed;
            while (m_stream->Read(rest.data(), rest.size()) == rest.size())
            {
            }
            m_stream->consumed = at;  // bytesRead() stays where the record failed
        }
        std::string cause;
        if (m_stream->zlib_error == Z_BUF_ERROR && !unparsable)  // "unexpected end of file"
        {
            cause = m_stream->consumed == start
                        ? "the gz file is cut after the previous record (its end is missing)"
                        : "the file ends in the middle of the record";
        }
        else if (m_stream->zlib_error != Z_OK && m_stream->zlib_error != Z_BUF_ERROR)
        {
            m_corrupt = true;
            cause = "the gz data is corrupt (zlib: " + m_stream->zlib_message + ")" +
                    (m_stream->zlib_message.find("check") != std::string::npos
                         ? std::string(": its CRC-32 or length does not match the data, so "
                                       "some earlier record holds damaged bytes")
                         : std::string());
        }
        else
        {
            cause = cut ? "the file ends in the middle of the record"
                        : emslam::util::shortExceptionMessage(e);
        }
        m_end_reason = "record " + std::to_string(m_records) + " (byte " + std::to_string(start) +
                       "): " + cause;
        return false;
    }
    ++m_records;
    if (auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj))
    {
        batch.push_back(std::move(obs));
    }
    else if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
    {
        batch.assign(sf->begin(), sf->end());
    }
    return true;
}

void RawlogInput::warnIfEndedEarly(const std::string& program) const
{
    if (m_ended_early)
    {
        std::fprintf(
            stderr, "%s: warning: rawlog '%s' ended early at %s; the records before it were used\n",
            program.c_str(), m_file.c_str(), m_end_reason.c_str());
    }
}

std::uint64_t RawlogInput::estimateUncompressedSize(
    std::uint32_t isize, std::uint64_t compressed_size, std::uint64_t position)
{
    constexpr std::uint64_t WRAP = std::uint64_t{1} << 32;
    // Deflate's worst case: stored blocks, 5 bytes per 16 KiB, plus header and trailer.
    const std::uint64_t overhead = 64 + compressed_size / 1000;
    const std::uint64_t floor =
        std::max(position, compressed_size > overhead ? compressed_size - overhead : 0);
    std::uint64_t size = isize;
    while (size < floor)
    {
        size += WRAP;
    }
    return size;
}

std::uint64_t RawlogInput::bytesRead() const
{
    return m_stream->consumed;
}

std::uint64_t RawlogInput::totalBytes() const
{
    if (!m_isize)
    {
        return m_file_size;
    }
    return estimateUncompressedSize(*m_isize, m_file_size, m_stream->consumed);
}

double RawlogInput::fractionRead() const
{
    const auto total = totalBytes();
    if (m_ended || total == 0)
    {
        return m_ended ? 1.0 : 0.0;
    }
    return std::min(1.0, static_cast<double>(m_stream->consumed) / static_cast<double>(total));
}

}  // namespace emslam::io
