// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/hwdrivers/CReplayStereoCamera.h>
#include <emslam/io/DatasetSequence.h>

#include <mrpt/config/CLoadableOptions.h>

#include <cstddef>
#include <memory>
#include <string>

namespace emslam::hwdrivers
{
/** Replays a KITTI-odometry or EuRoC-layout folder as a live stereo camera:
 * each call of doProcess() loads the next stereo pair (through
 * emslam::io::KittiSequence / EurocSequence, exactly as emslam-import
 * does) and emits it as a `CObservationStereoImages` with both images and the
 * calibration. MRPT 2.5.8's own `CCameraSensor` image-folder mode drops the
 * right image; this sensor does not. With `timestamps = dataset` (the
 * default) and the same label, every observation is identical to the one
 * emslam-import writes for that frame.
 *
 * After the last frame it starts again (`loop = true`) or throws EndOfStream
 * from doProcess().
 *
 * \code
 * [FOLDER_STEREO]
 * driver       = CStereoImageFolderCamera
 * sensorLabel  = STEREO        // label of the observations
 * process_rate = 10            // [Hz] replay rate (default: the dataset's mean frame rate)
 * format       = kitti         // kitti (sequences/NN: calib.txt, times.txt, image_0/1) | euroc
 * (mav0) folder       = ../shared/data/kitti-odometry/sequences/06   // relative to the working
 * folder first_frame  = 0             // first frame replayed max_frames   = 0             ; frames
 * per pass, 0: to the end of the folder loop         = false         // after the last frame: start
 * again (true) or end (false) timestamps   = dataset       // dataset: the folder's times | now:
 * wall clock when loaded time_offset  = 1317340800    // kitti only: UNIX time [s] of times.txt's
 * zero (as emslam-import) \endcode \ingroup emslam_hwdrivers_grp \sa CSimulatedStereoCamera */
class CStereoImageFolderCamera : public CReplayStereoCamera
{
    DEFINE_GENERIC_SENSOR(CStereoImageFolderCamera)

public:
    /** The sensor-specific INI keys (see the class comment). */
    struct TParameters : public TReplayOptions
    {
        /** `timestamps`: "dataset" (the folder's own times, the default) or "now". */
        TParameters() : TReplayOptions("CStereoImageFolderCamera", "dataset") {}
        void validate() const override;

        /** "kitti" or "euroc". (Default: kitti) */
        std::string format{"kitti"};
        /** The sequence folder (KITTI `sequences/NN`, EuRoC `mav0` or its
         * parent); relative paths are taken from the working folder. Mandatory. */
        std::string folder;
        /** kitti: UNIX time [s] of times.txt's zero. (Default: 1317340800,
         * emslam::io::KittiSequence::DEFAULT_TIME_OFFSET) */
        double time_offset{1317340800.0};

    protected:
        /** Walks the folder's keys. */
        void visitSourceKeys(util::ConfigVisitor& v) override;
    };

    CStereoImageFolderCamera() = default;

    /** The parameters loadConfig() read. */
    const TParameters& parameters() const { return m_params; }
    /** Frames in the folder. */
    std::size_t folderSize() const { return m_sequence ? m_sequence->size() : 0; }

protected:
    /** Reads TParameters from `section` of `cfg` and checks the folder;
     * CGenericSensor::loadConfig() calls it. */
    void loadConfig_sensorSpecific(
        const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    /** Loads the pair of folder frame `i`. */
    mrpt::obs::CObservation::Ptr replayFrame(std::size_t i) override;
    std::string sourceName() const override { return "'" + m_params.folder + "'"; }

private:
    TParameters m_params;
    std::shared_ptr<const emslam::io::DatasetSequence> m_sequence;
};

}  // namespace emslam::hwdrivers
