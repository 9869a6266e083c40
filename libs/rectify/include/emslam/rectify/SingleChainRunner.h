// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/rectify/RectificationRunner.h>
#include <emslam/rectify/TrajectoryRectifier.h>

namespace emslam::rectify
{
/** What the serial and AnyTime runners share: one trajectory rectified by one
 * rectifier (one Metropolis-Hastings chain), both set up from the options,
 * and the way a frame enters the trajectory (only its vertical band when
 * `vertical_band` is on; compression whenever N > N_max).
 * \ingroup emslam_rectify_grp \sa SerialRectification, AnyTimeRectification */
class SingleChainRunner : public RectificationRunner
{
protected:
    /** An empty trajectory whose map has `map_options` and
     * `insertion_options`, with the odometry prior, grid phases and threads
     * of `options`, and a rectifier with `options`. */
    SingleChainRunner(
        const TRectifierOptions& options,
        const emslam::CEntropyVoxelMap::TCreationOptions& map_options,
        const emslam::CEntropyVoxelMap::TInsertionOptions& insertion_options);

    /** The part of `cloud` the trajectory keeps: its vertical band
     * (keepVerticalBand()) when `vertical_band` is on, else all of it. */
    emslam::maps::WeightedPointCloud keptPart(const emslam::maps::WeightedPointCloud& cloud) const;

    /** Appends a frame whose cloud went through keptPart(), then compresses
     * the trajectory if it needs it (Trajectory::needsCompression()). */
    void appendFrame(
        const mrpt::poses::CPose3D& action,
        const emslam::maps::WeightedPointCloud& cloud,
        double timestamp,
        std::size_t frame_index,
        const std::optional<ActionCovariance>& covariance);

    TRectifierOptions m_options;      //!< the options the runner was made with
    Trajectory m_trajectory;          //!< the frames so far, as elements
    TrajectoryRectifier m_rectifier;  //!< the chain that rectifies m_trajectory
};

}  // namespace emslam::rectify
