// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/io/CStream.h>

#include <cstdint>
#include <string>

namespace emslam::io
{
/** A gzip-compressed output file as an mrpt::io::CStream (serialize into it
 * with `mrpt::serialization::archiveFrom(stream)`), written like
 * mrpt::io::CFileGZOutputStream, except that every failure throws
 * std::runtime_error naming the file and the OS reason, captured at the
 * failing call: "cannot write 'map.3Dscene': No space left on device".
 * MRPT 2.5.8's stream lets CArchive say "Cannot write bytes to stream!"
 * without the path, and ignores gzclose()'s result: the last compressed
 * block (all of a small file) is lost on a full disk without a word.
 * \ingroup emslam_io_grp \sa RawlogOutput, writeFileAtomically() */
class GzOutputStream : public mrpt::io::CStream
{
public:
    /** Creates (truncates) `file` with gzip level `gz_level` (0..9).
     * `name`: the file named in messages (e.g. the final name of a
     * `.partial` file; empty: `file`). Throws if it cannot be created. */
    GzOutputStream(const std::string& file, int gz_level, const std::string& name = {});
    /** Closes the file if close() was not called; errors are ignored there
     * (a failed write already threw). */
    ~GzOutputStream() override;
    GzOutputStream(const GzOutputStream&) = delete;
    GzOutputStream& operator=(const GzOutputStream&) = delete;

    /** Compresses `count` bytes; throws on failure (never a short count). */
    size_t Write(const void* buffer, size_t count) override;
    /** Flushes the compressor and closes the file; throws on failure. */
    void close();

    /** Not an input stream: throws. */
    size_t Read(void* buffer, size_t count) override;
    /** Not seekable: throws. */
    uint64_t Seek(int64_t offset, CStream::TSeekOrigin origin = sFromBeginning) override;
    /** Uncompressed bytes written so far. */
    uint64_t getTotalBytesCount() const override { return m_written; }
    /** Uncompressed bytes written so far. */
    uint64_t getPosition() const override { return m_written; }
    /** "gzip file 'NAME'", for MRPT's messages. */
    std::string getStreamDescription() const override { return "gzip file '" + m_name + "'"; }

private:
    [[noreturn]] void fail(int err) const;

    void* m_gz{nullptr};  // gzFile: zlib stays out of the header
    std::string m_name;
    uint64_t m_written{0};
};

}  // namespace emslam::io
