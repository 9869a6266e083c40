// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/sim/Trajectory.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/CVectorFixed.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace emslam::sim
{
namespace
{
constexpr const char* SECTION = "Trajectory";

[[noreturn]] void bad(const std::string& key, const std::string& msg)
{
    throw std::invalid_argument(std::string("[") + SECTION + "] " + key + ": " + msg);
}

std::vector<std::array<double, 3>> parseWaypoints(const std::string& txt)
{
    std::vector<std::array<double, 3>> pts;
    std::stringstream all(txt);
    std::string item;
    int dims = -1;
    while (std::getline(all, item, ';'))
    {
        std::istringstream in(item);
        std::vector<double> v;
        double x = 0;
        while (in >> x)
        {
            v.push_back(x);
        }
        in.clear();
        std::string rest;
        if ((in >> rest) || (v.size() != 2 && v.size() != 3))
        {
            if (v.empty() && rest.empty())
            {
                continue;  // empty item (trailing ';')
            }
            bad("waypoints", "each way-point is 'x z' or 'x y z', got '" + item + "'");
        }
        if (dims >= 0 && static_cast<int>(v.size()) != dims)
        {
            bad("waypoints", "mixes 2D and 3D way-points");
        }
        dims = static_cast<int>(v.size());
        pts.push_back(
            v.size() == 2 ? std::array<double, 3>{v[0], 0.0, v[1]}
                          : std::array<double, 3>{v[0], v[1], v[2]});
    }
    return pts;
}

/** Throws std::invalid_argument naming the first key out of range. */
void checkParameters(const Trajectory::TParameters& p)
{
    if (p.type != "robot3dof" && p.type != "walker6dof")
    {
        bad("type", "unknown trajectory type '" + p.type + "' (expected robot3dof or walker6dof)");
    }
    if (p.drive != "differential" && p.drive != "holonomic")
    {
        bad("drive", "expected differential or holonomic, got '" + p.drive + "'");
    }
    if (!(p.speed > 0))
    {
        bad("speed", "must be > 0");
    }
    if (!(p.angular_speed_deg > 0))
    {
        bad("angular_speed_deg", "must be > 0");
    }
    if (!(p.turn_blend >= 0))
    {
        bad("turn_blend", "must be >= 0");
    }
    // The path is unrolled loop by loop: a bound keeps it in memory.
    if (p.loops < 1 || p.loops > 1000)
    {
        bad("loops", "must be in 1..1000 (got " + std::to_string(p.loops) + ")");
    }
    const auto inRange = [](double v, double lo, double hi) { return v >= lo && v <= hi; };
    if (!inRange(p.speed, 0, 1000) || !inRange(p.angular_speed_deg, 0, 36000) ||
        !inRange(p.turn_blend, 0, 1e4))
    {
        bad(!inRange(p.speed, 0, 1000)                ? "speed"
            : !inRange(p.angular_speed_deg, 0, 36000) ? "angular_speed_deg"
                                                      : "turn_blend",
            "out of range: speed (0, 1000] m/s, angular_speed_deg (0, 36000], turn_blend [0, 1e4] "
            "m");
    }
    if (!inRange(p.step_frequency, 0, 100))
    {
        bad("step_frequency",
            "must be in [0, 100] Hz (got " + std::to_string(p.step_frequency) + ")");
    }
    if (!inRange(p.camera_height, -1e4, 1e4))
    {
        bad("camera_height",
            "must be in [-1e4, 1e4] m (got " + std::to_string(p.camera_height) + ")");
    }
    if (!inRange(p.bob_amplitude, 0, 100))
    {
        bad("bob_amplitude", "must be in [0, 100] m (got " + std::to_string(p.bob_amplitude) + ")");
    }
    if (!inRange(p.sway_roll_deg, -90, 90) || !inRange(p.sway_pitch_deg, -90, 90))
    {
        bad(inRange(p.sway_roll_deg, -90, 90) ? "sway_pitch_deg" : "sway_roll_deg",
            "must be in [-90, 90] deg");
    }
}

/** The way-points, checked: at least two, planar for a robot. */
std::vector<std::array<double, 3>> checkedWaypoints(const Trajectory::TParameters& p)
{
    auto pts = parseWaypoints(p.waypoints);
    if (pts.empty())
    {
        bad("waypoints", "the way-point list is empty");
    }
    if (pts.size() < 2)
    {
        bad("waypoints", "needs at least two way-points");
    }
    if (p.type == "robot3dof")
    {
        for (auto& q : pts)
        {
            if (q[1] != 0.0)
            {
                bad("waypoints", "robot3dof is planar: give 'x z' way-points");
            }
        }
    }
    return pts;
}
}  // namespace

namespace
{
/** Every key of the section, once for load and save. */
void visit(Trajectory::TParameters& p, emslam::util::ConfigVisitor& v)
{
    v.field("type", p.type);
    v.field("waypoints", p.waypoints);
    v.field("closed", p.closed);
    v.field("loops", p.loops);
    v.field("speed", p.speed);
    v.field("angular_speed_deg", p.angular_speed_deg);
    v.field("drive", p.drive);
    v.field("turn_blend", p.turn_blend);
    v.field("camera_height", p.camera_height);
    v.field("follow_ground", p.follow_ground);
    v.field("bob_amplitude", p.bob_amplitude);
    v.field("step_frequency", p.step_frequency);
    v.field("sway_roll_deg", p.sway_roll_deg);
    v.field("sway_pitch_deg", p.sway_pitch_deg);
}
}  // namespace

void Trajectory::TParameters::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
}

void Trajectory::TParameters::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
}

void Trajectory::setup(const TParameters& p)
{
    checkParameters(p);
    const auto pts = checkedWaypoints(p);
    if (p.loops > 1 && !p.closed)
    {
        bad("loops", "loops > 1 needs closed = true");
    }
    m_p = p;
    m_pts.clear();
    for (int l = 0; l < p.loops; ++l)
    {
        for (std::size_t i = 0; i < pts.size(); ++i)
        {
            if (l > 0 && i == 0)
            {
                continue;  // the loop's start equals the previous loop's end
            }
            m_pts.push_back(pts[i]);
        }
        if (p.closed)
        {
            m_pts.push_back(pts[0]);
        }
    }
    // Drop repeated points.
    m_pts.erase(
        std::unique(
            m_pts.begin(), m_pts.end(),
            [](const auto& a, const auto& b)
            { return std::hypot(a[0] - b[0], a[2] - b[2]) < 1e-9 && a[1] == b[1]; }),
        m_pts.end());
    if (m_pts.size() < 2)
    {
        bad("waypoints", "needs at least two distinct way-points");
    }

    buildSegments();
}

void Trajectory::buildSegments()
{
    const auto& p = m_p;
    const bool differential = p.type == "robot3dof" && p.drive == "differential";
    const double omega = p.angular_speed_deg * M_PI / 180.0;
    m_segments.clear();
    m_corner_s.clear();
    m_corner_dyaw.clear();
    double t = 0;
    double s = 0;
    double yaw_prev = 0;
    for (std::size_t i = 0; i + 1 < m_pts.size(); ++i)
    {
        const auto& a = m_pts[i];
        const auto& b = m_pts[i + 1];
        const double len = std::hypot(b[0] - a[0], b[2] - a[2]);
        if (len < 1e-9)
        {
            bad("waypoints", "two consecutive way-points differ only in height");
        }
        const double yaw = std::atan2(b[0] - a[0], b[2] - a[2]);
        if (i > 0)
        {
            const double dyaw = mrpt::math::wrapToPi(yaw - yaw_prev);
            m_corner_s.push_back(s);
            m_corner_dyaw.push_back(dyaw);
            if (differential && std::abs(dyaw) > 1e-9)
            {
                const double dt = std::abs(dyaw) / omega;
                m_segments.push_back({t, t + dt, a, a, yaw_prev, yaw_prev + dyaw, s});
                t += dt;
            }
        }
        const double y0 = i == 0 ? yaw : m_segments.back().yaw1;
        const double y1 = y0 + mrpt::math::wrapToPi(yaw - y0);
        m_segments.push_back({t, t + len / p.speed, a, b, y1, y1, s});
        t += len / p.speed;
        s += len;
        yaw_prev = y1;
    }
    if (p.closed && differential)
    {
        // A closed loop ends where it started, also in heading: the robot
        // turns on the spot back to its initial heading, so that the first and
        // last poses coincide exactly (what loop-closure tests measure).
        const double dyaw = mrpt::math::wrapToPi(m_segments.front().yaw0 - yaw_prev);
        if (std::abs(dyaw) > 1e-9)
        {
            const auto& e = m_pts.back();
            m_segments.push_back(
                {t, t + std::abs(dyaw) / omega, e, e, yaw_prev, yaw_prev + dyaw, s});
        }
    }
}

std::vector<std::array<double, 2>> Trajectory::waypointsXZ() const
{
    std::vector<std::array<double, 2>> v;
    for (const auto& q : m_pts)
    {
        v.push_back({q[0], q[2]});
    }
    return v;
}

double Trajectory::duration() const
{
    return m_segments.empty() ? 0.0 : m_segments.back().t1;
}

mrpt::poses::CPose3D Trajectory::cameraPose(double t, const World* world) const
{
    if (m_segments.empty())
    {
        throw std::logic_error("Trajectory::cameraPose: call setup() first");
    }
    t = std::clamp(t, 0.0, duration());
    std::size_t k = 0;
    while (k + 1 < m_segments.size() && t > m_segments[k].t1)
    {
        ++k;
    }
    const Segment& g = m_segments[k];
    const double a = g.t1 > g.t0 ? (t - g.t0) / (g.t1 - g.t0) : 0.0;
    std::array<double, 3> p{};
    for (std::size_t i = 0; i < 3; ++i)
    {
        p[i] = g.p0[i] + a * (g.p1[i] - g.p0[i]);
    }
    double yaw = g.yaw0 + a * (g.yaw1 - g.yaw0);
    const bool differential = m_p.type == "robot3dof" && m_p.drive == "differential";
    if (!differential && m_p.turn_blend > 0)
    {
        // Heading blends linearly across each corner over turn_blend metres of path.
        const double s = g.s0 + a * std::hypot(g.p1[0] - g.p0[0], g.p1[2] - g.p0[2]);
        yaw = m_segments.front().yaw0;
        for (std::size_t c = 0; c < m_corner_s.size(); ++c)
        {
            const double f =
                std::clamp((s - (m_corner_s[c] - m_p.turn_blend / 2)) / m_p.turn_blend, 0.0, 1.0);
            yaw += f * m_corner_dyaw[c];
        }
    }
    double height = p[1] + m_p.camera_height;
    if (m_p.follow_ground && world != nullptr)
    {
        double g_sum = 0;
        const double r = 0.5;
        const double off[5][2] = {{0, 0}, {r, 0}, {-r, 0}, {0, r}, {0, -r}};
        for (const auto& o : off)
        {
            g_sum += world->groundHeight(p[0] + o[0], p[2] + o[1]);
        }
        height += g_sum / 5;
    }
    double pitch = 0;
    double roll = 0;
    if (m_p.type == "walker6dof")
    {
        // A closed walk starts and ends standing still: the gait fades in over
        // the first second and out over the last, so the first and last poses
        // coincide (what loop-closure measures need).
        double gait = 1.0;
        if (m_p.closed)
        {
            const double x = std::clamp(std::min(t, duration() - t), 0.0, 1.0);
            gait = x * x * (3 - 2 * x);
        }
        const double ph = 2 * M_PI * m_p.step_frequency * t;
        height += gait * m_p.bob_amplitude * std::cos(ph);
        roll = gait * m_p.sway_roll_deg * M_PI / 180.0 * std::sin(ph / 2);
        pitch = gait * m_p.sway_pitch_deg * M_PI / 180.0 * std::sin(ph + 0.7);
    }
    // Camera axes in the scene: x right, y down, z forward (yaw about scene +Y).
    const double cy = std::cos(yaw);
    const double sy = std::sin(yaw);
    mrpt::math::CMatrixDouble33 R_yaw;
    R_yaw(0, 0) = -cy;
    R_yaw(1, 0) = 0;
    R_yaw(2, 0) = sy;
    R_yaw(0, 1) = 0;
    R_yaw(1, 1) = -1;
    R_yaw(2, 1) = 0;
    R_yaw(0, 2) = sy;
    R_yaw(1, 2) = 0;
    R_yaw(2, 2) = cy;
    mrpt::math::CMatrixDouble33 Rx;
    Rx.setIdentity();
    Rx(1, 1) = std::cos(pitch);
    Rx(1, 2) = -std::sin(pitch);
    Rx(2, 1) = std::sin(pitch);
    Rx(2, 2) = std::cos(pitch);
    mrpt::math::CMatrixDouble33 Rz;
    Rz.setIdentity();
    Rz(0, 0) = std::cos(roll);
    Rz(0, 1) = -std::sin(roll);
    Rz(1, 0) = std::sin(roll);
    Rz(1, 1) = std::cos(roll);
    const mrpt::math::CMatrixDouble33 R = R_yaw * Rx * Rz;
    mrpt::math::CVectorFixedDouble<3> xyz;
    xyz[0] = p[0];
    xyz[1] = height;
    xyz[2] = p[2];
    return mrpt::poses::CPose3D::FromRotationAndTranslation(R, xyz);
}

}  // namespace emslam::sim
