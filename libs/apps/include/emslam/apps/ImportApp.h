// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/App.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace emslam::apps
{
/** The dataset importer behind `emslam-import`: converts a KITTI odometry
 * sequence, a EuRoC MAV stereo sequence or a TUM RGB-D sequence into a
 * gz-compressed, observations-only rawlog of stock MRPT classes, plus
 * (optionally) the ground truth as a TUM trajectory file.
 *
 * \code
 * emslam-import kitti SEQUENCE_DIR -o OUT.rawlog [--poses POSES.txt] [--gt-out GT.tum]
 *                                                [--time-offset SECONDS]
 * emslam-import euroc MAV0_DIR     -o OUT.rawlog [--gt GT.csv]       [--gt-out GT.tum]
 * emslam-import tum   RGBD_DIR     -o OUT.rawlog [--intrinsics fx,fy,cx,cy] [--gt-out GT.tum]
 *   common: [--first N] [--last N] [--step K] | [--frames LIST]
 *           [--label LABEL] [--quiet]
 * \endcode
 *
 * - kitti / euroc: one `CObservationStereoImages` per frame (images embedded,
 *   calibration set, label "STEREO"); tum: one `CObservation3DRangeScan`
 *   (colour + depth image, label "RGBD"). See emslam::io::KittiSequence,
 *   EurocSequence and TumRgbdSequence for the details of each format.
 * - Frames `first, first+step, ...` up to `last` (inclusive, 0-based indices
 *   into the dataset's frame list) are imported; the same selection applies
 *   to the ground truth. Or `--frames LIST` (see `frames`) names the frames
 *   one by one, in any order: `0:50:2,49:1:-2` drives a sequence forward on
 *   the even frames and back on the odd ones (a "pseudo-loop").
 * - Timestamps stay strictly increasing, as MRPT tools and the mapper expect:
 *   if `frames` is not strictly increasing, the k-th written frame gets the
 *   time `t(frames[0]) + k * median frame period of the sequence`, in the
 *   rawlog and the ground truth alike (poses stay those of the listed
 *   frames), and `retimed` is set.
 * - The ground-truth file holds one line per imported frame that has ground
 *   truth: `t x y z qx qy qz qw`, the pose of the left (colour) camera in the
 *   frame of the first imported frame that has ground truth. Frames without
 *   ground truth are still imported; they are counted in frames_without_gt.
 * - Both outputs are written to `<name>.partial` and renamed when the whole
 *   import succeeded; on any error the partial files are removed and run()
 *   throws.
 *
 * Errors (bad arguments, bad input) are exceptions; nothing calls exit().
 * \ingroup emslam_apps_grp \sa doc/apps/emslam-import.md */
class ImportApp : public App
{
public:
    ImportApp();

    /** \name Settings (filled by initialize(); may be edited before run())
     * @{ */
    /** "kitti", "euroc" or "tum". */
    std::string dataset;
    /** Sequence folder (KITTI sequence, EuRoC mav0, TUM RGB-D folder). */
    std::string input_dir;
    /** Output rawlog file. */
    std::string output_file;
    /** KITTI poses file (optional). */
    std::string kitti_poses_file;
    /** EuRoC left-camera ground-truth CSV (optional). */
    std::string euroc_gt_file;
    /** Ground-truth output (TUM format); empty: not written. */
    std::string gt_out_file;
    /** TUM RGB-D intrinsics "fx,fy,cx,cy" (empty: the TUM defaults). */
    std::string tum_intrinsics;
    /** KITTI: UNIX time [s] of times.txt's zero; unset: the
     * emslam::io::KittiSequence default (2011-09-30 00:00:00 UTC). */
    std::optional<double> kitti_time_offset;
    /** Sensor label; empty: "STEREO" (kitti, euroc) or "RGBD" (tum). */
    std::string sensor_label;
    /** First frame index (0-based). */
    std::size_t first{0};
    /** Last frame index, inclusive; unset: the last frame. */
    std::optional<std::size_t> last;
    /** Import every `step`-th frame (>= 1). */
    std::size_t step{1};
    /** Frame indexes to import, in output order (repeats allowed); when not
     * empty, first / last / step are ignored. `--frames` fills it from a
     * comma-separated list of `N`, `A:B` or `A:B:STEP` items (B included when
     * reached; STEP may be negative; `A:B` steps by -1 if B < A), e.g.
     * `0:50:2,49:1:-2`. run() throws if an index is beyond the sequence. */
    std::vector<std::size_t> frames;
    /** gzip level of the rawlog, 0..9. (Default: 1, fastest) */
    int gz_level{1};
    /** No progress and summary output. */
    bool quiet{false};
    /** @} */

    /** \name Results
     * @{ */
    /** True after `--help` / `--version`: nothing to run. */
    /** Observations written to output_file. */
    std::size_t frames_written{0};
    /** Poses written to gt_out_file. */
    std::size_t poses_written{0};
    /** Imported frames that had no ground truth (not in gt_out_file). */
    std::size_t frames_without_gt{0};
    /** True if the frames got new timestamps (`frames` not strictly increasing). */
    bool retimed{false};
    /** Size of output_file [bytes]. */
    std::uintmax_t output_bytes{0};
    /** Wall-clock duration of run() [s]. */
    double elapsed_seconds{0.0};
    /** @} */

protected:
    bool parseArguments(int argc, const char** argv) override;
    /** Runs the import. Throws on any error, leaving no output file behind. */
    void execute() override;

private:
    struct Arguments;
    /** The dataset, folders, files and labels, and the options only some
     * datasets take. */
    void takeDataset(Arguments& args);
    /** The frames to import (--first/--last/--step or --frames), the
     * compression and --gt-out, checked. */
    void takeSelection(Arguments& args);

    bool m_initialized{false};
};

}  // namespace emslam::apps
