// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/slam/KeyframeScan.h>
#include <emslam/slam/LoopCloser.h>

#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CSerializable.h>

#include <cstddef>
#include <string>
#include <vector>

namespace emslam::slam
{
/** A mapping session saved to continue it with another rawlog, or to
 * localize a new run in it (`emslam-mapper --save-session / --load-session /
 * --localize`): every frame's final pose, the keyframes with their compact
 * descriptions and the pose graph that joined them (LoopCloser::Snapshot),
 * the keyframes' map clouds and the configuration of the run.
 *
 * MRPT-serialized (versioned, readable by any MRPT archive); save() writes a
 * gzip file through a temporary name, so a failed save leaves the former file
 * as it was, and load() names what is wrong with a file that is not one.
 * \ingroup emslam_slam_grp \sa EntropySlam::continueSession() */
class CMapSession : public mrpt::serialization::CSerializable
{
    DEFINE_SERIALIZABLE(CMapSession, emslam::slam)

public:
    /** One processed frame of the session. */
    struct Frame
    {
        double timestamp{0};                    //!< [s]
        std::size_t keyframe{0};                //!< the keyframe it is placed from (frame index)
        mrpt::poses::CPose3D T_keyframe_frame;  //!< the egomotion since that keyframe
        mrpt::poses::CPose3D egomotion;         //!< its egomotion pose (world)
        mrpt::poses::CPose3D online;            //!< the pose the run had for it then (world)
        bool accepted{false};                   //!< a keyframe
        bool egomotion_ok{true};                //!< its step succeeded
        std::size_t final_matches{0};           //!< after LWO
    };

    std::string config;         //!< effective INI of the run that made it
    std::vector<Frame> frames;  //!< every frame, in order (index = frame index)
    /** The keyframes in the graph, its edges and the drift's calibration
     * (frame indices as in `frames`). */
    LoopCloser::Snapshot graph;
    /** World pose of each of `graph.keyframes` (the final trajectory). */
    std::vector<mrpt::poses::CPose3D> keyframe_poses;
    /** The map clouds, each in the camera frame of its frame. */
    std::vector<KeyframeScan> scans;

    /** Throws std::runtime_error naming the first inconsistency (sizes,
     * indices out of range, frames out of order). */
    void validate() const;
    /** Writes the session to `file` (gzip). Throws std::runtime_error naming
     * the file. */
    void save(const std::string& file) const;
    /** Reads a session written by save(); throws std::runtime_error naming
     * the file and the cause (missing, not an emslam session, corrupt,
     * written by a newer version). */
    static Ptr load(const std::string& file);
};

}  // namespace emslam::slam
