// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/ObservationSource.h>
#include <emslam/io/RawlogInput.h>

#include <mrpt/obs/CObservation.h>

#include <cstddef>
#include <future>
#include <string>
#include <vector>

namespace emslam::io
{
/** Reads the next entry of a RawlogInput on a second thread while the
 * caller works on the current one, so that decompressing and deserializing
 * (about 9 ms per KITTI frame) overlap the mapping.
 *
 * Its queries describe the entries handed out by next(), not the one read
 * ahead: a caller that stops early (--max-frames, Ctrl-C) never sees the end
 * state of a record it did not ask for (a damaged record after the last frame
 * it wanted does not fail its run). The RawlogInput must outlive this
 * object, and must not be used directly while it exists (the destructor
 * waits for the read in flight).
 * \ingroup emslam_io_grp \sa RawlogInput, DatasetReadAhead */
class RawlogReadAhead : public ObservationSource
{
public:
    explicit RawlogReadAhead(RawlogInput& in);
    ~RawlogReadAhead() override;
    RawlogReadAhead(const RawlogReadAhead&) = delete;
    RawlogReadAhead& operator=(const RawlogReadAhead&) = delete;

    /** As RawlogInput::next(), from the entry read ahead; starts reading the
     * one after it. */
    bool next(std::vector<mrpt::obs::CObservation::Ptr>& batch) override;

    /** @name RawlogInput's state after the last entry handed out
     * @{ */
    std::size_t recordsRead() const override { return m_current.records; }
    double fractionRead() const override { return m_current.fraction; }
    bool endedEarly() const override { return m_current.ended_early; }
    bool corrupt() const override { return m_current.corrupt; }
    const std::string& endReason() const override { return m_current.end_reason; }
    /** @} */

private:
    struct Entry
    {
        bool ok{false};
        std::vector<mrpt::obs::CObservation::Ptr> batch;
        std::size_t records{0};
        double fraction{0};
        bool ended_early{false}, corrupt{false};
        std::string end_reason;
    };
    Entry readOne();
    void startReading();

    RawlogInput& m_in;
    std::future<Entry> m_ahead;
    Entry m_current;
};

}  // namespace emslam::io
