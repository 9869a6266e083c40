// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/RawlogReadAhead.h>

namespace emslam::io
{
RawlogReadAhead::RawlogReadAhead(RawlogInput& in) : m_in(in)
{
    startReading();
}

RawlogReadAhead::~RawlogReadAhead()
{
    if (m_ahead.valid())
    {
        m_ahead.wait();
    }
}

RawlogReadAhead::Entry RawlogReadAhead::readOne()
{
    Entry e;
    e.ok = m_in.next(e.batch);
    e.records = m_in.recordsRead();
    e.fraction = m_in.fractionRead();
    e.ended_early = m_in.endedEarly();
    e.corrupt = m_in.corrupt();
    e.end_reason = m_in.endReason();
    return e;
}

void RawlogReadAhead::startReading()
{
    m_ahead = std::async(std::launch::async, [this] { return readOne(); });
}

bool RawlogReadAhead::next(std::vector<mrpt::obs::CObservation::Ptr>& batch)
{
    batch.clear();
    if (!m_ahead.valid())
    {
        return false;  // the input has ended
    }
    m_current = m_ahead.get();
    batch = std::move(m_current.batch);
    m_current.batch.clear();
    if (m_current.ok)
    {
        startReading();
    }
    return m_current.ok;
}

}  // namespace emslam::io
