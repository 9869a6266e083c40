// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/sim/StereoRenderer.h>
#include <emslam/sim/Trajectory.h>
#include <emslam/sim/World.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <string>

namespace emslam::sim
{
/** A synthetic stereo camera moving through a World: loads a world INI file
 * ([Simulation], [Camera], [Trajectory], [World] and the generator / element
 * sections) and renders frame i as the `CObservationStereoImages` a real
 * camera would give (calibration set, `hasImageRight`, sensor label,
 * timestamp `start_time + i / fps`), with the exact ground-truth pose of the
 * left camera in the first left camera's frame and, on request, the exact
 * left depth. renderFrame() is const and deterministic, so it may serve a
 * simulated live camera.
 *
 * \code
 * [Simulation]
 * fps = 5                  ; frames per second [Hz]
 * start_time = 1700000000  ; UNIX time of frame 0 [s]
 * sensor_label = STEREO
 * exposure_amplitude = 0   ; relative gain change, gain = 1 + a sin(2 pi t / period)
 * exposure_period = 8      ; [s]
 * max_step = 0.5           ; [m] largest allowed camera motion between frames
 * max_step_deg = 15        ; [deg] largest allowed rotation between frames
 * \endcode
 * \ingroup emslam_sim_grp \sa World, Trajectory, StereoRenderer */
class StereoSimulator
{
public:
    /** [Simulation] parameters. */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        double fps{5.0};                     //!< [Hz] (Default: 5)
        double start_time{1700000000.0};     //!< UNIX time of frame 0 [s] (Default: 1700000000)
        std::string sensor_label{"STEREO"};  //!< (Default: STEREO)
        double exposure_amplitude{0.0};      //!< relative, in [0, 0.9) (Default: 0)
        double exposure_period{8.0};         //!< [s] (Default: 8)
        double max_step{0.5};                //!< [m] (Default: 0.5)
        double max_step_deg{15.0};           //!< [deg] (Default: 15)
    };

    /** One rendered frame. */
    struct Frame
    {
        /** The observation, as emslam-import writes them. */
        mrpt::obs::CObservationStereoImages::Ptr obs;
        /** Left camera pose in the first left camera's frame (ground truth). */
        mrpt::poses::CPose3D T_first_left;
        /** Timestamp [s, UNIX]. */
        double t{0.0};
        /** Left depth [m] (CV_32FC1, 0: nothing), if requested. */
        cv::Mat depth;
    };

    StereoSimulator() = default;

    /** Loads a world INI file, read by io::readIniFile() (at most
     * io::MAX_INI_BYTES, no repeated section or key); throws naming the
     * file, section and key on errors. */
    void loadFile(const std::string& ini_file);
    /** Loads from a config object. */
    void load(const mrpt::config::CConfigFileBase& cfg);

    /** Number of frames of the whole trajectory. */
    std::size_t frameCount() const { return m_frames; }
    /** Timestamp of frame i [s, UNIX]. */
    double frameTime(std::size_t i) const;
    /** Ground truth of frame i: the left camera in the first left camera's frame. */
    mrpt::poses::CPose3D groundTruth(std::size_t i) const;
    /** Pose of the left camera of frame i in the scene frame (Y up). */
    mrpt::poses::CPose3D scenePose(std::size_t i) const;
    /** Renders frame i (< frameCount()). */
    Frame renderFrame(std::size_t i, bool want_depth = false) const;

    /** The parameters it was built with. */
    const TParameters& params() const { return m_p; }
    /** The world it renders. */
    const World& world() const { return m_world; }
    /** The camera's path through the world. */
    const Trajectory& trajectory() const { return m_traj; }
    /** The stereo renderer of the camera. */
    const StereoRenderer& renderer() const { return m_renderer; }
    /** World seed ([World] seed). */
    int seed() const { return m_seed; }

private:
    TParameters m_p;
    World m_world;
    Trajectory m_traj;
    StereoRenderer m_renderer;
    mrpt::poses::CPose3D m_T_scene_first;
    std::size_t m_frames{0};
    int m_seed{1};
};

}  // namespace emslam::sim
