// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/obs/CObservation.h>

#include <cstddef>
#include <string>
#include <vector>

namespace emslam::io
{
/** Observations in recording order, one entry at a time, whatever holds
 * them: a rawlog (RawlogReadAhead) or a dataset folder (DatasetReadAhead).
 * The queries describe the entries handed out by next() so far.
 * \ingroup emslam_io_grp */
class ObservationSource
{
public:
    virtual ~ObservationSource() = default;

    /** The next entry's observations into `batch` (cleared first); false at
     * the end of the input (or where it ended early). */
    virtual bool next(std::vector<mrpt::obs::CObservation::Ptr>& batch) = 0;
    /** Entries handed out (records of a rawlog, frames of a dataset). */
    virtual std::size_t recordsRead() const = 0;
    /** How far through the input, 0..1 (for progress lines). */
    virtual double fractionRead() const = 0;
    /** True if the input ended before its end: a cut or damaged record, an
     * unreadable image. */
    virtual bool endedEarly() const = 0;
    /** True if it ended early on damaged data, not a cut (the entries read
     * may hold damaged pixels). */
    virtual bool corrupt() const = 0;
    /** Why the input ended early ("" otherwise). */
    virtual const std::string& endReason() const = 0;
};

}  // namespace emslam::io
