// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace emslam::hwdrivers
{
/** Thrown by a sensor's `doProcess()` when a finite source (a simulated
 * trajectory, an image folder) has delivered its last frame. emslam-grabber
 * treats it as a normal end of that sensor; the stock rawlog-grabber, whose
 * only way to end a run is an exception from a sensor, stops the run on it.
 * \ingroup emslam_hwdrivers_grp */
class EndOfStream : public std::runtime_error
{
public:
    /** `what`: which source ended, for the message. */
    explicit EndOfStream(const std::string& what) : std::runtime_error(what) {}
};

/** Optional interface of emslam sensors: frame statistics the grabber shows
 * in its status line.
 * \ingroup emslam_hwdrivers_grp */
class SensorStatus
{
public:
    virtual ~SensorStatus() = default;
    /** Frames the device produced that never reached the sensor's output
     * (e.g. the camera's DMA ring overran because doProcess() was late). */
    virtual std::size_t droppedFrames() const = 0;
};

}  // namespace emslam::hwdrivers
