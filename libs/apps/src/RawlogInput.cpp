// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/RawlogInput.h>

#include <mrpt/img/CImage.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/system/filesystem.h>

#include <stdexcept>

namespace emslam::apps
{
RawlogInput::RawlogInput(const std::string& file)
{
    if (!mrpt::system::fileExists(file))
    {
        throw std::runtime_error("rawlog '" + file + "' does not exist");
    }
    if (!m_stream.open(file))
    {
        throw std::runtime_error("cannot open rawlog '" + file + "'");
    }
    mrpt::img::CImage::setImagesPathBase(mrpt::obs::CRawlog::detectImagesDirectory(file));
    m_archive =
        std::make_unique<mrpt::serialization::CArchiveStreamBase<mrpt::io::CFileGZInputStream>>(
            m_stream);
}

bool RawlogInput::next(std::vector<mrpt::obs::CObservation::Ptr>& batch)
{
    batch.clear();
    if (!mrpt::obs::CRawlog::getActionObservationPairOrObservation(
            *m_archive, m_actions, m_sf, m_obs, m_index))
    {
        return false;
    }
    if (m_obs)
    {
        batch.push_back(m_obs);
    }
    else if (m_sf)
    {
        batch.assign(m_sf->begin(), m_sf->end());
    }
    return true;
}

}  // namespace emslam::apps
