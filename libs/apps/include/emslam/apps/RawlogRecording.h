// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/TumTrajectory.h>

#include <mrpt/serialization/CArchive.h>

#include <cstddef>
#include <functional>
#include <string>

namespace emslam::apps
{
/** What recordRawlog() wrote. \ingroup emslam_apps_grp */
struct RawlogRecording
{
    std::size_t frames_written{0};  //!< stereo observations written
    std::size_t poses_written{0};   //!< ground-truth poses (0 without a GT file)
};

/** Writes frame `k` of a recording to `out`, and its ground-truth pose (if
 * any) to `gt`. \ingroup emslam_apps_grp */
using RawlogFrameWriter = std::function<void(
    std::size_t k, mrpt::serialization::CArchive& out, emslam::io::TumTrajectory& gt)>;

/** The recording loop emslam-import and emslam-sim share: writes `frames`
 * frames through an io::RawlogOutput (`output_file`, gzip `gz_level`, the
 * ground truth to `gt_out_file` if not empty) by calling
 * `write_frame(k, archive, ground_truth)` for k = 0, 1, ..., with a progress
 * line (if `show_progress`). SIGINT / SIGTERM end the loop early and the
 * frames written so far are kept (noteInterruption()); any failure leaves no
 * file under the output names.
 * \ingroup emslam_apps_grp \sa ImportApp, SimApp */
RawlogRecording recordRawlog(
    const std::string& program,
    const std::string& output_file,
    int gz_level,
    const std::string& gt_out_file,
    std::size_t frames,
    bool show_progress,
    const RawlogFrameWriter& write_frame);

}  // namespace emslam::apps
