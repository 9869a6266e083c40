// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/DatasetSequence.h>

#include <mrpt/img/TCamera.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace emslam::io
{
/** Reader of a TUM RGB-D benchmark sequence (Sturm et al., IROS 2012):
 * \code
 *   RGBD_DIR/rgb.txt          "timestamp filename" per colour image ('#' comments)
 *   RGBD_DIR/depth.txt        "timestamp filename" per depth image
 *   RGBD_DIR/groundtruth.txt  "timestamp tx ty tz qx qy qz qw" (optional):
 *                             the colour camera's optical centre in the world
 *   RGBD_DIR/rgb/<t>.png      colour images (8-bit)
 *   RGBD_DIR/depth/<t>.png    depth images (16-bit, 5000 units per metre)
 * \endcode
 * Timestamps: each list holds seconds since the UNIX epoch, finite, within
 * [MIN_STAMP_NS, MAX_STAMP_NS] (after the epoch, before 2100-01-01) and
 * strictly increasing from line to line (TUM's lists are; a repeated or
 * earlier stamp is refused, not sorted). Each refusal is a
 * std::runtime_error "<rgb.txt>:<line>: timestamp '<text>' <reason>".
 *
 * Each colour image is associated with the depth image nearest in time, if
 * within `max_association_dt`, greedily by increasing time difference (each
 * depth image used at most once, as TUM's associate.py does); colour images
 * left without depth are dropped (unassociatedCount()).
 *
 * frame() gives a `CObservation3DRangeScan` with the colour image as
 * `intensityImage`, the raw depth as `rangeImage` (`rangeUnits =
 * 1/depth_factor`, `range_is_depth = true`, 0 = no depth), `cameraParams` =
 * `cameraParamsIntensity` = `intrinsics` (the registered depth is taken to
 * coincide with the colour camera), no 3D points. `sensorPose` maps MRPT's
 * range-scan sensor frame (+X forward, +Y left, +Z up) into the colour
 * camera's optical frame (x right, y down, z forward), so the robot frame is
 * the camera frame that the ground truth refers to.
 *
 * Ground truth: the groundtruth.txt row nearest to each colour image, if
 * within `gt_max_dt`; poses as in the file (camera in the world frame).
 * \ingroup emslam_io_grp \sa KittiSequence, EurocSequence */
class TumRgbdSequence : public DatasetSequence
{
public:
    /** One frame: the RGB-D observation and, if known, its ground truth. */
    struct Frame
    {
        mrpt::obs::CObservation3DRangeScan::Ptr obs;
        /** T_world_rgb from groundtruth.txt, if associated. */
        std::optional<mrpt::poses::CPose3D> ground_truth;
        /** Timestamp [s] of the colour image. */
        double t{0.0};
    };

    /** Sets `intrinsics` to the TUM default (fx = fy = 525, cx = 319.5,
     * cy = 239.5, 640x480, no distortion). */
    TumRgbdSequence();

    /** Opens and validates a sequence folder. Throws, naming the file and the
     * problem, on: a missing folder or list file, a garbled list line or
     * timestamp (see the class comment), a garbled ground-truth line, no
     * associated pair, a missing image, an unreadable first image, a depth
     * image that is not 16-bit single-channel, or colour and depth images of
     * different sizes. groundtruth.txt is optional.
     * Image sizes are read from the image headers (PNG, JPEG, PNM or BMP)
     * and checked before anything is decoded: an image over 8192 x 8192
     * pixels (or 65535 on a side) is refused naming the file, its size and
     * the limit. */
    void open(const std::string& rgbd_dir);

    bool isOpen() const { return !m_dir.empty(); }
    /** Number of associated (colour, depth) pairs. */
    std::size_t size() const override { return m_rgb_t.size(); }
    std::vector<std::string> inputFiles() const override;
    const std::string& directory() const { return m_dir; }
    unsigned int imageWidth() const { return m_width; }
    unsigned int imageHeight() const { return m_height; }

    /** Timestamp of frame `i` [s] (colour image). */
    double timestamp(std::size_t i) const override;
    /** Timestamp of the depth image of frame `i` [s]. */
    double depthTimestamp(std::size_t i) const;
    /** True if the folder has a groundtruth.txt. */
    bool hasGroundTruth() const override { return m_has_gt; }
    std::optional<mrpt::poses::CPose3D> groundTruthAt(std::size_t i) const override
    {
        return groundTruth(i);
    }
    /** Ground truth of frame `i` (T_world_rgb), if one was associated. */
    std::optional<mrpt::poses::CPose3D> groundTruth(std::size_t i) const;
    /** Number of frames with no ground truth within `gt_max_dt`. */
    std::size_t framesWithoutGroundTruth() const;
    /** Number of colour images dropped for lack of a depth image. */
    std::size_t unassociatedCount() const { return m_unassociated; }
    std::string rgbImageFile(std::size_t i) const;
    std::string depthImageFile(std::size_t i) const;

    /** Loads frame `i`. Throws, naming the file, if an image cannot be read,
     * is of the wrong type, or its size (from its header, before decoding)
     * differs from the first frame's. */
    Frame frame(std::size_t i) const;
    /** frame(), as a SequenceFrame. */
    SequenceFrame readFrame(std::size_t i) const override;

    /** Camera intrinsics (colour = depth). The image size is taken from the
     * images at open(). Set before open(). (Default: TUM's 525/525/319.5/239.5) */
    mrpt::img::TCamera intrinsics;
    /** Depth image units per metre. (Default: 5000) */
    double depth_factor{5000.0};
    /** Largest |t_rgb - t_depth| for an association [s]. (Default: 0.02) */
    double max_association_dt{0.02};
    /** Largest |t_rgb - t_gt| for a ground-truth association [s]. (Default: 0.02) */
    double gt_max_dt{0.02};
    /** `sensorLabel` of the observations. (Default: "RGBD") */
    std::string sensor_label{"RGBD"};

private:
    std::string m_dir;
    std::vector<double> m_rgb_t, m_depth_t;
    std::vector<std::string> m_rgb_files, m_depth_files;
    std::vector<std::optional<mrpt::poses::CPose3D>> m_gt;
    bool m_has_gt{false};
    std::size_t m_unassociated{0};
    unsigned int m_width{0}, m_height{0};
};

}  // namespace emslam::io
