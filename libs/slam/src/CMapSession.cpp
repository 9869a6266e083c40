// SPDX-License-Identifier: BSD-3-Clause
// CMapSession: the saved session, its binary layout and its file.
#include <emslam/slam/CMapSession.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

using emslam::slam::CMapSession;

IMPLEMENTS_SERIALIZABLE(CMapSession, mrpt::serialization::CSerializable, emslam::slam)

namespace
{
using emslam::egomotion::EgomotionEstimator;
using mrpt::serialization::CArchive;

/** The format this build writes; older ones it still reads. */
constexpr std::uint8_t SESSION_VERSION = 0;

// Poses as the 12 upper entries of their 4x4 matrix (f64, row major): a
// loaded pose is the saved one to the bit.
void writePose(CArchive& out, const mrpt::poses::CPose3D& p)
{
    const auto T = p.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 4; ++c)
        {
            out << T(r, c);
        }
    }
}

mrpt::poses::CPose3D readPose(CArchive& in)
{
    mrpt::math::CMatrixDouble44 T = mrpt::math::CMatrixDouble44::Identity();
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 4; ++c)
        {
            in >> T(r, c);
        }
    }
    return mrpt::poses::CPose3D(T);
}

template <typename Matrix>
void writeMatrix(CArchive& out, const Matrix& m)
{
    for (int r = 0; r < m.rows(); ++r)
    {
        for (int c = 0; c < m.cols(); ++c)
        {
            out << m(r, c);
        }
    }
}

template <typename Matrix>
void readMatrix(CArchive& in, Matrix& m)
{
    for (int r = 0; r < m.rows(); ++r)
    {
        for (int c = 0; c < m.cols(); ++c)
        {
            in >> m(r, c);
        }
    }
}

void writeCount(CArchive& out, std::size_t n)
{
    out.WriteAs<std::uint64_t>(n);
}

/** A count no larger than `limit` (a corrupt file names absurd ones). */
std::size_t readCount(CArchive& in, std::size_t limit, const char* what)
{
    const auto n = in.ReadAs<std::uint64_t>();
    if (n > limit)
    {
        throw std::runtime_error(
            std::string("corrupt: ") + std::to_string(n) + " " + what + " (at most " +
            std::to_string(limit) + ")");
    }
    return static_cast<std::size_t>(n);
}

constexpr std::size_t MAX_ITEMS = std::size_t{1} << 32;

template <typename T>
void writeArray(CArchive& out, const std::vector<T>& v)
{
    writeCount(out, v.size());
    if (!v.empty())
    {
        out.WriteBufferFixEndianness(v.data(), v.size());
    }
}

template <typename T>
void readArray(CArchive& in, std::vector<T>& v, const char* what)
{
    v.resize(readCount(in, MAX_ITEMS, what));
    if (!v.empty())
    {
        in.ReadBufferFixEndianness(v.data(), v.size());
    }
}

void writeKept(CArchive& out, const EgomotionEstimator::CompactDescription& k)
{
    writeCount(out, k.features.size());
    for (const auto& f : k.features)
    {
        out << f.u << f.v << f.point.x << f.point.y << f.point.z << f.gradient_angle
            << f.gradient_magnitude;
    }
    out.WriteAs<std::int32_t>(k.dim);
    writeArray(out, k.codes);
    writeArray(out, k.scales);
    out << k.camera << k.baseline;
}

void readKept(CArchive& in, EgomotionEstimator::CompactDescription& k)
{
    k.features.resize(readCount(in, MAX_ITEMS, "features"));
    for (auto& f : k.features)
    {
        in >> f.u >> f.v >> f.point.x >> f.point.y >> f.point.z >> f.gradient_angle >>
            f.gradient_magnitude;
    }
    k.dim = in.ReadAs<std::int32_t>();
    readArray(in, k.codes, "descriptor codes");
    readArray(in, k.scales, "descriptor scales");
    in >> k.camera >> k.baseline;
    if (k.dim < 0 || k.codes.size() != k.features.size() * static_cast<std::size_t>(k.dim) ||
        k.scales.size() != k.features.size())
    {
        throw std::runtime_error("corrupt: a kept description's sizes disagree");
    }
}

void writeKeyframe(CArchive& out, const emslam::slam::LoopCloser::Snapshot::Keyframe& k)
{
    writeCount(out, k.frame_index);
    writeKept(out, k.kept);
    writeMatrix(out, k.covariance);
    out << k.motion.has_value();
    if (k.motion)
    {
        writePose(out, *k.motion);
    }
    out << k.predicted << k.vertical.has_value();
    if (k.vertical)
    {
        out << k.vertical->up.x << k.vertical->up.y << k.vertical->up.z;
        writeMatrix(out, k.vertical->covariance);
        writeCount(out, k.vertical->patches);
        out << k.vertical->dispersion;
    }
}

void readKeyframe(CArchive& in, emslam::slam::LoopCloser::Snapshot::Keyframe& k)
{
    k.frame_index = readCount(in, MAX_ITEMS, "frame index");
    readKept(in, k.kept);
    readMatrix(in, k.covariance);
    if (in.ReadAs<bool>())
    {
        k.motion = readPose(in);
    }
    in >> k.predicted;
    if (in.ReadAs<bool>())
    {
        emslam::stereo::VerticalMeasurement v;
        in >> v.up.x >> v.up.y >> v.up.z;
        readMatrix(in, v.covariance);
        v.patches = readCount(in, MAX_ITEMS, "patches");
        in >> v.dispersion;
        k.vertical = v;
    }
}

void writeGraph(CArchive& out, const emslam::slam::LoopCloser::Snapshot& g)
{
    writeCount(out, g.keyframes.size());
    for (std::size_t k = 0; k < g.keyframes.size(); ++k)
    {
        writeKeyframe(out, g.keyframes[k]);
        writePose(out, g.nodes.at(k));
    }
    writeCount(out, g.edges.size());
    for (const auto& e : g.edges)
    {
        writeCount(out, e.from);
        writeCount(out, e.to);
        writePose(out, e.measurement);
        writeMatrix(out, e.information);
        writeCount(out, e.tag);
    }
    writeCount(out, g.loop_edges.size());
    for (const auto& e : g.loop_edges)
    {
        writeCount(out, e.frame_from);
        writeCount(out, e.frame_to);
        writePose(out, e.measurement);
        writeCount(out, e.matches);
    }
    writeCount(out, g.loop_tag);
    writeArray(out, g.local_misclosures);
    out << g.largest_step_t << g.largest_step_r;
}

void readGraph(CArchive& in, emslam::slam::LoopCloser::Snapshot& g)
{
    const std::size_t n = readCount(in, MAX_ITEMS, "keyframes");
    g.keyframes.resize(n);
    g.nodes.resize(n);
    for (std::size_t k = 0; k < n; ++k)
    {
        readKeyframe(in, g.keyframes[k]);
        g.nodes[k] = readPose(in);
    }
    g.edges.resize(readCount(in, MAX_ITEMS, "graph edges"));
    for (auto& e : g.edges)
    {
        e.from = readCount(in, MAX_ITEMS, "node index");
        e.to = readCount(in, MAX_ITEMS, "node index");
        e.measurement = readPose(in);
        readMatrix(in, e.information);
        e.tag = readCount(in, MAX_ITEMS, "edge tag");
    }
    g.loop_edges.resize(readCount(in, MAX_ITEMS, "loop edges"));
    for (auto& e : g.loop_edges)
    {
        e.frame_from = readCount(in, MAX_ITEMS, "frame index");
        e.frame_to = readCount(in, MAX_ITEMS, "frame index");
        e.measurement = readPose(in);
        e.matches = readCount(in, MAX_ITEMS, "matches");
    }
    g.loop_tag = readCount(in, MAX_ITEMS, "loop tag");
    readArray(in, g.local_misclosures, "misclosures");
    in >> g.largest_step_t >> g.largest_step_r;
}
}  // namespace

uint8_t CMapSession::serializeGetVersion() const
{
    return SESSION_VERSION;
}

// Version 0: config (string); frames (u64 count; per frame timestamp f64,
// keyframe u64, T_keyframe_frame, egomotion and online poses, accepted,
// egomotion_ok, final_matches u64); the graph (writeGraph); the keyframes'
// world poses; the scans (frame u64, points as x y z f32 arrays, grey levels
// u8, sigmas f32). Poses are 12 f64 (writePose), counts u64.
void CMapSession::serializeTo(mrpt::serialization::CArchive& out) const
{
    validate();
    out << config;
    writeCount(out, frames.size());
    for (const auto& f : frames)
    {
        out << f.timestamp;
        writeCount(out, f.keyframe);
        writePose(out, f.T_keyframe_frame);
        writePose(out, f.egomotion);
        writePose(out, f.online);
        out << f.accepted << f.egomotion_ok;
        writeCount(out, f.final_matches);
    }
    writeGraph(out, graph);
    writeCount(out, keyframe_poses.size());
    for (const auto& p : keyframe_poses)
    {
        writePose(out, p);
    }
    writeCount(out, scans.size());
    for (const auto& s : scans)
    {
        writeCount(out, s.frame_index);
        std::vector<float> xyz;
        xyz.reserve(3 * s.cloud.size());
        for (const auto& p : s.cloud.points)
        {
            xyz.insert(xyz.end(), {p.x, p.y, p.z});
        }
        writeArray(out, xyz);
        writeArray(out, s.cloud.intensity);
        writeArray(out, s.cloud.sigma);
    }
}

void CMapSession::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    if (version > SESSION_VERSION)
    {
        throw std::runtime_error(
            "written by a newer emslam (session format " + std::to_string(version) +
            "; this one reads up to " + std::to_string(SESSION_VERSION) + ")");
    }
    *this = CMapSession();
    in >> config;
    frames.resize(readCount(in, MAX_ITEMS, "frames"));
    for (auto& f : frames)
    {
        in >> f.timestamp;
        f.keyframe = readCount(in, MAX_ITEMS, "keyframe index");
        f.T_keyframe_frame = readPose(in);
        f.egomotion = readPose(in);
        f.online = readPose(in);
        in >> f.accepted >> f.egomotion_ok;
        f.final_matches = readCount(in, MAX_ITEMS, "matches");
    }
    readGraph(in, graph);
    keyframe_poses.resize(readCount(in, MAX_ITEMS, "keyframe poses"));
    for (auto& p : keyframe_poses)
    {
        p = readPose(in);
    }
    scans.resize(readCount(in, MAX_ITEMS, "scans"));
    for (auto& s : scans)
    {
        s.frame_index = readCount(in, MAX_ITEMS, "frame index");
        std::vector<float> xyz;
        readArray(in, xyz, "coordinates");
        readArray(in, s.cloud.intensity, "grey levels");
        readArray(in, s.cloud.sigma, "sigmas");
        if (xyz.size() % 3 != 0 || s.cloud.intensity.size() != xyz.size() / 3 ||
            (!s.cloud.sigma.empty() && s.cloud.sigma.size() != xyz.size() / 3))
        {
            throw std::runtime_error("corrupt: a scan's sizes disagree");
        }
        s.cloud.points.resize(xyz.size() / 3);
        for (std::size_t i = 0; i < s.cloud.points.size(); ++i)
        {
            s.cloud.points[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
        }
    }
    validate();
}

void CMapSession::validate() const
{
    const auto bad = [](const std::string& what)
    { throw std::runtime_error("inconsistent session: " + what); };
    const std::size_t n = frames.size();
    for (std::size_t i = 0; i < n; ++i)
    {
        if (!(frames[i].keyframe < n))
        {
            bad("frame " + std::to_string(i) + " is placed from frame " +
                std::to_string(frames[i].keyframe) + " of " + std::to_string(n));
        }
    }
    const std::size_t k = graph.keyframes.size();
    if (graph.nodes.size() != k || keyframe_poses.size() != k)
    {
        bad(std::to_string(k) + " keyframes, " + std::to_string(graph.nodes.size()) +
            " graph poses and " + std::to_string(keyframe_poses.size()) + " world poses");
    }
    for (std::size_t j = 0; j < k; ++j)
    {
        const std::size_t f = graph.keyframes[j].frame_index;
        if (f >= n || (j > 0 && f <= graph.keyframes[j - 1].frame_index))
        {
            bad("keyframe " + std::to_string(j) + " is frame " + std::to_string(f) +
                " (frames: " + std::to_string(n) + ", increasing)");
        }
    }
    for (const auto& e : graph.edges)
    {
        if (e.from >= k || e.to >= k || e.from == e.to)
        {
            bad("a graph edge joins " + std::to_string(e.from) + " and " + std::to_string(e.to));
        }
    }
    for (const auto& s : scans)
    {
        if (s.frame_index >= n)
        {
            bad("a map cloud of frame " + std::to_string(s.frame_index));
        }
    }
}

void CMapSession::save(const std::string& file) const
{
    validate();
    // Through a temporary name: a failed save leaves the former file whole.
    const std::string tmp = file + ".part";
    try
    {
        mrpt::io::CFileGZOutputStream f;
        if (!f.open(tmp))
        {
            throw std::runtime_error("cannot write the session file '" + tmp + "'");
        }
        auto out = mrpt::serialization::archiveFrom(f);
        out << *this;
        f.close();
    }
    catch (...)
    {
        std::remove(tmp.c_str());
        throw;
    }
    if (std::rename(tmp.c_str(), file.c_str()) != 0)
    {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write the session file '" + file + "'");
    }
}

CMapSession::Ptr CMapSession::load(const std::string& file)
{
    mrpt::io::CFileGZInputStream f;
    if (!std::ifstream(file).good() || !f.open(file))
    {
        throw std::runtime_error("cannot open the session file '" + file + "'");
    }
    mrpt::serialization::CSerializable::Ptr obj;
    try
    {
        auto in = mrpt::serialization::archiveFrom(f);
        obj = in.ReadObject();
    }
    catch (const std::exception& e)
    {
        const std::string why = emslam::util::shortExceptionMessage(e);
        throw std::runtime_error("'" + file + "' is not a readable emslam session (" + why + ")");
    }
    auto session = std::dynamic_pointer_cast<CMapSession>(obj);
    if (!session)
    {
        throw std::runtime_error(
            "'" + file + "' holds an MRPT " + (obj ? obj->GetRuntimeClass()->className : "null") +
            ", not an emslam session (emslam-mapper --save-session writes one)");
    }
    return session;
}
