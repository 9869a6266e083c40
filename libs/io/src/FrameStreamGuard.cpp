// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/FrameStreamGuard.h>
#include <emslam/io/TumTrajectory.h>
#include <emslam/stereo/StereoCalibration.h>

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationStereoImages.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

namespace emslam::io
{
namespace
{
/** Frame timestamps are UNIX times after 1970-01-01 (0.0 is MRPT's "no
 * timestamp", and what Clock::fromDouble(1e300) stores) and before 2100
 * (fromDouble(NaN) stores year 31198). */
constexpr double END_OF_VALID_STAMPS = 4102444800.0;  // 2100-01-01

/** Values from the same camera are bit-identical; this only absorbs a
 * calibration that went through float once. */
bool close(double a, double b)
{
    return std::abs(a - b) <= 1e-6 * std::max(std::abs(a), std::abs(b));
}

/** `v` for a message, with `digits` significant digits. */
std::string number(double v, int digits = 10)
{
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.*g", digits, v);
    return buf;
}

std::optional<FrameStreamGuard::Camera> stereoCamera(const mrpt::obs::CObservationStereoImages& s)
{
    if (!s.hasImageRight)
    {
        return std::nullopt;
    }
    const mrpt::img::TStereoCamera cam = s.getStereoCameraParams();
    emslam::stereo::validateStereoCamera(cam, "");
    FrameStreamGuard::Camera c;
    c.width = static_cast<std::uint32_t>(s.imageLeft.getWidth());
    c.height = static_cast<std::uint32_t>(s.imageLeft.getHeight());
    if (c.width == 0 || c.height == 0 || cam.leftCamera.ncols != c.width ||
        cam.leftCamera.nrows != c.height)
    {
        return std::nullopt;
    }
    c.fx = cam.leftCamera.fx();
    c.fy = cam.leftCamera.fy();
    c.cx = cam.leftCamera.cx();
    c.cy = cam.leftCamera.cy();
    c.right_fx = cam.rightCamera.fx();
    c.right_fy = cam.rightCamera.fy();
    c.right_cx = cam.rightCamera.cx();
    c.right_cy = cam.rightCamera.cy();
    c.baseline = emslam::stereo::baselineOf(cam);
    return c;
}

std::optional<FrameStreamGuard::Camera> rgbdCamera(const mrpt::obs::CObservation3DRangeScan& r)
{
    if (!r.hasIntensityImage)
    {
        return std::nullopt;
    }
    FrameStreamGuard::Camera c;
    c.rgbd = true;
    c.width = static_cast<std::uint32_t>(r.intensityImage.getWidth());
    c.height = static_cast<std::uint32_t>(r.intensityImage.getHeight());
    const auto& i = r.cameraParamsIntensity;
    const auto& d = r.cameraParams;
    c.fx = i.fx();
    c.fy = i.fy();
    c.cx = i.cx();
    c.cy = i.cy();
    c.right_fx = d.fx();
    c.right_fy = d.fy();
    c.right_cx = d.cx();
    c.right_cy = d.cy();
    for (const double v : {c.fx, c.fy, c.cx, c.cy, c.right_fx, c.right_fy, c.right_cx, c.right_cy})
    {
        if (!std::isfinite(v))
        {
            return std::nullopt;
        }
    }
    if (c.width == 0 || c.height == 0 || !(c.fx > 0) || !(c.fy > 0))
    {
        return std::nullopt;
    }
    return c;
}
}  // namespace

bool FrameStreamGuard::Camera::sameAs(const Camera& o) const
{
    return width == o.width && height == o.height && rgbd == o.rgbd && close(fx, o.fx) &&
           close(fy, o.fy) && close(cx, o.cx) && close(cy, o.cy) && close(right_fx, o.right_fx) &&
           close(right_fy, o.right_fy) && close(right_cx, o.right_cx) &&
           close(right_cy, o.right_cy) && close(baseline, o.baseline);
}

std::string FrameStreamGuard::Camera::toString() const
{
    std::string s = std::to_string(width) + "x" + std::to_string(height) + " (fx " + number(fx) +
                    ", fy " + number(fy) + ", cx " + number(cx) + ", cy " + number(cy);
    if (!close(right_fx, fx) || !close(right_fy, fy) || !close(right_cx, cx) ||
        !close(right_cy, cy))
    {
        const std::string which = rgbd ? "depth" : "right";
        s += "; " + which + " fx " + number(right_fx) + ", fy " + number(right_fy) + ", cx " +
             number(right_cx) + ", cy " + number(right_cy);
    }
    if (!rgbd)
    {
        s += ", baseline " + number(baseline) + " m";
    }
    return s + ")";
}

std::optional<FrameStreamGuard::Camera> FrameStreamGuard::cameraOf(
    const mrpt::obs::CObservation& obs)
{
    try
    {
        if (const auto* s = dynamic_cast<const mrpt::obs::CObservationStereoImages*>(&obs))
        {
            return stereoCamera(*s);
        }
        if (const auto* r = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs))
        {
            return rgbdCamera(*r);
        }
    }
    catch (const std::exception&)
    {
        // An invalid calibration, an external image that cannot be loaded:
        // the front-end refuses the frame with the exact reason.
    }
    return std::nullopt;
}

std::string FrameStreamGuard::invalidStampReason(double t)
{
    if (!std::isfinite(t))
    {
        return "its timestamp " + number(t) + " is not finite";
    }
    if (!(t > 0.0))
    {
        return "its timestamp " + number(t) + " s is not after 1970-01-01";
    }
    if (!(t < END_OF_VALID_STAMPS))
    {
        return "its timestamp " + number(t) + " s is after 2100";
    }
    return {};
}

FrameStreamGuard::Decision FrameStreamGuard::check(
    const mrpt::obs::CObservation& obs, std::size_t record)
{
    const bool frame = dynamic_cast<const mrpt::obs::CObservationStereoImages*>(&obs) != nullptr ||
                       dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs) != nullptr;
    if (!frame)
    {
        m_pending.reset();
        return {};
    }
    const bool unset = obs.timestamp == INVALID_TIMESTAMP;
    return checkFrame(
        unset ? 0.0 : mrpt::Clock::toDouble(obs.timestamp),
        unset ? "its timestamp is INVALID_TIMESTAMP (never set)" : "", cameraOf(obs), record);
}

FrameStreamGuard::Decision FrameStreamGuard::check(
    double stamp, const std::optional<Camera>& camera, std::size_t record)
{
    return checkFrame(stamp, "", camera, record);
}

FrameStreamGuard::Decision FrameStreamGuard::checkFrame(
    double stamp,
    const std::string& stamp_problem,
    const std::optional<Camera>& camera,
    std::size_t record)
{
    m_pending.reset();
    // A new camera is the bigger news: a camera swapped mid-run often restarts its clock too.
    if (camera && m_session && !camera->sameAs(*m_session))
    {
        if (!m_change)
        {
            m_change = CameraChange{record, *m_session, *camera, true, 0, m_accepted};
        }
        if (!m_in_change_run)
        {
            ++m_change->runs;
            m_in_change_run = true;
        }
        return skip(
            Cause::CameraChanged, record,
            "its camera " + camera->toString() + " differs from the session's " +
                m_session->toString());
    }
    const std::string bad = stamp_problem.empty() ? invalidStampReason(stamp) : stamp_problem;
    if (!bad.empty())
    {
        return skip(Cause::BadStamp, record, bad);
    }
    if (m_last_stamp && !(stamp > *m_last_stamp))
    {
        const std::string last = "record " + std::to_string(m_last_record) + "'s";
        return skip(
            Cause::BadStamp, record,
            "its timestamp " + formatTimestamp(stamp) +
                (stamp == *m_last_stamp
                     ? " is the same as " + last
                     : " is " + number(*m_last_stamp - stamp, 6) + " s before " + last) +
                " (the last frame used)");
    }
    m_pending = Pending{stamp, camera, record};
    Decision d;
    d.verdict = Verdict::Use;
    return d;
}

void FrameStreamGuard::accept()
{
    if (!m_pending)
    {
        return;
    }
    m_last_stamp = m_pending->stamp;
    m_last_record = m_pending->record;
    if (!m_session && m_pending->camera)
    {
        m_session = m_pending->camera;
    }
    if (m_change)
    {
        m_change->for_good = false;  // the session's camera came back
    }
    m_in_change_run = false;
    ++m_accepted;
    m_pending.reset();
}

std::string FrameStreamGuard::skipUnusable(std::size_t record, const std::string& reason)
{
    m_pending.reset();
    return skip(Cause::Unusable, record, reason).warning;
}

FrameStreamGuard::Decision FrameStreamGuard::skip(
    Cause cause, std::size_t record, const std::string& what)
{
    std::size_t& n = cause == Cause::BadStamp        ? m_counts.bad_stamps
                     : cause == Cause::CameraChanged ? m_counts.camera_changes
                                                     : m_counts.unusable;
    ++n;
    Decision d;
    d.verdict = Verdict::Skip;
    if (n <= NAMED_PER_CAUSE)
    {
        const std::string named = "record " + std::to_string(record) + ": " + what;
        m_named.push_back(named);
        d.warning = std::string(
                        cause == Cause::Unusable ? "skipping unusable observation at "
                                                 : "skipping frame at ") +
                    named + (n == NAMED_PER_CAUSE ? " (further ones are only counted)" : "");
    }
    return d;
}

std::string FrameStreamGuard::cameraChangeWarning() const
{
    if (!m_change)
    {
        return {};
    }
    const std::string n = std::to_string(m_counts.camera_changes) + " frame" +
                          (m_counts.camera_changes == 1 ? "" : "s") + " skipped: ";
    if (m_change->for_good)
    {
        return n + "camera changed from " + m_change->from.toString() + " to " +
               m_change->to.toString() + " at record " + std::to_string(m_change->record) +
               "; only the " + std::to_string(m_change->used_before) +
               " frames before it were used";
    }
    return n + "their camera differed from the session's " + m_change->from.toString() + " in " +
           std::to_string(m_change->runs) + " run" + (m_change->runs == 1 ? "" : "s") +
           " (the first at record " + std::to_string(m_change->record) + ": " +
           m_change->to.toString() + "); the frames with the session's camera were used";
}

std::string FrameStreamGuard::skippedText() const
{
    const std::size_t total = m_counts.total();
    if (total == 0)
    {
        return {};
    }
    std::string causes;
    const auto add = [&](std::size_t k, const std::string& what)
    {
        if (k > 0)
        {
            causes += (causes.empty() ? "" : ", ") + std::to_string(k) + " " + what;
        }
    };
    add(m_counts.bad_stamps, "with a bad timestamp");
    add(m_counts.camera_changes, "with another camera");
    add(m_counts.unusable, "unusable");
    return std::to_string(total) + " frame" + (total == 1 ? "" : "s") + " skipped (" + causes + ")";
}

}  // namespace emslam::io
