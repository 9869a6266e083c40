// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/io/CStream.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/serialization/CArchive.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace emslam::io
{
/** Reads a rawlog (plain or gz, either format: action/sensory-frame pairs or
 * bare observations) entry by entry, each entry flattened into a batch of
 * observations. Opening it also points mrpt::img::CImage at the rawlog's
 * external images folder.
 * \code
 * RawlogInput in(file);
 * std::vector<mrpt::obs::CObservation::Ptr> batch;
 * while (in.next(batch)) { for (const auto& o : batch) { ... } }
 * if (in.endedEarly()) { warn(in.endReason()); }
 * \endcode
 * Unlike mrpt::obs::CRawlog's reader, which ends silently on any error, it
 * tells a clean end of file from a file cut in the middle of a record or a
 * record that cannot be read (endedEarly(), endReason()): everything before
 * stays usable.
 * \ingroup emslam_io_grp \sa RawlogOutput */
class RawlogInput
{
public:
    /** Opens `file`; throws std::runtime_error ("rawlog 'FILE' does not
     * exist", "... is a folder, not a file", "cannot open rawlog 'FILE'"; see
     * requireInputFile()) if it cannot. */
    explicit RawlogInput(const std::string& file);
    ~RawlogInput();

    RawlogInput(const RawlogInput&) = delete;
    RawlogInput& operator=(const RawlogInput&) = delete;

    /** Reads the next entry into `batch` (the observation, or all those of the
     * sensory frame; possibly none, e.g. for an action). Returns false at the
     * end of the file, or when a record cannot be read (see endedEarly()). */
    bool next(std::vector<mrpt::obs::CObservation::Ptr>& batch);

    /** True if reading stopped before a clean end of file: the file is cut in
     * the middle of a record, or a record is corrupt or of an unknown class. */
    bool endedEarly() const { return m_ended_early; }
    /** True if reading stopped because the gz data is damaged: zlib found
     * an invalid deflate stream, or the CRC-32 / length in the gz trailer
     * does not match what was decompressed (a flipped byte). Records read
     * before may then hold damaged bytes: the check covers the whole file.
     * Implies endedEarly(). */
    bool corrupt() const { return m_corrupt; }
    /** Why reading stopped early: the record number, the byte offset (of the
     * uncompressed stream) where that record starts, and the cause. */
    const std::string& endReason() const { return m_end_reason; }
    /** If endedEarly(), prints one warning line on stderr, prefixed by
     * `program`, naming the file and endReason(); otherwise nothing. */
    void warnIfEndedEarly(const std::string& program) const;
    /** Records (serialized objects) read completely so far. */
    std::size_t recordsRead() const { return m_records; }
    /** Fraction of the rawlog read so far, in [0, 1]: bytes of the
     * uncompressed stream read / totalBytes(); 1 once the file has ended.
     * For progress and ETA. */
    double fractionRead() const;
    /** Bytes of the uncompressed stream read so far. */
    std::uint64_t bytesRead() const;
    /** Size of the uncompressed stream [bytes]: the file size of a plain
     * rawlog; for a gz one, estimateUncompressedSize() of its trailer. */
    std::uint64_t totalBytes() const;

    /** The uncompressed size of a gz file whose trailer says `isize` (the
     * size modulo 2^32, RFC 1952) and whose compressed size is
     * `compressed_size`, once `position` uncompressed bytes were read: the
     * smallest isize + k·2^32 that is at least the position and at least what
     * the compressed size implies (deflate expands by < 0.1 % + a few bytes).
     * Exact below 4 GiB; above, it may be 4 GiB short until the position
     * passes it. */
    static std::uint64_t estimateUncompressedSize(
        std::uint32_t isize, std::uint64_t compressed_size, std::uint64_t position);

private:
    class CountingStream;
    std::string m_file;
    std::unique_ptr<CountingStream> m_stream;
    std::unique_ptr<mrpt::serialization::CArchive> m_archive;
    std::size_t m_records{0};
    std::uint64_t m_file_size{0};
    /** The gz trailer's ISIZE; empty for a plain file. */
    std::optional<std::uint32_t> m_isize;
    bool m_ended{false};
    bool m_ended_early{false};
    bool m_corrupt{false};
    std::string m_end_reason;
};

}  // namespace emslam::io
