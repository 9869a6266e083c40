// SPDX-License-Identifier: BSD-3-Clause
#include "SimulatedDrive.h"

#include <emslam/rectify/Action.h>
#include <emslam/sim/StereoSimulator.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/io/vector_loadsave.h>
#include <mrpt/poses/Lie/SO.h>

#include <TestData.h>

#include <cmath>
#include <random>

namespace emslam::test
{
std::vector<DrivenFrame> driveWorld(const std::string& world_ini, const DriveOptions& o)
{
    mrpt::config::CConfigFileMemory cfg(mrpt::io::file_get_contents(sourceDir() + "/" + world_ini));
    cfg.write("Camera", "width", o.width);
    cfg.write("Camera", "height", o.height);
    cfg.write("Camera", "focal_px", o.focal_px);
    emslam::sim::StereoSimulator sim;
    sim.load(cfg);

    std::mt19937_64 rng(o.seed);
    std::normal_distribution<double> gauss(0.0, 1.0);
    const double cx = (o.width - 1) / 2.0, cy = (o.height - 1) / 2.0;

    std::vector<DrivenFrame> out;
    mrpt::poses::CPose3D last_accepted_true;
    const std::size_t n =
        o.max_frames > 0 ? std::min(o.max_frames, sim.frameCount()) : sim.frameCount();
    for (std::size_t i = 0; i < n; ++i)
    {
        const mrpt::poses::CPose3D T = sim.groundTruth(i);
        const mrpt::poses::CPose3D a_true = T - last_accepted_true;
        const double angle = mrpt::poses::Lie::SO<3>::log(a_true.getRotationMatrix()).norm();
        if (!out.empty() && a_true.translation().norm() <= o.t_min &&
            angle <= mrpt::DEG2RAD(o.theta_min_deg))
        {
            continue;
        }
        DrivenFrame f;
        f.timestamp = sim.frameTime(i);
        f.frame_index = i;
        f.T_world_true = T;
        if (out.empty())
        {
            f.action_drifted = mrpt::poses::CPose3D();
        }
        else
        {
            // Scale error on the translation, a yaw bias proportional to the
            // distance travelled (about the vertical camera axis y).
            const double dist = a_true.translation().norm();
            emslam::rectify::ActionDelta d{};
            d[0] = o.scale_error * a_true.x();
            d[1] = o.scale_error * a_true.y();
            d[2] = o.scale_error * a_true.z();
            const double turn = mrpt::poses::Lie::SO<3>::log(a_true.getRotationMatrix())[1];
            d[4] = mrpt::DEG2RAD(o.heading_drift_deg_per_m) * dist + o.turn_scale_error * turn;
            f.action_drifted = emslam::rectify::perturbAction(a_true, d);
        }
        last_accepted_true = T;

        cv::Mat intensity, depth;
        sim.renderer().renderView(
            sim.world(), sim.scenePose(i), sim.frameTime(i) - sim.params().start_time, intensity,
            &depth);
        for (int v = 0; v < depth.rows; ++v)
        {
            for (int u = 0; u < depth.cols; ++u)
            {
                const double z0 = depth.at<float>(v, u);
                if (!(z0 > 0.2 && z0 < o.max_depth))
                {
                    continue;
                }
                const double z = z0 + o.depth_noise * z0 * z0 * gauss(rng);
                const double y = (v - cy) / o.focal_px * z;
                if (y < o.keep_y_min || y > o.keep_y_max)
                {
                    continue;
                }
                f.cloud.push_back(
                    {static_cast<float>((u - cx) / o.focal_px * z),
                     static_cast<float>((v - cy) / o.focal_px * z), static_cast<float>(z)},
                    1.0f);
            }
        }
        out.push_back(std::move(f));
    }
    return out;
}

std::vector<mrpt::poses::CPose3D> composeActions(const std::vector<DrivenFrame>& frames)
{
    std::vector<mrpt::poses::CPose3D> poses;
    mrpt::poses::CPose3D p;
    for (const DrivenFrame& f : frames)
    {
        p = p + f.action_drifted;
        poses.push_back(p);
    }
    return poses;
}

double positionRmse(
    const std::vector<mrpt::poses::CPose3D>& est, const std::vector<DrivenFrame>& truth)
{
    double sum = 0;
    for (std::size_t i = 0; i < est.size(); ++i)
    {
        sum += (est[i].translation() - truth[i].T_world_true.translation()).sqrNorm();
    }
    return std::sqrt(sum / static_cast<double>(est.size()));
}

double loopGap(const std::vector<mrpt::poses::CPose3D>& poses)
{
    return (poses.back().translation() - poses.front().translation()).norm();
}
}  // namespace emslam::test
