// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/io/CStream.h>

#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace emslam::io
{
/** A plain output file whose every failure names the file and the OS
 * reason, captured at the failing system call: "cannot write 'stats.csv':
 * No space left on device". Binary data goes through the mrpt::io::CStream
 * interface (`mrpt::serialization::archiveFrom(file)`), text through text().
 * Data is buffered (64 KiB); close() writes the rest, closes the file and
 * throws if any write or the close failed: std::ofstream and
 * mrpt::io::CFileOutputStream only set a flag (errno lost by then) or, at
 * close, nothing at all.
 * \ingroup emslam_io_grp \sa AtomicTextFile, GzOutputStream */
class OutputFile : public mrpt::io::CStream
{
public:
    /** Creates (truncates) `file`. `name`: the file named in messages (e.g.
     * the final name of a `.partial` file; empty: `file`). Throws
     * std::runtime_error if it cannot be created. */
    explicit OutputFile(const std::string& file, const std::string& name = {});
    /** Closes the file if close() was not called; errors are ignored there. */
    ~OutputFile() override;
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    /** A text stream into the file. A failed write sets its badbit and is
     * thrown by close(). */
    std::ostream& text() { return *m_text; }
    /** Writes the buffered data and closes the file; throws
     * std::runtime_error "cannot write 'NAME': REASON" if that or any
     * earlier write failed. */
    void close();

    /** Buffers `count` bytes; throws std::runtime_error on a write error. */
    size_t Write(const void* buffer, size_t count) override;
    /** Not an input stream: throws. */
    size_t Read(void* buffer, size_t count) override;
    /** Not seekable: throws. */
    uint64_t Seek(int64_t offset, CStream::TSeekOrigin origin = sFromBeginning) override;
    /** Bytes written so far (buffered ones included). */
    uint64_t getTotalBytesCount() const override { return m_written; }
    /** Bytes written so far (buffered ones included). */
    uint64_t getPosition() const override { return m_written; }
    /** "file 'NAME'", for MRPT's messages. */
    std::string getStreamDescription() const override { return "file '" + m_name + "'"; }

    /** Appends `count` bytes; false (the error kept for close()) on failure. */
    bool put(const void* buffer, size_t count) noexcept;

private:
    class TextBuffer;
    bool flushBuffer() noexcept;
    [[noreturn]] void fail() const;

    int m_fd{-1};
    std::string m_name;
    std::vector<char> m_buffer;
    uint64_t m_written{0};
    int m_errno{0};  // of the first failed call; 0: none
    std::unique_ptr<TextBuffer> m_text_buffer;
    std::unique_ptr<std::ostream> m_text;
};

}  // namespace emslam::io
