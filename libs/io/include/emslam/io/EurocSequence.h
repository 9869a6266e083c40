// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/DatasetSequence.h>

#include <mrpt/img/TStereoCamera.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace emslam::io
{
/** Reader of the stereo cameras of a EuRoC MAV sequence (Burri et al., IJRR
 * 2016), ASL layout:
 * \code
 *   MAV0_DIR/cam0/data.csv       "#timestamp [ns],filename" (left)
 *   MAV0_DIR/cam0/data/<ts>.png  left images (raw: distorted, not rectified)
 *   MAV0_DIR/cam0/sensor.yaml    intrinsics, distortion, T_BS
 *   MAV0_DIR/cam1/...            same for the right camera
 *   GT.csv (optional)            timestamp_ns,x,y,z,qx,qy,qz,qw: the left
 *                                camera (cam0) in the world frame
 * \endcode
 * `MAV0_DIR` may also be the folder that contains `mav0/`.
 *
 * Timestamps: each data.csv holds whole nanoseconds since the UNIX epoch (a
 * `.000` fraction is allowed; a non-zero one is refused, not truncated),
 * within [MIN_STAMP_NS, MAX_STAMP_NS] (after the epoch, before 2100-01-01:
 * 0 and INT64_MAX are refused), strictly increasing from line to line (a
 * repeated or earlier stamp is refused). Each refusal is a
 * std::runtime_error "<data.csv>:<line>: timestamp '<text>' <reason>".
 *
 * Left and right images are paired by equal timestamps (exactly: the cameras
 * are triggered together). An image that the other camera has no image for
 * is dropped and counted in unpairedCount(), not refused: a few real
 * sequences (V2_03_difficult) miss some frames of one camera. frame() gives
 * a `CObservationStereoImages` with the raw images embedded, `hasImageRight =
 * true`, the calibration of the two sensor.yaml files (distortion included;
 * `areImagesRectified()` is false) and identity `cameraPose` (the robot frame
 * is the left camera frame). Timestamps are the EuRoC nanosecond UNIX times,
 * converted exactly to MRPT's 100 ns clock ticks.
 *
 * Ground truth: the GT row nearest to each image timestamp is used if it is
 * within `gt_max_dt`; frames with no such row have none. Poses are returned as
 * in the file (left camera in the world frame).
 * \ingroup emslam_io_grp \sa KittiSequence, TumRgbdSequence */
class EurocSequence : public DatasetSequence
{
public:
    /** One frame: the stereo observation and, if known, its ground truth. */
    struct Frame
    {
        mrpt::obs::CObservationStereoImages::Ptr obs;
        /** T_world_left from the ground-truth file, if associated. */
        std::optional<mrpt::poses::CPose3D> ground_truth;
        /** Timestamp [s] (UNIX time). */
        double t{0.0};
    };

    EurocSequence() = default;
    /** Same as open(). */
    explicit EurocSequence(const std::string& mav0_dir, const std::string& gt_csv = {})
    {
        open(mav0_dir, gt_csv);
    }

    /** Opens and validates a `mav0` folder and, if not empty, a ground-truth
     * CSV file. Throws, naming the file and the problem, on: a missing folder
     * or file, a garbled data.csv line or timestamp (see the class comment),
     * an unreadable calibration, no left/right pair, a missing image, an
     * unreadable first image, left/right or image/calibration size mismatch,
     * or a garbled ground-truth line (including the 17-column
     * `state_groundtruth_estimate0` body-frame file, which is not the left
     * camera's pose).
     * Image sizes are read from the image headers (PNG, JPEG, PNM or BMP)
     * and checked before anything is decoded: an image over 8192 x 8192
     * pixels (or 65535 on a side) is refused naming the file, its size and
     * the limit. */
    void open(const std::string& mav0_dir, const std::string& gt_csv = {});

    bool isOpen() const { return !m_dir.empty(); }
    /** Number of stereo pairs. */
    std::size_t size() const override { return m_stamps.size(); }
    std::vector<std::string> inputFiles() const override;
    /** The `mav0` folder in use. */
    const std::string& directory() const { return m_dir; }
    /** Raw stereo calibration read from the sensor.yaml files. */
    const mrpt::img::TStereoCamera& calibration() const { return m_calib; }
    unsigned int imageWidth() const { return m_width; }
    unsigned int imageHeight() const { return m_height; }

    /** Timestamp of frame `i` [ns since the UNIX epoch]. */
    std::int64_t timestampNs(std::size_t i) const;
    /** Timestamp of frame `i` [s since the UNIX epoch]. */
    double timestamp(std::size_t i) const override
    {
        return 1e-9 * static_cast<double>(timestampNs(i));
    }
    /** True if a ground-truth file was given. */
    bool hasGroundTruth() const override { return m_has_gt; }
    std::optional<mrpt::poses::CPose3D> groundTruthAt(std::size_t i) const override
    {
        return groundTruth(i);
    }
    /** Ground truth of frame `i` (T_world_left), if one was associated. */
    std::optional<mrpt::poses::CPose3D> groundTruth(std::size_t i) const;
    /** Number of frames with no ground truth within `gt_max_dt`. */
    std::size_t framesWithoutGroundTruth() const;
    /** Number of images (left and right) dropped because the other camera has
     * no image with their timestamp. */
    std::size_t unpairedCount() const { return m_unpaired; }
    std::string leftImageFile(std::size_t i) const;
    std::string rightImageFile(std::size_t i) const;

    /** Loads frame `i`. Throws, naming the file, if an image cannot be read
     * or its size (from its header, before decoding) differs from the
     * calibration's. */
    Frame frame(std::size_t i) const;
    /** frame(), as a SequenceFrame. */
    SequenceFrame readFrame(std::size_t i) const override;

    /** `sensorLabel` of the observations. (Default: "STEREO") */
    std::string sensor_label{"STEREO"};
    /** Largest |image time - GT time| for a GT association [s]; set before
     * open(). (Default: 0.005) */
    double gt_max_dt{0.005};

    /** One row of a EuRoC camera-pose CSV file. */
    struct GtRow
    {
        std::int64_t t_ns{0};
        mrpt::poses::CPose3D pose;
    };
    /** Reads a `timestamp_ns,x,y,z,qx,qy,qz,qw` file (a `#` header line is
     * allowed; timestamps may carry a fractional part, which is ignored).
     * Throws naming the file and line on garbled input. Rows are sorted by
     * time. */
    static std::vector<GtRow> readGroundTruthCsv(const std::string& file);

private:
    std::string m_dir;
    std::vector<std::int64_t> m_stamps;
    std::vector<std::string> m_left_files, m_right_files;
    std::vector<std::optional<mrpt::poses::CPose3D>> m_gt;
    bool m_has_gt{false};
    std::size_t m_unpaired{0};
    mrpt::img::TStereoCamera m_calib;
    unsigned int m_width{0}, m_height{0};
};

}  // namespace emslam::io
