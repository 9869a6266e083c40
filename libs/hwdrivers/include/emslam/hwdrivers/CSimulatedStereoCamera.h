// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/hwdrivers/CReplayStereoCamera.h>
#include <emslam/sim/StereoSimulator.h>

#include <mrpt/config/CLoadableOptions.h>

#include <cstddef>
#include <memory>
#include <string>

namespace emslam::hwdrivers
{
/** A live stereo camera backed by the simulator (emslam::sim::StereoSimulator):
 * each call of doProcess() renders the next frame of a world INI file
 * (config/sim/) and emits it as a `CObservationStereoImages` (rectified pair,
 * calibration filled, `hasImageRight`). Capture without hardware, for demos
 * and tests; the stock `rawlog-grabber` runs it as a plugin
 * (`rawlog-grabber grab.ini -p libemslam_hwdrivers.so`).
 *
 * After the last frame of the trajectory (or `max_frames`) it either starts
 * again (`loop = true`) or throws EndOfStream from doProcess().
 *
 * \code
 * [SIM_STEREO]
 * driver       = CSimulatedStereoCamera
 * sensorLabel  = STEREO             // label of the observations
 * process_rate = 5                  // [Hz] frame rate (default: the world's [Simulation] fps)
 * world_file   = config/sim/hall_double_loop.ini   // relative to the working folder
 * first_frame  = 0                  // first trajectory frame rendered
 * max_frames   = 0                  // frames per pass, 0: up to the trajectory's end
 * loop         = false              // after the last frame: start again (true) or end (false)
 * timestamps   = now                // now: wall clock at render time | simulation: world time
 * \endcode
 * Missing or invalid keys throw from loadConfig() naming the key; a missing
 * or invalid world file throws naming the file.
 * \ingroup emslam_hwdrivers_grp \sa CStereoImageFolderCamera, CDigiclopsStereoCamera */
class CSimulatedStereoCamera : public CReplayStereoCamera
{
    DEFINE_GENERIC_SENSOR(CSimulatedStereoCamera)

public:
    /** The sensor-specific INI keys (see the class comment). */
    struct TParameters : public TReplayOptions
    {
        /** `timestamps`: "now" (wall clock when rendered, the default) or
         * "simulation" (the world's own times, [Simulation] start_time + i / fps). */
        TParameters() : TReplayOptions("CSimulatedStereoCamera", "simulation")
        {
            timestamps = "now";
        }
        void validate() const override;

        /** World INI file (config/sim/ format); relative paths are taken from
         * the working folder. Mandatory. */
        std::string world_file;

    protected:
        /** Walks `world_file`. */
        void visitSourceKeys(util::ConfigVisitor& v) override;
    };

    CSimulatedStereoCamera() = default;

    /** The parameters loadConfig() read. */
    const TParameters& parameters() const { return m_params; }
    /** The simulator (valid after loadConfig()). */
    const emslam::sim::StereoSimulator& simulator() const { return *m_sim; }

protected:
    /** Reads TParameters from `section` of `cfg` and checks that the world file exists;
     * CGenericSensor::loadConfig() calls it. */
    void loadConfig_sensorSpecific(
        const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    /** Renders trajectory frame `i`. */
    mrpt::obs::CObservation::Ptr replayFrame(std::size_t i) override;
    std::string sourceName() const override { return "the trajectory"; }

private:
    TParameters m_params;
    std::shared_ptr<emslam::sim::StereoSimulator> m_sim;
};

}  // namespace emslam::hwdrivers
