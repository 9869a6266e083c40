// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/obs/CObservation.h>

#include <cstddef>
#include <string>

namespace emslam::hwdrivers
{
/** The INI keys every replayed source shares (frames first_frame ..
 * first_frame + max_frames - 1, then loop or end). Sensors' TParameters
 * derive from it. \ingroup emslam_hwdrivers_grp \sa CReplayStereoCamera */
struct TReplayRange
{
    /** First frame replayed. (Default: 0) */
    std::size_t first_frame{0};
    /** Frames per pass; 0: to the end of the source. (Default: 0) */
    std::size_t max_frames{0};
    /** Start again at first_frame after the last frame. (Default: false) */
    bool loop{false};

    /** Reads first_frame, max_frames (whole numbers ≥ 0: throws
     * std::invalid_argument naming the key otherwise) and loop. */
    void loadRangeKeys(const mrpt::config::CConfigFileBase& c, const std::string& s);
    void saveRangeKeys(mrpt::config::CConfigFileBase& c, const std::string& s) const;
};

/** A "live" camera replaying a finite source frame by frame (the simulator,
 * a dataset folder): each doProcess() emits the next frame of the range
 * (TReplayRange), stamped with the wall clock if asked, and after the last
 * one starts again (`loop`) or throws EndOfStream. Subclasses open their
 * source in loadConfig_sensorSpecific(), then call startReplay().
 * \ingroup emslam_hwdrivers_grp \sa CSimulatedStereoCamera, CStereoImageFolderCamera */
class CReplayStereoCamera : public mrpt::hwdrivers::CGenericSensor
{
public:
    /** Emits the next frame; throws EndOfStream after the last one unless
     * `loop`, std::logic_error before loadConfig(). */
    void doProcess() override;

    /** Frames delivered so far. */
    std::size_t framesDelivered() const { return m_delivered; }

protected:
    /** Starts the range over a source of `source_frames` frames; throws
     * std::invalid_argument (prefixed by `where`) if first_frame is past it.
     * A process_rate of 0 becomes `default_rate` [Hz]. */
    void startReplay(
        const TReplayRange& range,
        std::size_t source_frames,
        bool stamp_now,
        double default_rate,
        const std::string& where);

    /** Frame `i` of the source (its label set by the caller). */
    virtual mrpt::obs::CObservation::Ptr replayFrame(std::size_t i) = 0;
    /** "the trajectory", "'FOLDER'": what ended, for EndOfStream. */
    virtual std::string sourceName() const = 0;

private:
    TReplayRange m_range;
    bool m_started{false};
    bool m_stamp_now{false};
    std::size_t m_next{0};
    std::size_t m_end{0};
    std::size_t m_delivered{0};
};

}  // namespace emslam::hwdrivers
