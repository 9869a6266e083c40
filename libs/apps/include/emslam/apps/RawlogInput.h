// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace emslam::apps
{
/** Reads a rawlog (plain or gz, either format: action/sensory-frame pairs or
 * bare observations) entry by entry, each entry flattened into a batch of
 * observations. Opening it also points mrpt::img::CImage at the rawlog's
 * external images folder.
 * \code
 * RawlogInput in(file);
 * std::vector<mrpt::obs::CObservation::Ptr> batch;
 * while (in.next(batch)) { for (const auto& o : batch) { ... } }
 * \endcode
 * \ingroup emslam_apps_grp \sa RawlogOutput */
class RawlogInput
{
public:
    /** Opens `file`; throws std::runtime_error ("rawlog 'FILE' does not
     * exist", "cannot open rawlog 'FILE'") if it cannot. */
    explicit RawlogInput(const std::string& file);

    RawlogInput(const RawlogInput&) = delete;
    RawlogInput& operator=(const RawlogInput&) = delete;

    /** Reads the next entry into `batch` (the observation, or all those of the
     * sensory frame; possibly none). Returns false at the end of the file. */
    bool next(std::vector<mrpt::obs::CObservation::Ptr>& batch);

private:
    mrpt::io::CFileGZInputStream m_stream;
    std::unique_ptr<mrpt::serialization::CArchive> m_archive;
    mrpt::obs::CActionCollection::Ptr m_actions;
    mrpt::obs::CSensoryFrame::Ptr m_sf;
    mrpt::obs::CObservation::Ptr m_obs;
    std::size_t m_index{0};
};

}  // namespace emslam::apps
