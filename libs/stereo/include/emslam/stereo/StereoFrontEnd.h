// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/stereo/SparseStereoMatcher.h>
#include <emslam/stereo/StereoFrame.h>
#include <emslam/stereo/StereoMatcher.h>
#include <emslam/stereo/StereoRectifier.h>

#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationStereoImages.h>

#include <functional>
#include <vector>

namespace emslam::stereo
{
/** The stereo front-end of emslam: turns the observations in a rawlog into
 * StereoFrames. `CObservationStereoImages` are rectified (with cached maps,
 * rebuilt only when the calibration changes) and matched by StereoMatcher;
 * `CObservation3DRangeScan` (RGB-D) are converted directly.
 *
 * **Sparse mode** (`[StereoMatcher] sparse_at_features` and a pixel selector set):
 * process() gives a frame at full resolution whose points are only those of
 * SparseStereoMatcher at the pixels the selector picks in the rectified left
 * image (the egomotion's features), and mapFrameTask() computes the dense
 * cloud of that observation (StereoMatcher at `image_scale`) only when the
 * map takes the frame, possibly on another thread. Dense work is then done
 * once per map frame, off the egomotion's path.
 * \ingroup emslam_stereo_grp */
class StereoFrontEnd
{
public:
    /** Picks, in a rectified 8-bit left image, the pixels that need a point. */
    using PixelSelector = std::function<std::vector<PixelCoord>(const cv::Mat& left_gray)>;

    StereoFrontEnd() = default;
    /** A front-end with the matcher parameters `p` (validated). */
    explicit StereoFrontEnd(const StereoMatcher::TParameters& p);

    /** Turns sparse mode on if the parameters ask for it (no-op otherwise). */
    void setPixelSelector(PixelSelector selector);
    /** True when process() gives sparse frames. */
    bool sparse() const { return m_selector && m_matcher.parameters().sparse_at_features; }

    /** Sparse mode: a task that computes the dense frame (the map's cloud)
     * of the stereo observation behind `processed`, the frame process() just
     * returned. It owns its copy of the rectified pair, so it may run on
     * another thread while process() handles the next observations; one
     * task at a time (they share the dense matcher). Empty (no task) when
     * not in sparse mode or after an RGB-D observation: `processed` is then
     * the map's cloud itself. */
    std::function<StereoFrame()> mapFrameTask(const StereoFrame& processed) const;

    /** The dense matcher. */
    ///@{
    StereoMatcher& matcher() { return m_matcher; }
    const StereoMatcher& matcher() const { return m_matcher; }
    ///@}

    /** Processes one stereo observation. Throws if the right image is missing,
     * the images are empty or their sizes differ from each other or from the
     * calibration. */
    StereoFrame process(const mrpt::obs::CObservationStereoImages& obs);
    /** Processes one RGB-D observation. */
    StereoFrame process(const mrpt::obs::CObservation3DRangeScan& obs);
    /** Dispatches on the observation class; returns false (frame untouched)
     * for classes the front-end does not handle. */
    bool process(const mrpt::obs::CObservation& obs, StereoFrame& frame);

    /** The rectification maps of the last calibration. */
    const StereoRectifier& rectifier() const { return m_rectifier; }

private:
    StereoMatcher m_matcher;
    SparseStereoMatcher m_sparse;
    StereoRectifier m_rectifier;
    PixelSelector m_selector;
    /** Sparse mode: the last rectified pair (owned: never the caller's pixels). */
    cv::Mat m_rect_left, m_rect_right;
};

}  // namespace emslam::stereo
