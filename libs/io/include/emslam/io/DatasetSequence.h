// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/TumTrajectory.h>

#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace emslam::io
{
/** One frame of a DatasetSequence: its observation (stereo pair or RGB-D
 * scan, as emslam-import writes it), timestamp and ground truth if known.
 * \ingroup emslam_io_grp */
struct SequenceFrame
{
    mrpt::obs::CObservation::Ptr obs;
    std::optional<mrpt::poses::CPose3D> ground_truth;
    double t{0.0};  //!< [s], UNIX time
};

/** A recorded dataset folder read frame by frame, whatever its layout
 * (KittiSequence, EurocSequence, TumRgbdSequence): what emslam-import and
 * the replay camera (hwdrivers::CStereoImageFolderCamera) need of it. Each
 * reader's own frame() gives the typed observation.
 * \ingroup emslam_io_grp */
class DatasetSequence
{
public:
    virtual ~DatasetSequence() = default;

    /** Frames in the folder (0 before open()). */
    virtual std::size_t size() const = 0;
    /** Timestamp of frame `i` [s] (UNIX time). */
    virtual double timestamp(std::size_t i) const = 0;
    /** True if ground truth was read with the folder. */
    virtual bool hasGroundTruth() const = 0;
    /** Ground truth of frame `i` as the file gives it, if it has one (no
     * image is read). */
    virtual std::optional<mrpt::poses::CPose3D> groundTruthAt(std::size_t i) const = 0;
    /** Every file of the folder the reader reads: its lists, calibration and
     * the images of every frame, so that no output overwrites one
     * (requireOutputsAreNotInputs()). */
    virtual std::vector<std::string> inputFiles() const = 0;
    /** Loads frame `i`; throws naming the file on a missing or bad image. */
    virtual SequenceFrame readFrame(std::size_t i) const = 0;

    /** The mean frame rate [Hz] from the first and last timestamps, or
     * `fallback` for fewer than two frames or non-increasing times. */
    double meanFrameRate(double fallback) const;
    /** The ground truth of every frame that has one, at its timestamp, as
     * the pose in the first such frame (that one exactly the identity): what
     * `emslam-import --gt-out` writes for the whole sequence. Empty without
     * ground truth. */
    TumTrajectory groundTruthTrajectory() const;
};

}  // namespace emslam::io
