// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/obs/CObservationStereoImages.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace emslam::test
{
/** The first `frames` frames of the simulated hall (config/sim/hall_double_loop.ini:
 * 320x240, 5 fps), rendered once per size and process; its ground truth is
 * beside it (same name, .tum). */
std::string simulatedHall(std::size_t frames);

/** Writes the first `frames` frames of the simulated hall to `rawlog` (gz),
 * each stereo observation passed through `edit(frame_index, observation)`
 * first. */
void writeEditedHall(
    const std::string& rawlog,
    std::size_t frames,
    const std::function<void(std::size_t, mrpt::obs::CObservationStereoImages&)>& edit);

/** Writes frames [first, first + count) of the simulated hall to `rawlog` (gz). */
void writeHallFrames(const std::string& rawlog, std::size_t first, std::size_t count);

/** Makes `stereo` a frame of another camera: both images resized to `width`
 * x `height` and the calibration scaled to match (a valid frame, of another
 * size). */
void resizeStereoFrame(mrpt::obs::CObservationStereoImages& stereo, int width, int height);

/** Replaces the right image of `stereo` by a 160x120 copy: a frame the
 * stereo front-end refuses (left and right of different sizes). */
void shrinkRightImage(mrpt::obs::CObservationStereoImages& stereo);

/** The timestamps of a TUM trajectory file, in file order. */
std::vector<double> trajectoryTimes(const std::string& tum_file);

}  // namespace emslam::test
