// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/DatasetSequence.h>
#include <emslam/io/ObservationSource.h>

#include <cstddef>
#include <future>
#include <string>
#include <vector>

namespace emslam::io
{
/** The frames of a DatasetSequence as an ObservationSource, one observation
 * per entry, the next frame's images loaded on a second thread while the
 * caller works on the current one (as RawlogReadAhead does for a rawlog).
 *
 * A frame that cannot be read (a missing or damaged image) ends the input
 * early: endedEarly() and corrupt() are true and endReason() names the frame
 * and the file. The sequence must outlive this object (the destructor waits
 * for the read in flight).
 * \ingroup emslam_io_grp \sa DatasetFolder */
class DatasetReadAhead : public ObservationSource
{
public:
    explicit DatasetReadAhead(const DatasetSequence& sequence);
    ~DatasetReadAhead() override;
    DatasetReadAhead(const DatasetReadAhead&) = delete;
    DatasetReadAhead& operator=(const DatasetReadAhead&) = delete;

    bool next(std::vector<mrpt::obs::CObservation::Ptr>& batch) override;
    std::size_t recordsRead() const override { return m_frames; }
    double fractionRead() const override;
    bool endedEarly() const override { return !m_end_reason.empty(); }
    bool corrupt() const override { return endedEarly(); }
    const std::string& endReason() const override { return m_end_reason; }

private:
    void startReading();

    const DatasetSequence& m_sequence;
    std::future<SequenceFrame> m_ahead;
    std::size_t m_frames{0};
    std::string m_end_reason;
};

}  // namespace emslam::io
