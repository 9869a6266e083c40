// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/App.h>
#include <emslam/sim/SurfaceSampler.h>
#include <emslam/slam/OccupancyGridBuilder.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace emslam::apps
{
/** The synthetic-data generator behind `emslam-sim`: renders a world INI file
 * (see emslam::sim::StereoSimulator and config/sim/) into a gz-compressed,
 * observations-only rawlog of `CObservationStereoImages` (calibration set,
 * label from [Simulation] sensor_label, default "STEREO"), plus the exact
 * ground truth of the left camera in the first left camera's frame as a TUM
 * trajectory.
 *
 * \code
 * emslam-sim WORLD.ini -o OUT.rawlog [--gt-out GT.tum] [--frames N] [--seed S]
 *                                    [--png DIR] [--gz-level L] [--quiet]
 *                                    [--video V.avi [--video-codec FFV1]
 *                                     [--video-calibration CALIB.yml]]
 *                                    [--map-gt-out REF.ply [--map-gt-spacing M]
 *                                     [--map-gt-range M]]
 *                                    [--grid-gt-out PLAN.gridmap [--grid-config MAPPER.ini]]
 * \endcode
 *
 * - Same INI and seed, same bytes (rawlog and ground truth).
 * - Outputs go to `<name>.partial` and are renamed when everything succeeded;
 *   on any error the partial files are removed and run() throws.
 * - `--png DIR` also writes `left_NNNNNN.png` / `right_NNNNNN.png`.
 * - `--video` also writes the frames as one side-by-side video
 *   (emslam::sim::StereoVideoWriter; FFV1 is lossless) and
 *   `--video-calibration` its calibration as an OpenCV file
 *   (io::saveOpenCvStereoCalibration()): the input of CVideoStereoCamera.
 * - `--map-gt-out` writes the true surfaces the rendered frames saw
 *   (sim::SurfaceSampler, saveReferencePly()) and `--grid-gt-out` the true
 *   floor plan (sim::floorPlanGrid()), after the rawlog: the references of
 *   `emslam-eval --map-gt / --grid-gt`.
 * \ingroup emslam_apps_grp \sa doc/apps/emslam-sim.md */
class SimApp : public App
{
public:
    SimApp();

    /** The check run() makes of a world INI before rendering: the values of
     * the sections of StereoSimulator, StereoRenderer, Trajectory and World
     * must be of their keys' kind (requireValidConfig(); other keys and the
     * `[Element*]` sections are left to the loaders) and the world must load
     * (every parameter in its range). Throws std::exception naming the
     * section and key. */
    static void checkConfig(const mrpt::config::CConfigFileBase& params);

    /** \name Settings (filled by initialize(); may be edited before run())
     * @{ */
    /** World file name (for messages). */
    std::string world_file;
    /** Output rawlog. */
    std::string output_file;
    /** Ground-truth output (TUM); empty: not written. */
    std::string gt_out_file;
    /** True surfaces output (PLY); empty: not written. */
    std::string map_gt_out_file;
    /** How the true surfaces are sampled (spacing and max_range from the
     * command line). */
    emslam::sim::SurfaceSampler::TParameters map_gt;
    /** True floor plan output (MRPT gridmap, gz-compressed); empty: not written. */
    std::string grid_gt_out_file;
    /** The band and cell size of the floor plan: the mapper's [OccupancyGridBuilder]
     * (--grid-config) or its defaults. */
    emslam::slam::OccupancyGridBuilder::TParameters grid_gt;
    /** Folder for PNG copies of the images; empty: none. */
    std::string png_dir;
    /** Side-by-side video of the frames; empty: none. */
    std::string video_file;
    /** Four-character codec of the video. (Default: FFV1, lossless) */
    std::string video_codec{"FFV1"};
    /** OpenCV calibration file of the video; empty: none. */
    std::string video_calibration_file;
    /** Render at most this many frames; unset: the whole trajectory. */
    std::optional<std::size_t> max_frames;
    /** gzip level of the rawlog, 0..9. (Default: 1) */
    int gz_level{1};
    /** No progress and summary output. */
    bool quiet{false};
    /** @} */

    /** \name Results
     * @{ */
    std::size_t frames_written{0};       //!< observations written
    std::size_t poses_written{0};        //!< ground-truth lines written
    std::uintmax_t output_bytes{0};      //!< size of output_file [bytes]
    std::size_t reference_points{0};     //!< samples written to map_gt_out_file
    std::size_t floor_plan_occupied{0};  //!< occupied cells written to grid_gt_out_file
    double elapsed_seconds{0.0};         //!< wall-clock time of run() [s]
    /** @} */
protected:
    bool parseArguments(int argc, const char** argv) override;
    /** Renders and writes the outputs. Throws on any error, leaving no output. */
    void execute() override;

private:
    struct Arguments;
    /** The world, the rawlog and the optional image, video and ground-truth outputs. */
    void takeOutputs(Arguments& args);
    /** --map-gt-out and --grid-gt-out with their options, checked. */
    void takeReferences(Arguments& args);
    /** Usage error if two outputs name the same file. */
    void requireDistinctOutputs() const;
    /** Writes map_gt_out_file and grid_gt_out_file from the frames [0, frames). */
    void writeReferences(const emslam::sim::StereoSimulator& sim, std::size_t frames);
};

}  // namespace emslam::apps
