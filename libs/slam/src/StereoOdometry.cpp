// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/StereoOdometry.h>

#include <chrono>

namespace emslam::slam
{
StereoOdometry::StereoOdometry(
    const emslam::stereo::StereoMatcher::TParameters& stereo,
    const emslam::egomotion::EgomotionEstimator::TParameters& egomotion)
    : m_front(stereo), m_estimator(egomotion)
{
    // [StereoMatcher] sparse_at_features: stereo only at the egomotion's features.
    m_front.setPixelSelector([this](const cv::Mat& image)
                             { return m_estimator.locateFeatures(image); });
}

bool StereoOdometry::process(const mrpt::obs::CObservation& obs, Step& step)
{
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    if (!m_front.process(obs, step.frame))
    {
        return false;
    }
    step.ms_stereo = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    step.egomotion = m_estimator.process(step.frame);
    step.first = m_frames == 0;
    step.predicted = false;
    step.action = mrpt::poses::CPose3D();
    if (!step.first)
    {
        m_guided_steps += step.egomotion.ok && step.egomotion.guided;
        m_guided_fallbacks += step.egomotion.guided_fallback;
        if (step.egomotion.ok)
        {
            m_velocity = step.egomotion.T_prev_cur;
        }
        else
        {
            ++m_failures;
            step.predicted = true;
        }
        step.action = m_velocity;
    }
    m_T_world_cur = m_T_world_cur + step.action;
    ++m_frames;
    return true;
}

}  // namespace emslam::slam
