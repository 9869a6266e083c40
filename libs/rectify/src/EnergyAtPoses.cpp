// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/Action.h>
#include <emslam/rectify/EnergyAtPoses.h>

#include <stdexcept>
#include <string>

namespace emslam::rectify
{
std::vector<mrpt::poses::CPose3D> elementPosesAt(
    const Trajectory& t, const FramePoseLookup& T_world_frame)
{
    std::vector<mrpt::poses::CPose3D> poses;
    poses.reserve(t.size());
    for (std::size_t i = 0; i < t.size(); ++i)
    {
        const ElementFrame& first = t.framesOf(i).front();
        // T_world_element = T_world_frame ⊕ (T_element_frame)⁻¹
        poses.push_back(
            T_world_frame(first.frame_index) + (mrpt::poses::CPose3D() - first.T_element_frame));
    }
    if (t.dof() == 3)
    {
        // Planar actions, composed again: the poses the trajectory could hold.
        const std::vector<mrpt::poses::CPose3D> raw = poses;
        for (std::size_t i = 0; i < raw.size(); ++i)
        {
            // raw[i] - raw[i-1] is the action from element i-1 to element i.
            poses[i] =
                i == 0 ? planarAction(raw[0]) : poses[i - 1] + planarAction(raw[i] - raw[i - 1]);
        }
    }
    return poses;
}

double entropyAtElementPoses(
    const Trajectory& t, const std::vector<mrpt::poses::CPose3D>& element_poses, int grid_phases)
{
    if (element_poses.size() != t.size())
    {
        throw std::invalid_argument(
            "entropyAtElementPoses: " + std::to_string(element_poses.size()) + " poses for " +
            std::to_string(t.size()) + " elements");
    }
    if (grid_phases < 1)
    {
        throw std::invalid_argument("entropyAtElementPoses: grid_phases must be >= 1");
    }
    double sum = 0;
    for (int k = 0; k < grid_phases; ++k)
    {
        sum += entropyOnShiftedGrid(t, element_poses, k, grid_phases);
    }
    return sum / grid_phases;
}

double entropyOnShiftedGrid(
    const Trajectory& t, const std::vector<mrpt::poses::CPose3D>& element_poses, int k, int phases)
{
    if (element_poses.size() != t.size())
    {
        throw std::invalid_argument(
            "entropyOnShiftedGrid: " + std::to_string(element_poses.size()) + " poses for " +
            std::to_string(t.size()) + " elements");
    }
    const mrpt::poses::CPose3D shift =
        Trajectory::gridPhaseShift(k, phases, t.map().creationOptions().cell_size);
    std::vector<mrpt::poses::CPose3D> shifted;
    shifted.reserve(element_poses.size());
    for (const auto& pose : element_poses)
    {
        shifted.push_back(shift + pose);
    }
    return t.map().energyAtPoses(shifted);
}

double priorAtElementPoses(
    const Trajectory& t, const std::vector<mrpt::poses::CPose3D>& element_poses)
{
    if (element_poses.size() != t.size())
    {
        throw std::invalid_argument(
            "priorAtElementPoses: " + std::to_string(element_poses.size()) + " poses for " +
            std::to_string(t.size()) + " elements");
    }
    return t.priorEnergyOf(actionsBetween(element_poses));
}

}  // namespace emslam::rectify
