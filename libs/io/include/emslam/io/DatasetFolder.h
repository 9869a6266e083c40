// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/DatasetSequence.h>

#include <memory>
#include <string>

namespace emslam::io
{
/** A recorded dataset folder given as a program's input, recognised by the
 * files it holds, with the ground truth that comes with it:
 * - KITTI odometry: a sequence folder (`calib.txt`, `times.txt`, `image_0/`,
 *   `image_1/`), or the dataset folder above it when its `sequences/` holds
 *   exactly one sequence; ground truth `poses/NN.txt` two levels above the
 *   sequence `sequences/NN`, if present;
 * - EuRoC MAV: a `mav0` folder (`cam0/data.csv`, `cam1/data.csv`) or the
 *   folder holding it; ground truth `groundtruth_left_cam.csv` (the left
 *   camera's pose, `timestamp_ns,x,y,z,qx,qy,qz,qw`) in either, if present
 *   (EuRoC's own `state_groundtruth_estimate0` is the body's pose, not the
 *   camera's, and is not read);
 * - TUM RGB-D: a folder with `rgb.txt` and `depth.txt`; ground truth its
 *   `groundtruth.txt`, if present.
 * \ingroup emslam_io_grp \sa DatasetSequence, DatasetReadAhead */
struct DatasetFolder
{
    enum class Format
    {
        Kitti,
        Euroc,
        TumRgbd
    };
    Format format{Format::Kitti};
    /** The folder the reader opens (KITTI `sequences/NN`, EuRoC `mav0`, ...). */
    std::string sequence_dir;
    /** KITTI / EuRoC ground-truth file found with it, or "" (TUM's reader
     * finds its own groundtruth.txt). */
    std::string ground_truth_file;

    /** "KITTI odometry", "EuRoC MAV" or "TUM RGB-D". */
    std::string formatName() const;

    /** True if `path` is a folder (it may be of no known format). */
    static bool isFolder(const std::string& path);
    /** The dataset in folder `dir`. Throws std::invalid_argument naming the
     * folder and the layouts expected when it is none of them (or a KITTI
     * dataset folder with several sequences, naming them). */
    static DatasetFolder detect(const std::string& dir);
    /** Opens the folder with its reader (KittiSequence, EurocSequence,
     * TumRgbdSequence) and the ground truth found with it; throws as the
     * reader's open() does. */
    std::shared_ptr<DatasetSequence> open() const;
};

}  // namespace emslam::io
