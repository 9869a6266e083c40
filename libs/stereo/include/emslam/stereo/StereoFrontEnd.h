// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/stereo/StereoFrame.h>
#include <emslam/stereo/StereoMatcher.h>
#include <emslam/stereo/StereoRectifier.h>

#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationStereoImages.h>

namespace emslam::stereo
{
/** The stereo front-end of emslam: turns the observations in a rawlog into
 * StereoFrames. `CObservationStereoImages` are rectified (with cached maps,
 * rebuilt only when the calibration changes) and matched by StereoMatcher;
 * `CObservation3DRangeScan` (RGB-D) are converted directly.
 * \ingroup emslam_stereo_grp */
class StereoFrontEnd
{
public:
    StereoFrontEnd() = default;
    explicit StereoFrontEnd(const StereoMatcher::TParameters& p) : m_matcher(p) {}

    StereoMatcher& matcher() { return m_matcher; }
    const StereoMatcher& matcher() const { return m_matcher; }

    /** Processes one stereo observation. Throws if the right image is missing,
     * the images are empty or their sizes differ from each other or from the
     * calibration. */
    StereoFrame process(const mrpt::obs::CObservationStereoImages& obs);
    /** Processes one RGB-D observation. */
    StereoFrame process(const mrpt::obs::CObservation3DRangeScan& obs);
    /** Dispatches on the observation class; returns false (frame untouched)
     * for classes the front-end does not handle. */
    bool process(const mrpt::obs::CObservation& obs, StereoFrame& frame);

    const StereoRectifier& rectifier() const { return m_rectifier; }

private:
    StereoMatcher m_matcher;
    StereoRectifier m_rectifier;
};

}  // namespace emslam::stereo
