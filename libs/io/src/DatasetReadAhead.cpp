// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/DatasetReadAhead.h>
#include <emslam/util/ExceptionMessage.h>

namespace emslam::io
{
DatasetReadAhead::DatasetReadAhead(const DatasetSequence& sequence) : m_sequence(sequence)
{
    startReading();
}

DatasetReadAhead::~DatasetReadAhead()
{
    if (m_ahead.valid())
    {
        m_ahead.wait();
    }
}

void DatasetReadAhead::startReading()
{
    const std::size_t i = m_frames;
    if (i < m_sequence.size())
    {
        m_ahead = std::async(std::launch::async, [this, i] { return m_sequence.readFrame(i); });
    }
}

bool DatasetReadAhead::next(std::vector<mrpt::obs::CObservation::Ptr>& batch)
{
    batch.clear();
    if (!m_ahead.valid())
    {
        return false;  // the last frame was handed out, or a frame could not be read
    }
    try
    {
        batch.push_back(m_ahead.get().obs);
    }
    catch (const std::exception& e)
    {
        m_end_reason =
            "frame " + std::to_string(m_frames) + ": " + emslam::util::shortExceptionMessage(e);
        return false;
    }
    ++m_frames;
    startReading();
    return true;
}

double DatasetReadAhead::fractionRead() const
{
    const std::size_t n = m_sequence.size();
    return n == 0 ? 1.0 : static_cast<double>(m_frames) / static_cast<double>(n);
}

}  // namespace emslam::io
