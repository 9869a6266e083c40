// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/obs/CObservation.h>

#include <cstddef>
#include <string>

namespace emslam::hwdrivers
{
/** The INI keys every replayed source shares: frames first_frame ..
 * first_frame + max_frames - 1, then loop or end, stamped with the source's
 * own clock or the wall clock. A sensor's TParameters derive from it and add
 * their source's keys (visitSourceKeys(), validate()).
 * \ingroup emslam_hwdrivers_grp \sa CReplayStereoCamera */
struct TReplayOptions : public mrpt::config::CLoadableOptions
{
    /** `sensor`: the class name for messages; `source_clock`: the name of
     * the source's own times ("simulation", "dataset"), the default of
     * `timestamps`. */
    TReplayOptions(std::string sensor, std::string source_clock);

    /** First frame replayed. (Default: 0) */
    std::size_t first_frame{0};
    /** Frames per pass; 0: to the end of the source. (Default: 0) */
    std::size_t max_frames{0};
    /** Start again at first_frame after the last frame. (Default: false) */
    bool loop{false};
    /** The source's clock (see the constructor) or "now" (the wall clock
     * when the frame is emitted). */
    std::string timestamps;

    /** Reads the source's keys, then first_frame, max_frames (whole numbers
     * ≥ 0), loop and timestamps, and validates; throws
     * std::invalid_argument naming the key of a bad value. */
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) final;
    /** Writes the source's keys and first_frame, max_frames, loop, timestamps. */
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const final;
    /** Throws std::invalid_argument naming the key of an invalid value
     * (overrides check their keys, then call this one). */
    virtual void validate() const;
    /** True if frames get the wall clock's time. */
    bool stampNow() const { return timestamps == "now"; }

protected:
    /** Walks the keys of the concrete source (its files, world, ...), for
     * loading and for saving alike (util::ConfigVisitor). */
    virtual void visitSourceKeys(util::ConfigVisitor& v) = 0;
    /** The sensor's class name, for messages. */
    const std::string& sensorName() const { return m_sensor; }

private:
    /** The source's keys, then first_frame, max_frames, loop, timestamps. */
    void visitKeys(util::ConfigVisitor& v);

    std::string m_sensor, m_source_clock;
};

/** A "live" camera replaying a finite source frame by frame (the simulator,
 * a dataset folder): each doProcess() emits the next frame of the range
 * (TReplayOptions), stamped with the wall clock if asked, and after the last
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
    /** Starts the range of `options` over a source of `source_frames`
     * frames; throws std::invalid_argument (prefixed by `where`) if
     * first_frame is past it. A process_rate of 0 becomes `default_rate` [Hz]. */
    void startReplay(
        const TReplayOptions& options,
        std::size_t source_frames,
        double default_rate,
        const std::string& where);

    /** Frame `i` of the source (its label set by the caller). */
    virtual mrpt::obs::CObservation::Ptr replayFrame(std::size_t i) = 0;
    /** "the trajectory", "'FOLDER'": what ended, for EndOfStream. */
    virtual std::string sourceName() const = 0;

private:
    std::size_t m_first{0};
    bool m_loop{false};
    bool m_started{false};
    bool m_stamp_now{false};
    std::size_t m_next{0};
    std::size_t m_end{0};
    std::size_t m_delivered{0};
};

}  // namespace emslam::hwdrivers
