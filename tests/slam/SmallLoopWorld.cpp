// SPDX-License-Identifier: BSD-3-Clause
#include "SmallLoopWorld.h"

#include <emslam/sim/StereoSimulator.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/poses/Lie/SO.h>

#include <cmath>
#include <map>
#include <mutex>
#include <utility>

namespace emslam::test
{
std::string smallLoopWorldIni(double fps)
{
    // A 10 m square room (1.25 m cells) with a 2.5 m pillar in the middle;
    // the loop runs 1.9 m from the walls, so both are always in view.
    return "[Simulation]\nfps = " + std::to_string(fps) +
           "\nmax_step = 0.5\nmax_step_deg = 20\n"
           "[Camera]\nwidth = 320\nheight = 240\nfocal_px = 200\nbaseline = 0.1\n"
           "noise_sigma = 1.0\nmax_range = 20\n"
           "[Trajectory]\ntype = robot3dof\nwaypoints = 3.1 3.1; 8.4 3.1; 8.4 8.4; 3.1 8.4\n"
           "closed = true\nloops = 2\nspeed = 1.0\ndrive = holonomic\nturn_blend = 1.5\n"
           "camera_height = 1.0\n"
           "[World]\ntype = building\nseed = 5\n"
           "[Building]\ncell_size = 1.25\ndoor_probability = 0\nposter_probability = 0.5\n"
           "map_0 = ##########/#........#/#........#/#........#/#...##...#/"
           "#...##...#/#........#/#........#/#........#/##########\n";
}

const std::vector<TruthFrame>& smallLoopFrames(double fps, std::size_t count)
{
    static std::mutex mutex;
    static std::map<std::pair<double, std::size_t>, std::vector<TruthFrame>> cache;
    const std::lock_guard<std::mutex> lock(mutex);
    auto& frames = cache[{fps, count}];
    if (frames.empty())
    {
        mrpt::config::CConfigFileMemory cfg(smallLoopWorldIni(fps));
        emslam::sim::StereoSimulator sim;
        sim.load(cfg);
        const std::size_t n = count == 0 ? sim.frameCount() : std::min(count, sim.frameCount());
        for (std::size_t i = 0; i < n; ++i)
        {
            auto f = sim.renderFrame(i);
            frames.push_back({f.obs, f.T_first_left});
        }
    }
    return frames;
}

double rotationDeg(const mrpt::poses::CPose3D& p)
{
    return mrpt::RAD2DEG(mrpt::poses::Lie::SO<3>::log(p.getRotationMatrix()).norm());
}

}  // namespace emslam::test
