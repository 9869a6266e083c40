// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/EnergyScanOutputs.h>
#include <emslam/io/AtomicTextFile.h>
#include <emslam/io/Json.h>

#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace emslam::apps
{
namespace
{
using emslam::rectify::EnergyScanLine;

/** Offsets and their derivatives in the CSV's and JSON's units: m, deg. */
double toUnit(bool rotation, double v)
{
    return rotation ? mrpt::RAD2DEG(v) : v;
}

std::string number(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.9g", v);
    return buf;
}
}  // namespace

MapperEnergyScan scanMapperEnergy(
    const slam::EntropySlam& m, const emslam::rectify::FramePoseLookup& T_world_frame)
{
    const auto& t = m.trajectory();
    MapperEnergyScan s;
    const auto truth = emslam::rectify::elementPosesAt(t, T_world_frame);
    s.scan = emslam::rectify::scanEnergy(t, truth);
    const int phases = s.scan.summary.grid_phases;
    const auto& ego = m.egomotionPoses();
    const auto egomotion =
        emslam::rectify::elementPosesAt(t, [&](std::size_t i) { return ego.at(i).T_world_frame; });
    s.entropy_egomotion = emslam::rectify::entropyAtElementPoses(t, egomotion, phases);
    std::vector<mrpt::poses::CPose3D> slam;
    for (std::size_t i = 0; i < t.size(); ++i)
    {
        slam.push_back(t.pose(i));
    }
    s.entropy_slam = emslam::rectify::entropyAtElementPoses(t, slam, phases);
    s.prior_truth = emslam::rectify::priorAtElementPoses(t, truth);
    s.prior_egomotion = emslam::rectify::priorAtElementPoses(t, egomotion);
    s.prior_slam = emslam::rectify::priorAtElementPoses(t, slam);
    return s;
}

emslam::rectify::FramePoseLookup groundTruthFramePoses(
    const slam::EntropySlam& m, const emslam::io::TumTrajectory& ground_truth, double max_dt)
{
    const auto& frames = m.egomotionPoses();  // one per frame, with its timestamp
    const auto nearest = [&](std::size_t i)
    {
        if (i >= frames.size())
        {
            throw std::out_of_range("groundTruthFramePoses: no frame " + std::to_string(i));
        }
        const double t = frames[i].timestamp;
        const auto it = std::min_element(
            ground_truth.poses.begin(), ground_truth.poses.end(),
            [t](const auto& a, const auto& b) { return std::abs(a.t - t) < std::abs(b.t - t); });
        if (it == ground_truth.poses.end() || !(std::abs(it->t - t) <= max_dt))
        {
            char buf[160];
            std::snprintf(
                buf, sizeof(buf), "frame %zu (t = %.6f s) has no ground-truth pose within %g s", i,
                t, max_dt);
            throw std::runtime_error(
                std::string("--energy-scan: ") + buf + " in the --gt trajectory");
        }
        return it->pose;
    };
    const mrpt::poses::CPose3D T_map_gt = -nearest(0);
    return [=](std::size_t i) { return T_map_gt + nearest(i); };
}

void writeEnergyScanCsv(const emslam::rectify::EnergyScan& scan, const std::string& file)
{
    std::size_t steps = 0;
    for (const EnergyScanLine& l : scan.lines)
    {
        steps = std::max(steps, l.offsets.size() / 2);
    }
    io::AtomicTextFile f(file);
    auto& o = f.stream();
    o << "action,elements_moved,dimension,unit,step,energy_at_truth,argmin_offset,"
         "min_minus_truth,truth_is_min,curvature,slope";
    for (std::size_t j = steps; j >= 1; --j)
    {
        o << ",dE_-" << j;
    }
    for (std::size_t j = 1; j <= steps; ++j)
    {
        o << ",dE_+" << j;
    }
    o << '\n';
    for (const EnergyScanLine& l : scan.lines)
    {
        const bool rot = l.isRotation();
        const std::size_t k = l.offsets.size() / 2;  // index of offset 0
        const double step = toUnit(rot, l.offsets[k + 1]);
        o << l.action << ',' << scan.summary.elements - l.action << ','
          << emslam::rectify::actionDimensionName(l.dimension) << ',' << (rot ? "deg" : "m") << ','
          << number(step) << ',' << number(l.energy_at_truth) << ','
          << number(toUnit(rot, l.argmin_offset)) << ',' << number(l.min_energy - l.energy_at_truth)
          << ',' << (l.truthIsMinimum() ? 1 : 0) << ','
          << number(l.curvature / (toUnit(rot, 1.0) * toUnit(rot, 1.0))) << ','
          << number(l.slope / toUnit(rot, 1.0));
        // Empty cells first on the negative side, so dE_±j line up across lines.
        for (std::size_t j = steps; j >= 1; --j)
        {
            o << ',';
            if (j <= k)
            {
                o << number(l.energies[k - j] - l.energy_at_truth);
            }
        }
        for (std::size_t j = 1; j <= steps; ++j)
        {
            o << ',';
            if (j <= k)
            {
                o << number(l.energies[k + j] - l.energy_at_truth);
            }
        }
        o << '\n';
    }
    f.commit();
}

std::string energyScanJson(const MapperEnergyScan& m)
{
    const emslam::rectify::EnergyScanSummary& s = m.scan.summary;
    std::ostringstream j;
    j << "{\"lines\": " << s.lines << ", \"lines_at_truth\": " << s.lines_at_truth
      << ", \"elements\": " << s.elements << ", \"evaluations\": " << s.evaluations
      << ", \"grid_phases\": " << s.grid_phases
      << ", \"energy_at_truth\": " << io::jsonNumber(s.energy_at_truth)
      << ", \"energy_at_egomotion\": " << io::jsonNumber(m.entropy_egomotion)
      << ", \"energy_at_slam\": " << io::jsonNumber(m.entropy_slam)
      << ", \"prior_at_truth\": " << io::jsonNumber(m.prior_truth)
      << ", \"prior_at_egomotion\": " << io::jsonNumber(m.prior_egomotion)
      << ", \"prior_at_slam\": " << io::jsonNumber(m.prior_slam)
      << ", \"fraction_at_truth\": " << io::jsonNumber(s.fraction_at_truth)
      << ", \"median_abs_argmin_translation_m\": "
      << io::jsonNumber(s.median_abs_argmin_translation_m)
      << ", \"median_abs_argmin_rotation_deg\": "
      << io::jsonNumber(mrpt::RAD2DEG(s.median_abs_argmin_rotation_rad))
      << ", \"seconds\": " << io::jsonNumber(s.seconds) << ", \"dimensions\": {";
    bool first = true;
    for (const auto& d : s.dimensions)
    {
        const bool rot = d.dimension >= 3;
        const double unit = toUnit(rot, 1.0);
        j << (first ? "" : ", ")
          << io::jsonString(emslam::rectify::actionDimensionName(d.dimension))
          << ": {\"unit\": " << io::jsonString(rot ? "deg" : "m") << ", \"lines\": " << d.lines
          << ", \"fraction_at_truth\": " << io::jsonNumber(d.fraction_at_truth)
          << ", \"median_abs_argmin\": " << io::jsonNumber(toUnit(rot, d.median_abs_argmin))
          << ", \"median_curvature\": " << io::jsonNumber(d.median_curvature / (unit * unit))
          << '}';
        first = false;
    }
    j << "}}";
    return j.str();
}

}  // namespace emslam::apps
