// SPDX-License-Identifier: BSD-3-Clause
#include "GrayImage.h"

#include <emslam/stereo/RangeScanConversion.h>
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/stereo/StereoFrontEnd.h>

#include <mrpt/core/exceptions.h>

namespace emslam::stereo
{
StereoFrontEnd::StereoFrontEnd(const StereoMatcher::TParameters& p)
    : m_matcher(p), m_sparse(SparseStereoMatcher::fromStereo(p))
{
}

void StereoFrontEnd::setPixelSelector(PixelSelector selector)
{
    m_selector = std::move(selector);
}

std::function<StereoFrame()> StereoFrontEnd::mapFrameTask(const StereoFrame& processed) const
{
    if (!sparse() || m_rect_left.empty())
    {
        return {};
    }
    return [matcher = &m_matcher, left = m_rect_left, right = m_rect_right,
            camera = m_rectifier.rectifiedCamera(), timestamp = processed.timestamp,
            label = processed.sensor_label]
    {
        StereoFrame d = matcher->compute(left, right, camera);
        d.timestamp = timestamp;
        d.sensor_label = label;
        return d;
    };
}

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
    m_rect_left.release();
    m_rect_right.release();
    StereoFrame f;
    if (sparse())
    {
        const cv::Mat gl = grayImage(rl), gr = grayImage(rr);
        f = m_sparse.compute(gl, gr, m_rectifier.rectifiedCamera(), m_selector(gl));
        // An already rectified pair shares the observation's pixels, which
        // the caller may reuse before a map-frame task runs.
        m_rect_left = m_rectifier.isIdentity() ? rl.clone() : rl;
        m_rect_right = m_rectifier.isIdentity() ? rr.clone() : rr;
    }
    else
    {
        f = m_matcher.compute(rl, rr, m_rectifier.rectifiedCamera());
    }
    f.timestamp = obs.timestamp;
    f.sensor_label = obs.sensorLabel;
    return f;
}

StereoFrame StereoFrontEnd::process(const mrpt::obs::CObservation3DRangeScan& obs)
{
    m_rect_left.release();
    m_rect_right.release();
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
