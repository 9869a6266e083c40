// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/stereo/CalibrationReaders.h>
#include <emslam/stereo/RangeScanConversion.h>
#include <emslam/stereo/StereoFrontEnd.h>

#include <mrpt/core/exceptions.h>

namespace emslam::stereo
{
StereoFrame StereoFrontEnd::process(const mrpt::obs::CObservationStereoImages& obs)
{
    const std::string who = "stereo observation '" + obs.sensorLabel + "'";
    ASSERTMSG_(obs.hasImageRight, who + " has no right image");
    const cv::Mat left = obs.imageLeft.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY);
    const cv::Mat right = obs.imageRight.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY);
    ASSERTMSG_(!left.empty() && !right.empty(), who + " has an empty image");
    ASSERTMSG_(
        left.size() == right.size(),
        mrpt::format(
            "%s: left image is %dx%d but right image is %dx%d", who.c_str(), left.cols, left.rows,
            right.cols, right.rows));

    const mrpt::img::TStereoCamera cam = obs.getStereoCameraParams();
    ASSERTMSG_(
        cam.leftCamera.ncols == static_cast<uint32_t>(left.cols) &&
            cam.leftCamera.nrows == static_cast<uint32_t>(left.rows),
        mrpt::format(
            "%s: images are %dx%d but the calibration says %ux%u", who.c_str(), left.cols,
            left.rows, cam.leftCamera.ncols, cam.leftCamera.nrows));
    validateStereoCamera(cam, who + " calibration");

    m_rectifier.setCalibration(cam);
    cv::Mat rl, rr;
    m_rectifier.rectify(left, right, rl, rr);
    StereoFrame f = m_matcher.compute(rl, rr, m_rectifier.rectifiedCamera());
    f.timestamp = obs.timestamp;
    f.sensor_label = obs.sensorLabel;
    return f;
}

StereoFrame StereoFrontEnd::process(const mrpt::obs::CObservation3DRangeScan& obs)
{
    return fromRangeScan(obs);
}

bool StereoFrontEnd::process(const mrpt::obs::CObservation& obs, StereoFrame& frame)
{
    if (const auto* s = dynamic_cast<const mrpt::obs::CObservationStereoImages*>(&obs))
    {
        frame = process(*s);
        return true;
    }
    if (const auto* r = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs))
    {
        frame = process(*r);
        return true;
    }
    return false;
}

}  // namespace emslam::stereo
