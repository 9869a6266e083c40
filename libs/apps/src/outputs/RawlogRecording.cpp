// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/ProgressLine.h>
#include <emslam/apps/RawlogRecording.h>
#include <emslam/apps/StopSignal.h>
#include <emslam/io/RawlogOutput.h>

namespace emslam::apps
{
RawlogRecording recordRawlog(
    const std::string& program,
    const std::string& output_file,
    int gz_level,
    const std::string& gt_out_file,
    std::size_t frames,
    bool show_progress,
    const RawlogFrameWriter& write_frame)
{
    RawlogRecording r;
    emslam::io::TumTrajectory gt;
    StopSignal::clear();
    const StopSignalGuard signals;
    io::RawlogOutput out(output_file, gz_level, gt_out_file);
    {
        ProgressLine progress(program, frames, show_progress);
        for (std::size_t k = 0; k < frames && !StopSignal::requested(); ++k)
        {
            write_frame(k, out.archive(), gt);
            ++r.frames_written;
            progress.update(k + 1);
        }
        progress.finish();
    }
    noteInterruption(program, r.frames_written, frames, output_file);
    r.poses_written = out.commit(gt);
    return r;
}

}  // namespace emslam::apps
