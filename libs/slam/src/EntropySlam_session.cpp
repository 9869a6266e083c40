// SPDX-License-Identifier: BSD-3-Clause
// EntropySlam: continuing a saved session, or being localized in it.
#include <emslam/slam/EntropySlam.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <limits>
#include <map>
#include <stdexcept>

namespace emslam::slam
{
namespace
{
/** Localize: the session's frame indices in the loop closer start here,
 * beyond any frame of a run. */
constexpr std::size_t LOCALIZED_SESSION_OFFSET = std::size_t{1} << 40;
/** χ²(6) median: the drift scale of the local misclosures (LoopCloser). */
constexpr double CHI2_6DOF_MEDIAN = 5.348;

double driftScale(std::vector<double> misclosures)
{
    if (misclosures.empty())
    {
        return 1.0;
    }
    const auto mid = misclosures.begin() + static_cast<long>(misclosures.size() / 2);
    std::nth_element(misclosures.begin(), mid, misclosures.end());
    return std::max(1.0, *mid / CHI2_6DOF_MEDIAN);
}
}  // namespace

void EntropySlam::continueSession(std::shared_ptr<const CMapSession> session, SessionUse use)
{
    if (!session)
    {
        throw std::invalid_argument("EntropySlam::continueSession: no session");
    }
    if (!m_records.empty() || m_session)
    {
        throw std::logic_error("EntropySlam::continueSession after process() or twice");
    }
    if (!loopClosing())
    {
        throw std::invalid_argument(
            "a session needs loop closing and rectification ([LoopCloser] enabled = true, "
            "[EntropySlam] egomotion_only = false): its keyframes join the run through the "
            "loop closer's pose graph");
    }
    session->validate();
    const auto& g = session->graph;
    if (g.keyframes.empty())
    {
        throw std::invalid_argument("the session has no keyframe to be located in");
    }
    m_session = std::move(session);
    m_session_use = use;
    m_session_offset = use == SessionUse::Localize ? LOCALIZED_SESSION_OFFSET : 0;
    m_loops.seed(g, m_session_offset, use == SessionUse::Localize);
    std::vector<Relocalizer::Place> places;
    for (std::size_t k = 0; k < g.keyframes.size(); ++k)
    {
        places.push_back(
            {g.keyframes[k].kept, m_session->keyframe_poses[k], g.keyframes[k].covariance});
    }
    Relocalizer::TOptions o;
    o.candidates = static_cast<std::size_t>(m_p.loop_closer.max_candidates);
    o.covariance_scale = driftScale(g.local_misclosures);
    o.max_distance = m_p.loop_closer.max_distance;
    o.max_angle = mrpt::DEG2RAD(m_p.loop_closer.max_angle_deg);
    m_relocalizer = std::make_unique<Relocalizer>(std::move(places), o);
    if (use == SessionUse::Continue)
    {
        // The session's frames come first, as they ended.
        std::map<std::size_t, mrpt::poses::CPose3D> T_world_keyframe;
        for (std::size_t k = 0; k < g.keyframes.size(); ++k)
        {
            T_world_keyframe[g.keyframes[k].frame_index] = m_session->keyframe_poses[k];
        }
        for (std::size_t i = 0; i < m_session->frames.size(); ++i)
        {
            const CMapSession::Frame& f = m_session->frames[i];
            FrameRecord r;
            r.index = i;
            r.timestamp = f.timestamp;
            r.accepted = f.accepted;
            r.egomotion_ok = f.egomotion_ok;
            r.final_matches = f.final_matches;
            m_records.push_back(r);
            m_links.push_back({f.keyframe, f.T_keyframe_frame});
            m_egomotion.push_back({f.timestamp, i, f.egomotion});
            m_online.push_back({f.timestamp, i, f.online});
        }
        m_session_frames = m_session->frames.size();
    }
}

bool EntropySlam::relocalize(FrameRecord& r)
{
    const auto description = m_odometry.estimator().lastDescription();
    const auto& saved = m_session->graph.keyframes.front().kept;
    if (description && !saved.features.empty() &&
        emslam::egomotion::EgomotionEstimator::compact(description, 1).dim != saved.dim)
    {
        throw std::invalid_argument(
            "the session's features are described by " + std::to_string(saved.dim) +
            " values, this configuration's by another number: [EgomotionEstimator] must "
            "describe them as the session's run did (its config is in the session)");
    }
    // Continuing, the run most likely starts where the session stopped.
    std::optional<mrpt::poses::CPose3D> prior;
    if (m_session_use == SessionUse::Continue)
    {
        prior = m_session->keyframe_poses.back();
    }
    const auto fix = m_relocalizer->locate(description, m_loop_estimator, prior);
    if (!fix)
    {
        m_unlocated.push_back(r.index);
        return false;
    }
    // The run's egomotion world into the session's, and the frames before
    // this one with it.
    const mrpt::poses::CPose3D ego_run = m_odometry.pose();
    m_T_session_run = fix->T_world_frame + (mrpt::poses::CPose3D() - ego_run);
    for (const std::size_t i : m_unlocated)
    {
        const mrpt::poses::CPose3D ego_i = m_egomotion[i].T_world_frame;  // run world still
        m_egomotion[i].T_world_frame = m_T_session_run + ego_i;
        m_online[i].T_world_frame = m_egomotion[i].T_world_frame;
        m_links[i] = {r.index, ego_i - ego_run};
    }
    m_egomotion[r.index].T_world_frame = fix->T_world_frame;
    m_relocalization = Relocalization{r.index, m_unlocated.size(), *fix};
    m_unlocated.clear();
    m_relocalizer.reset();
    // In the loop closer the run's first keyframe follows the session's last.
    m_junction =
        std::make_pair(fix->T_world_frame - m_session->keyframe_poses.back(), fix->covariance);
    return true;
}

std::vector<emslam::rectify::TimedPose> EntropySlam::withSessionKeyframes(
    const std::vector<emslam::rectify::TimedPose>& poses) const
{
    const auto& g = m_session->graph;
    std::vector<emslam::rectify::TimedPose> all;
    for (std::size_t k = 0; k < g.keyframes.size(); ++k)
    {
        const std::size_t frame = g.keyframes[k].frame_index;
        all.push_back(
            {m_session->frames[frame].timestamp, m_session_offset + frame,
             m_session->keyframe_poses[k]});
    }
    if (poses.empty() || !m_relocalization)
    {
        return all;
    }
    // The rectifier's world is the run's first keyframe, where it was located.
    const mrpt::poses::CPose3D& located = m_egomotion[poses.front().frame_index].T_world_frame;
    const mrpt::poses::CPose3D T_session_rectified =
        located + (mrpt::poses::CPose3D() - poses.front().T_world_frame);
    for (const auto& p : poses)
    {
        all.push_back({p.timestamp, p.frame_index, T_session_rectified + p.T_world_frame});
    }
    return all;
}

CMapSession::Ptr EntropySlam::session() const
{
    if (!m_finished)
    {
        throw std::logic_error("EntropySlam::session before finish()");
    }
    if (m_session && m_session_use == SessionUse::Localize)
    {
        throw std::logic_error("a run localized in a session does not change it: no session");
    }
    if (!loopClosing() || m_keyframe_slam.empty())
    {
        throw std::logic_error(
            "no session to save: it needs loop closing ([LoopCloser] enabled) and a keyframe");
    }
    auto s = std::make_shared<CMapSession>();
    mrpt::config::CConfigFileMemory ini;
    m_p.saveToConfigFile(ini);
    s->config = ini.getContent();
    for (std::size_t i = 0; i < m_records.size(); ++i)
    {
        CMapSession::Frame f;
        f.timestamp = m_records[i].timestamp;
        f.keyframe = m_links[i].keyframe;
        f.T_keyframe_frame = m_links[i].T_keyframe_frame;
        f.egomotion = m_egomotion[i].T_world_frame;
        f.online = m_online[i].T_world_frame;
        f.accepted = m_records[i].accepted;
        f.egomotion_ok = m_records[i].egomotion_ok;
        f.final_matches = m_records[i].final_matches;
        s->frames.push_back(f);
    }
    s->graph = m_loops.snapshot();
    for (const auto& p : m_keyframe_slam)
    {
        s->keyframe_poses.push_back(p.T_world_frame);
    }
    s->scans = m_keyframe_scans;
    s->validate();
    return s;
}

}  // namespace emslam::slam
