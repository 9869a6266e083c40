// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/SpaceSampler.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/poses/Lie/SO.h>

#include <cmath>
#include <stdexcept>

namespace emslam::rectify
{
namespace
{
/** Every key of the section, once for load and save. */
void visit(SpaceSampler::TParameters& p, emslam::util::ConfigVisitor& v)
{
    v.field("enabled", p.enabled, "false: every frame joins the trajectory");
    v.field("t_min", p.t_min, "t_min, translation since the last accepted frame [m]");
    v.field("theta_min_deg", p.theta_min_deg, "theta_min, rotation since it [deg]");
}
}  // namespace

void SpaceSampler::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    validate();
}

void SpaceSampler::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void SpaceSampler::TParameters::validate() const
{
    if (!(std::isfinite(t_min) && t_min >= 0))
    {
        throw std::invalid_argument("[SpaceSampler] t_min: must be >= 0");
    }
    if (!(std::isfinite(theta_min_deg) && theta_min_deg >= 0 && theta_min_deg <= 180))
    {
        throw std::invalid_argument("[SpaceSampler] theta_min_deg: must be in [0, 180]");
    }
}

SpaceSampler::SpaceSampler(const TParameters& p) : m_p(p)
{
    m_p.validate();
}

bool SpaceSampler::feed(const mrpt::poses::CPose3D& T_prev_cur)
{
    if (!m_has_reference)
    {
        m_has_reference = true;
        ++m_accepted;
        m_pending = mrpt::poses::CPose3D();
        m_since_accepted = mrpt::poses::CPose3D();
        return true;
    }
    m_pending = m_pending + T_prev_cur;
    const double t = m_pending.translation().norm();
    const double angle = mrpt::poses::Lie::SO<3>::log(m_pending.getRotationMatrix()).norm();
    const bool accept = !m_p.enabled || t > m_p.t_min || angle > mrpt::DEG2RAD(m_p.theta_min_deg);
    if (!accept)
    {
        ++m_rejected;
        return false;
    }
    ++m_accepted;
    m_since_accepted = m_pending;
    m_pending = mrpt::poses::CPose3D();
    return true;
}

void SpaceSampler::reset()
{
    m_has_reference = false;
    m_pending = mrpt::poses::CPose3D();
    m_since_accepted = mrpt::poses::CPose3D();
}

}  // namespace emslam::rectify
