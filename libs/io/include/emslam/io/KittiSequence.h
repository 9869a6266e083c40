// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/DatasetSequence.h>

#include <mrpt/img/TStereoCamera.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace emslam::io
{
/** Reader of one sequence of the KITTI odometry benchmark (Geiger, Lenz,
 * Urtasun, CVPR 2012), in the official layout:
 * \code
 *   SEQUENCE_DIR/calib.txt           P0: (left) and P1: (right) 3x4 projections
 *   SEQUENCE_DIR/times.txt           one timestamp [s] per frame
 *   SEQUENCE_DIR/image_0/NNNNNN.png  left grayscale images (rectified)
 *   SEQUENCE_DIR/image_1/NNNNNN.png  right grayscale images (rectified)
 *   poses/XX.txt (optional)          one 3x4 row-major pose per frame
 * \endcode
 * open() validates the folder (files present, calibration readable, first
 * image pair readable and of equal size, one pose per frame); frame() loads
 * one stereo pair as a `CObservationStereoImages` with embedded images,
 * `hasImageRight = true`, the calibration of calib.txt and identity
 * `cameraPose` (the robot frame is the left camera frame: x right, y down,
 * z forward).
 *
 * Timestamps: `times.txt` holds seconds from the start of the sequence. The
 * observations carry the UNIX time `time_offset + t`
 * (`mrpt::Clock::fromDouble`); the default offset, DEFAULT_TIME_OFFSET, is
 * 2011-09-30 00:00:00 UTC (KITTI was recorded in Sept./Oct. 2011). An offset
 * is needed because MRPT tools take a time of exactly 0.0 (1970-01-01) as
 * "no timestamp".
 *
 * Ground truth (if a poses file is given): pose of the left camera in the
 * frame of the first left camera of the sequence (frame 0), as in the file;
 * the rotation is re-orthonormalized (the file prints 7 digits).
 * \ingroup emslam_io_grp \sa EurocSequence, TumRgbdSequence */
class KittiSequence : public DatasetSequence
{
public:
    /** One frame: the stereo observation and, if known, its ground truth. */
    struct Frame
    {
        mrpt::obs::CObservationStereoImages::Ptr obs;
        /** T_first_left: the left camera in the frame of sequence frame 0. */
        std::optional<mrpt::poses::CPose3D> ground_truth;
        /** Timestamp [s]: UNIX time, `time_offset` + times.txt value. */
        double t{0.0};
    };

    KittiSequence() = default;
    /** Same as open(). */
    explicit KittiSequence(const std::string& sequence_dir, const std::string& poses_file = {})
    {
        open(sequence_dir, poses_file);
    }

    /** Opens and validates a sequence folder and, if not empty, its poses
     * file. Throws, naming the file and the problem, on: a missing folder or
     * file, a missing or garbled `P0:`/`P1:` calibration line, a times.txt
     * line that is not a number, a times.txt count that differs from the
     * number of images in image_0 or image_1, a missing image, an unreadable
     * first image, left/right images of different sizes, or a poses file whose
     * line count differs from the frame count (or with a garbled line).
     * Image sizes are read from the image headers (PNG, JPEG, PNM or BMP)
     * and checked before anything is decoded: an image over 8192 x 8192
     * pixels (or 65535 on a side) is refused naming the file, its size and
     * the limit. */
    void open(const std::string& sequence_dir, const std::string& poses_file = {});

    bool isOpen() const { return !m_dir.empty(); }
    /** Number of frames (lines of times.txt). */
    std::size_t size() const override { return m_times.size(); }
    std::vector<std::string> inputFiles() const override;
    const std::string& directory() const { return m_dir; }
    /** Rectified stereo calibration read from calib.txt. */
    const mrpt::img::TStereoCamera& calibration() const { return m_calib; }
    unsigned int imageWidth() const { return m_width; }
    unsigned int imageHeight() const { return m_height; }

    /** Timestamp of frame `i` [s]: UNIX time, `time_offset + sequenceTime(i)`. */
    double timestamp(std::size_t i) const override;
    /** Time of frame `i` [s] from the start of the sequence, as in times.txt. */
    double sequenceTime(std::size_t i) const;
    bool hasGroundTruth() const override { return !m_poses.empty(); }
    std::optional<mrpt::poses::CPose3D> groundTruthAt(std::size_t i) const override
    {
        return hasGroundTruth() ? std::optional(groundTruth(i)) : std::nullopt;
    }
    /** Ground-truth pose of frame `i` (T_first_left); throws if there is none. */
    const mrpt::poses::CPose3D& groundTruth(std::size_t i) const;
    std::string leftImageFile(std::size_t i) const;
    std::string rightImageFile(std::size_t i) const;

    /** Loads frame `i`. Throws, naming the file, if an image cannot be read
     * or its size (from its header, before decoding) differs from the first
     * frame's. */
    Frame frame(std::size_t i) const;
    /** frame(), as a SequenceFrame. */
    SequenceFrame readFrame(std::size_t i) const override;

    /** 2011-09-30 00:00:00 UTC as UNIX time [s]. */
    static constexpr double DEFAULT_TIME_OFFSET = 1317340800.0;

    /** `sensorLabel` of the observations. (Default: "STEREO") */
    std::string sensor_label{"STEREO"};
    /** UNIX time [s] of times.txt's zero. (Default: DEFAULT_TIME_OFFSET) */
    double time_offset{DEFAULT_TIME_OFFSET};

    /** Reads a KITTI poses file (one 3x4 row-major matrix per line; the
     * rotation is re-orthonormalized). Throws naming the file and line on a
     * garbled line or a matrix that is far from a rotation. */
    static std::vector<mrpt::poses::CPose3D> readPosesFile(const std::string& file);

private:
    std::string m_dir;
    std::vector<double> m_times;
    std::vector<mrpt::poses::CPose3D> m_poses;
    mrpt::img::TStereoCamera m_calib;
    unsigned int m_width{0}, m_height{0};
};

}  // namespace emslam::io
