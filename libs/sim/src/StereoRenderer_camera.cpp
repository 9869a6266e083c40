// SPDX-License-Identifier: BSD-3-Clause
// StereoRenderer: the [Camera] parameters, their checks, and the calibration
// of the rendered pair.
#include <emslam/sim/StereoRenderer.h>
#include <emslam/util/ConfigVisitor.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace emslam::sim
{
namespace
{
constexpr const char* SECTION = "Camera";

[[noreturn]] void bad(const std::string& key, const std::string& msg)
{
    throw std::invalid_argument(std::string("[") + SECTION + "] " + key + ": " + msg);
}
}  // namespace

namespace
{
/** Every key of the section, once for load and save. */
void visit(StereoRenderer::TParameters& p, emslam::util::ConfigVisitor& v)
{
    v.field("width", p.width);
    v.field("height", p.height);
    v.field("focal_px", p.focal_px);
    v.field("cx", p.cx);
    v.field("cy", p.cy);
    v.field("baseline", p.baseline);
    v.field("supersampling", p.supersampling);
    v.field("noise_sigma", p.noise_sigma);
    v.field("max_range", p.max_range);
}
}  // namespace

void StereoRenderer::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    validate();
}

void StereoRenderer::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void StereoRenderer::TParameters::validate() const
{
    if (width < 8 || width > 8192)
    {
        bad("width", "must be in 8..8192 (got " + std::to_string(width) + ")");
    }
    if (height < 8 || height > 8192)
    {
        bad("height", "must be in 8..8192 (got " + std::to_string(height) + ")");
    }
    if (!(focal_px > 0 && focal_px <= 1e6))
    {
        bad("focal_px", "must be in (0, 1e6] (got " + std::to_string(focal_px) + ")");
    }
    // < 0: the image centre.
    if (!(std::abs(cx) <= 1e6) || !(std::abs(cy) <= 1e6))
    {
        bad(std::abs(cx) <= 1e6 ? "cy" : "cx", "must be in [-1e6, 1e6] px (< 0: image centre)");
    }
    if (!(baseline > 0 && baseline <= 1000))
    {
        bad("baseline", "must be in (0, 1000] m (got " + std::to_string(baseline) + ")");
    }
    if (supersampling < 1 || supersampling > 4)
    {
        bad("supersampling", "must be in 1..4 (got " + std::to_string(supersampling) + ")");
    }
    if (!(noise_sigma >= 0 && noise_sigma <= 255))
    {
        bad("noise_sigma", "must be in [0, 255] (got " + std::to_string(noise_sigma) + ")");
    }
    if (!(max_range > 0 && max_range <= 1e6))
    {
        bad("max_range", "must be in (0, 1e6] m (got " + std::to_string(max_range) + ")");
    }
}

void StereoRenderer::setParameters(const TParameters& p)
{
    p.validate();
    m_p = p;
}

mrpt::img::TStereoCamera StereoRenderer::stereoCamera() const
{
    mrpt::img::TStereoCamera c;
    const double cx = m_p.cx >= 0 ? m_p.cx : (m_p.width - 1) / 2.0;
    const double cy = m_p.cy >= 0 ? m_p.cy : (m_p.height - 1) / 2.0;
    for (auto* cam : {&c.leftCamera, &c.rightCamera})
    {
        cam->ncols = static_cast<uint32_t>(m_p.width);
        cam->nrows = static_cast<uint32_t>(m_p.height);
        cam->setIntrinsicParamsFromValues(m_p.focal_px, m_p.focal_px, cx, cy);
        cam->distortion = mrpt::img::DistortionModel::none;
        cam->dist.fill(0);
    }
    c.leftCamera.cameraName = "left";
    c.rightCamera.cameraName = "right";
    c.rightCameraPose = mrpt::math::TPose3DQuat(m_p.baseline, 0, 0, 1, 0, 0, 0);
    return c;
}

}  // namespace emslam::sim
