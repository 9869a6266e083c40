// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/sim/World.h>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose3D.h>

#include <array>
#include <string>
#include <vector>

namespace emslam::sim
{
/** Camera trajectory generator: a 3DOF robot (planar motion, camera at a fixed
 * height, differential or holonomic drive) or a 6DOF walker (gait bobbing,
 * pitch and roll sway, heights from the way-points, e.g. stairs), moving along
 * a polyline of way-points at constant speed.
 *
 * \code
 * [Trajectory]
 * type = robot3dof         ; robot3dof | walker6dof
 * waypoints = 1 1; 9 1; 9 9; 1 9   ; 'x z' (or 'x y z': floor height y) in the scene frame [m]
 * closed = true            ; return to the first way-point
 * loops = 1                ; repetitions of a closed path
 * speed = 0.6              ; [m/s]
 * angular_speed_deg = 30   ; [deg/s] differential drive: turn on the spot at corners
 * drive = differential     ; differential | holonomic (heading blended over turn_blend)
 * turn_blend = 1.5         ; [m]
 * camera_height = 1.2      ; [m] above the floor (or the terrain if follow_ground)
 * follow_ground = false    ; add World::groundHeight() (averaged over 0.5 m)
 * bob_amplitude = 0.03     ; walker6dof: vertical gait bobbing [m]
 * step_frequency = 1.8     ; walker6dof: steps per second [Hz]
 * sway_roll_deg = 1.5      ; walker6dof: roll amplitude
 * sway_pitch_deg = 1.0     ; walker6dof: pitch amplitude
 * \endcode
 * A closed walk starts and ends standing still: the gait fades in over the
 * first second and out over the last, so its last pose is its first one.
 * Scene frame: X, Z horizontal, Y up. The camera looks along the heading
 * (yaw 0: +Z), x right, y down.
 * \ingroup emslam_sim_grp \sa StereoSimulator */
class Trajectory
{
public:
    /** [Trajectory] parameters. */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;

        std::string type{"robot3dof"};      //!< robot3dof | walker6dof (Default: robot3dof)
        std::string waypoints;              //!< 'x z; x z; ...' or 'x y z; ...' [m]
        bool closed{false};                 //!< back to the first way-point (Default: false)
        int loops{1};                       //!< repetitions of a closed path (Default: 1)
        double speed{0.6};                  //!< [m/s] (Default: 0.6)
        double angular_speed_deg{30.0};     //!< [deg/s] (Default: 30)
        std::string drive{"differential"};  //!< differential | holonomic (Default: differential)
        double turn_blend{1.5};             //!< [m] holonomic / walker heading blend (Default: 1.5)
        double camera_height{1.2};          //!< [m] (Default: 1.2)
        bool follow_ground{false};          //!< add the terrain height (Default: false)
        double bob_amplitude{0.03};         //!< [m] walker6dof (Default: 0.03)
        double step_frequency{1.8};         //!< [Hz] walker6dof (Default: 1.8)
        double sway_roll_deg{1.5};          //!< walker6dof (Default: 1.5)
        double sway_pitch_deg{1.0};         //!< walker6dof (Default: 1.0)
    };

    Trajectory() = default;

    /** Builds the trajectory from `p` (validated: throws
     * std::invalid_argument naming the [Trajectory] key on bad values). */
    void setup(const TParameters& p);

    /** Parameters in use. */
    const TParameters& params() const { return m_p; }
    /** Way-points (x, z) after closing / looping, for World keep-out areas. */
    std::vector<std::array<double, 2>> waypointsXZ() const;
    /** Duration of the whole trajectory [s]. */
    double duration() const;
    /** Pose of the (left) camera in the scene frame at time t [s] (clamped
     * to [0, duration]); `world` gives the ground for follow_ground. */
    mrpt::poses::CPose3D cameraPose(double t, const World* world = nullptr) const;

private:
    struct Segment
    {
        double t0, t1;                 // time span
        std::array<double, 3> p0, p1;  // x, y(floor), z
        double yaw0, yaw1;
        double s0;  // arc length at start
    };
    /** The timed segments (and corners) along m_pts, with m_p. */
    void buildSegments();
    TParameters m_p;
    std::vector<std::array<double, 3>> m_pts;
    std::vector<Segment> m_segments;
    std::vector<double> m_corner_s;  // arc length at each inner corner
    std::vector<double> m_corner_dyaw;
};

}  // namespace emslam::sim
