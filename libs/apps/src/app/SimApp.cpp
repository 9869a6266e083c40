// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>
#include <emslam/apps/ConfigLookup.h>
#include <emslam/apps/ConfigValidation.h>
#include <emslam/apps/PlyFile.h>
#include <emslam/apps/ProgressLine.h>
#include <emslam/apps/RawlogRecording.h>
#include <emslam/apps/SimApp.h>
#include <emslam/apps/StopSignal.h>
#include <emslam/io/AtomicFile.h>
#include <emslam/io/GzOutputStream.h>
#include <emslam/io/ImageOutput.h>
#include <emslam/io/IniFile.h>
#include <emslam/io/InputFileChecks.h>
#include <emslam/io/InputOutputClash.h>
#include <emslam/io/OpenCvStereoCalibration.h>
#include <emslam/io/RawlogOutput.h>
#include <emslam/io/TumTrajectory.h>
#include <emslam/sim/FloorPlan.h>
#include <emslam/sim/StereoSimulator.h>
#include <emslam/sim/StereoVideoWriter.h>

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/os.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <stdexcept>
#include <vector>

namespace fs = std::filesystem;

namespace emslam::apps
{
namespace
{
constexpr const char* PROGRAM = "emslam-sim";

}  // namespace

SimApp::SimApp() : App(PROGRAM) {}

/** The command line of emslam-sim, each argument added to `cmd` in the
 * order of its help; defaults from the app's settings. */
struct SimApp::Arguments
{
    explicit Arguments(const SimApp& app_defaults) : app(app_defaults) {}

    const SimApp& app;
    TCLAP::CmdLine cmd{
        "Renders a synthetic stereo world (config/sim/*.ini) into a gz-compressed rawlog of "
        "CObservationStereoImages and its exact ground truth (left camera in the first left "
        "camera's frame) into a TUM file; Ctrl-C keeps the frames rendered so far (exit 130). "
        "Example: '" +
            std::string(PROGRAM) +
            " hall_double_loop -o hall.rawlog --gt-out hall.tum' (a shipped world by name).",
        ' ', std::string("emslam-sim (") + mrpt::system::MRPT_getVersion() + ")"};
    TCLAP::UnlabeledValueArg<std::string> arg_world{
        "world",
        "World INI file, or the name of a shipped one (hall_double_loop, ...: "
        "share/emslam/config/sim).",
        true,
        "",
        "WORLD.ini",
        cmd};
    TCLAP::ValueArg<std::string> arg_out{
        "o",          "output", "Output rawlog (gz-compressed, observations only).", true, "",
        "OUT.rawlog", cmd};
    TCLAP::ValueArg<std::string> arg_gt{
        "", "gt-out", "Write the ground truth here (TUM format).", false, "", "GT.tum", cmd};
    TCLAP::ValueArg<long long> arg_frames{
        "",
        "max-frames",
        "Render only the first N frames (default 0: the whole trajectory).",
        false,
        0,
        "N",
        cmd};
    TCLAP::ValueArg<long long> arg_seed{
        "", "seed", "World seed (overrides [World] seed).", false, 1, "S", cmd};
    TCLAP::ValueArg<std::string> arg_png{
        "",    "png", "Also write the images as PNG files into this folder (created).", false, "",
        "DIR", cmd};
    TCLAP::ValueArg<int> arg_gz{
        "", "gz-level", "gzip level of the rawlog, 0..9 (default 1).", false, 1, "0..9", cmd};
    TCLAP::ValueArg<std::string> arg_video{
        "",
        "video",
        "Also write the frames as one side-by-side video (left | right), e.g. hall.avi or "
        "hall.mkv, for CVideoStereoCamera.",
        false,
        "",
        "VIDEO",
        cmd};
    TCLAP::ValueArg<std::string> arg_codec{
        "",
        "video-codec",
        "Four-character codec of --video: FFV1 (lossless, default), PNG, MJPG (lossy), H264 "
        "(lossy), ...",
        false,
        "FFV1",
        "FOURCC",
        cmd};
    TCLAP::ValueArg<std::string> arg_video_calib{
        "",
        "video-calibration",
        "Write the stereo calibration of --video as an OpenCV file (M1 D1 M2 D2 R T, metres; "
        ".yml, .xml or .json).",
        false,
        "",
        "CALIB.yml",
        cmd};
    TCLAP::ValueArg<std::string> arg_map_gt{
        "",
        "map-gt-out",
        "Write the true surfaces the camera saw (samples with normals and the nearest depth "
        "they were seen at, first camera's frame) to this PLY file: the reference of "
        "'emslam-eval --map-gt'.",
        false,
        "",
        "REF.ply",
        cmd};
    TCLAP::ValueArg<double> arg_map_gt_spacing{
        "",
        "map-gt-spacing",
        "Distance between the samples of --map-gt-out [m] (default " +
            mrpt::format("%g", app.map_gt.spacing) + ").",
        false,
        app.map_gt.spacing,
        "M",
        cmd};
    TCLAP::ValueArg<double> arg_map_gt_range{
        "",
        "map-gt-range",
        "Farthest depth a surface of --map-gt-out is seen at [m] (default " +
            mrpt::format("%g", app.map_gt.max_range) + ", the mapper's [StereoMatcher] max_range).",
        false,
        app.map_gt.max_range,
        "M",
        cmd};
    TCLAP::ValueArg<std::string> arg_grid_gt{
        "",
        "grid-gt-out",
        "Write the true floor plan (the walls and obstacles the camera saw in the height band "
        "of [OccupancyGridBuilder]) as an MRPT occupancy grid, the reference of 'emslam-eval "
        "--grid-gt'.",
        false,
        "",
        "PLAN.gridmap",
        cmd};
    TCLAP::ValueArg<std::string> arg_grid_config{
        "",
        "grid-config",
        "Mapper INI whose [OccupancyGridBuilder] cell_size, min_height, max_height and max_range "
        "--grid-gt-out uses (default: the mapper's defaults).",
        false,
        "",
        "MAPPER.ini",
        cmd};
    TCLAP::SwitchArg arg_quiet{"q", "quiet", "No progress or summary output.", cmd, false};
};

bool SimApp::parseArguments(int argc, const char** argv)
{
    Arguments args(*this);
    if (!parseCommandLine(args.cmd, argc, argv, {{"--frames", "--max-frames", 0, "N"}}))
    {
        return false;
    }
    takeOutputs(args);
    takeReferences(args);
    if (gz_level < 0 || gz_level > 9)
    {
        usageError("--gz-level must be in 0..9");
    }
    max_frames.reset();
    if (countOption(args.arg_frames.getValue(), "--max-frames", 0, PROGRAM) > 0)
    {
        max_frames = static_cast<std::size_t>(args.arg_frames.getValue());
    }
    requireDistinctOutputs();
    io::requireOutputsAreNotInputs(
        {{"output rawlog", output_file},
         {"ground-truth output (--gt-out)", gt_out_file},
         {"video (--video)", video_file},
         {"video calibration (--video-calibration)", video_calibration_file},
         {"true surfaces (--map-gt-out)", map_gt_out_file},
         {"true floor plan (--grid-gt-out)", grid_gt_out_file}},
        {{"the world file", world_file},
         {"the mapper INI (--grid-config)", args.arg_grid_config.getValue()}});
    params.setContent(io::readIniFile(world_file, "world file"));
    if (args.arg_seed.isSet())
    {
        params.write("World", "seed", static_cast<int>(args.arg_seed.getValue()));
    }
    return true;
}

void SimApp::takeOutputs(Arguments& args)
{
    world_file = findConfigFile(args.arg_world.getValue(), "sim");
    output_file = args.arg_out.getValue();
    gt_out_file = args.arg_gt.getValue();
    png_dir = args.arg_png.getValue();
    video_file = args.arg_video.getValue();
    video_codec = args.arg_codec.getValue();
    video_calibration_file = args.arg_video_calib.getValue();
    if (video_codec.size() != 4)
    {
        usageError("--video-codec must be four characters (FFV1, MJPG, 'PNG ', ...)");
    }
    if (!video_calibration_file.empty() && !io::isOpenCvStorageFile(video_calibration_file))
    {
        usageError("--video-calibration must end in .yml, .yaml, .xml or .json");
    }
    gz_level = args.arg_gz.getValue();
    quiet = args.arg_quiet.getValue();
}

void SimApp::takeReferences(Arguments& args)
{
    map_gt_out_file = args.arg_map_gt.getValue();
    grid_gt_out_file = args.arg_grid_gt.getValue();
    map_gt.spacing = args.arg_map_gt_spacing.getValue();
    map_gt.max_range = args.arg_map_gt_range.getValue();
    try
    {
        map_gt.validate();
    }
    catch (const std::invalid_argument&)
    {
        usageError(
            "--map-gt-spacing must be in [0.001, 10] m and --map-gt-range above " +
            mrpt::format("%g", map_gt.min_range) + " m");
    }
    if (args.arg_grid_config.isSet())
    {
        mrpt::config::CConfigFileMemory mapper;
        try
        {
            loadConfig(mapper, args.arg_grid_config.getValue(), {});  // old section names too
        }
        catch (const std::exception& e)
        {
            throw std::runtime_error(std::string("--grid-config: ") + e.what());
        }
        grid_gt.loadFromConfigFile(mapper, "OccupancyGridBuilder");
        grid_gt.validate();
    }
}

void SimApp::requireDistinctOutputs() const
{
    const std::vector<std::pair<std::string, std::string>> outputs = {
        {"--output", output_file},         {"--gt-out", gt_out_file},
        {"--video", video_file},           {"--video-calibration", video_calibration_file},
        {"--map-gt-out", map_gt_out_file}, {"--grid-gt-out", grid_gt_out_file}};
    for (std::size_t a = 0; a < outputs.size(); ++a)
    {
        for (std::size_t b = a + 1; b < outputs.size(); ++b)
        {
            if (!outputs[b].second.empty() && fs::path(outputs[a].second).lexically_normal() ==
                                                  fs::path(outputs[b].second).lexically_normal())
            {
                usageError(outputs[b].first + " and " + outputs[a].first + " name the same file");
            }
        }
    }
}

namespace
{
/** Values of the parameter sections that MRPT would misread (see
 * requireValidConfig()). */
void requireWellFormedValues(const mrpt::config::CConfigFileBase& cfg)
{
    mrpt::config::CConfigFileMemory known;
    emslam::sim::StereoSimulator::TParameters().saveToConfigFile(known, "Simulation");
    emslam::sim::StereoRenderer::TParameters().saveToConfigFile(known, "Camera");
    emslam::sim::Trajectory::TParameters().saveToConfigFile(known, "Trajectory");
    emslam::sim::World::TBuildingParams().saveToConfigFile(known, "Building");
    emslam::sim::World::TGroundParams().saveToConfigFile(known, "Ground");
    emslam::sim::World::TTerrainParams().saveToConfigFile(known, "Terrain");
    known.write("World", "seed", 1);
    requireWellFormedConfigValues(cfg, known);
}
/** emslam-sim's --video: the frames side by side in NAME.partial.EXT
 * (OpenCV picks the container from the extension), renamed by commit() once
 * the rawlog is complete, removed if the run fails before. */
class SideBySideVideoOutput
{
public:
    SideBySideVideoOutput(
        const std::string& file, const std::string& codec, const emslam::sim::StereoSimulator& sim)
        : m_file(file), m_partial(partialName(file))
    {
        const auto& cam = sim.renderer().params();
        m_writer = std::make_unique<emslam::sim::StereoVideoWriter>(
            m_partial, sim.params().fps, cv::Size(cam.width, cam.height), codec);
    }
    ~SideBySideVideoOutput()
    {
        if (!m_committed)
        {
            m_writer->close();
            std::error_code ec;
            fs::remove(m_partial, ec);
        }
    }
    SideBySideVideoOutput(const SideBySideVideoOutput&) = delete;
    SideBySideVideoOutput& operator=(const SideBySideVideoOutput&) = delete;

    void write(const mrpt::obs::CObservationStereoImages& obs)
    {
        m_writer->write(obs.imageLeft.asCvMatRef(), obs.imageRight.asCvMatRef());
    }

    /** Closes and renames the video; writes `cam` to `calibration_file` if not empty. */
    void commit(const std::string& calibration_file, const mrpt::img::TStereoCamera& cam)
    {
        m_writer->close();
        if (!calibration_file.empty())
        {
            io::saveOpenCvStereoCalibration(calibration_file, cam);
        }
        fs::rename(m_partial, m_file);
        m_committed = true;
    }

private:
    static std::string partialName(const std::string& file)
    {
        const fs::path v(file);
        return (v.parent_path() / (v.stem().string() + ".partial" + v.extension().string()))
            .string();
    }

    std::string m_file, m_partial;
    std::unique_ptr<emslam::sim::StereoVideoWriter> m_writer;
    bool m_committed{false};
};
}  // namespace

void SimApp::checkConfig(const mrpt::config::CConfigFileBase& params)
{
    requireWellFormedValues(params);
    emslam::sim::StereoSimulator().load(params);
}

void SimApp::execute()
{
    ASSERTMSG_(!output_file.empty(), "SimApp: no output file");
    const auto t_start = std::chrono::steady_clock::now();
    frames_written = 0;
    poses_written = 0;
    output_bytes = 0;

    emslam::sim::StereoSimulator sim;
    try
    {
        // Re-parse the text (a CConfigFileMemory written to reads back defaults otherwise).
        mrpt::config::CConfigFileMemory cfg(params.getContent());
        requireWellFormedValues(cfg);
        sim.load(cfg);
    }
    catch (const std::exception& e)
    {
        throw std::invalid_argument("'" + world_file + "': " + e.what());
    }
    const std::size_t n = std::min(sim.frameCount(), max_frames.value_or(sim.frameCount()));

    io::RawlogOutput::checkOutputFolders(output_file, gt_out_file);
    if (!png_dir.empty())
    {
        fs::create_directories(png_dir);
    }
    if (!quiet)
    {
        const auto& cam = sim.renderer().params();
        std::cerr << PROGRAM << ": rendering " << n << " of " << sim.frameCount() << " frames of '"
                  << world_file << "' (" << sim.world().type() << ", "
                  << sim.world().elements().size() << " elements, " << cam.width << "x"
                  << cam.height << ", seed " << sim.seed() << ") into '" << output_file << "'\n";
    }
    std::optional<SideBySideVideoOutput> video;
    if (!video_file.empty())
    {
        video.emplace(video_file, video_codec, sim);
    }
    const RawlogRecording rec = recordRawlog(
        PROGRAM, output_file, gz_level, gt_out_file, n, !quiet,
        [&](std::size_t i, mrpt::serialization::CArchive& out, emslam::io::TumTrajectory& gt)
        {
            const auto fr = sim.renderFrame(i);
            out << *fr.obs;
            gt.add(fr.t, fr.T_first_left);
            if (!png_dir.empty())
            {
                char name[64];
                std::snprintf(name, sizeof(name), "/left_%06zu.png", i);
                io::writeImageFile(png_dir + name, fr.obs->imageLeft.asCvMatRef());
                std::snprintf(name, sizeof(name), "/right_%06zu.png", i);
                io::writeImageFile(png_dir + name, fr.obs->imageRight.asCvMatRef());
            }
            if (video)
            {
                video->write(*fr.obs);
            }
        });
    if (video)
    {
        video->commit(video_calibration_file, sim.renderer().stereoCamera());
    }
    frames_written = rec.frames_written;
    poses_written = rec.poses_written;
    output_bytes = fs::file_size(output_file);
    writeReferences(sim, frames_written);
    elapsed_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    if (!quiet)
    {
        std::cout << PROGRAM << ": wrote " << frames_written << " frames to '" << output_file
                  << "'";
        if (!gt_out_file.empty())
        {
            std::cout << ", " << poses_written << " ground-truth poses to '" << gt_out_file << "'";
        }
        if (!video_file.empty())
        {
            std::cout << ", a side-by-side " << video_codec << " video to '" << video_file << "'";
        }
        if (!map_gt_out_file.empty())
        {
            std::cout << ", " << reference_points << " true-surface samples to '" << map_gt_out_file
                      << "'";
        }
        if (!grid_gt_out_file.empty())
        {
            std::cout << ", a floor plan of " << floor_plan_occupied << " occupied cells to '"
                      << grid_gt_out_file << "'";
        }
        std::cout << mrpt::format(
            " in %.2f s (%.1f ms/frame)\n", elapsed_seconds,
            1e3 * elapsed_seconds / static_cast<double>(std::max<std::size_t>(frames_written, 1)));
        std::cout.flush();
    }
}

void SimApp::writeReferences(const emslam::sim::StereoSimulator& sim, std::size_t frames)
{
    reference_points = 0;
    floor_plan_occupied = 0;
    if ((map_gt_out_file.empty() && grid_gt_out_file.empty()) || frames == 0)
    {
        return;
    }
    auto sampling = map_gt;
    if (!grid_gt_out_file.empty())
    {
        // The floor plan needs the surfaces out to its range, with several
        // samples in each of its cells.
        sampling.max_range = std::max(sampling.max_range, grid_gt.max_range);
        sampling.spacing = std::min(sampling.spacing, grid_gt.cell_size / 3);
    }
    const auto seen = emslam::sim::SurfaceSampler(sampling).visibleSurfaces(sim, frames);
    if (!map_gt_out_file.empty())
    {
        eval::ReferenceSurface ref;
        ref.spacing = sampling.spacing;
        for (const auto& s : seen)
        {
            if (s.seen_range > map_gt.max_range)
            {
                continue;
            }
            ref.points.emplace_back(s.position[0], s.position[1], s.position[2]);
            ref.normals.emplace_back(s.normal[0], s.normal[1], s.normal[2]);
            ref.seen_range.push_back(s.seen_range);
        }
        saveReferencePly(ref, map_gt_out_file);
        reference_points = ref.points.size();
    }
    if (!grid_gt_out_file.empty())
    {
        const auto grid = emslam::sim::floorPlanGrid(
            seen, {grid_gt.cell_size, grid_gt.min_height, grid_gt.max_height, grid_gt.max_range});
        for (unsigned cy = 0; cy < grid.getSizeY(); ++cy)
        {
            for (unsigned cx = 0; cx < grid.getSizeX(); ++cx)
            {
                floor_plan_occupied += grid.getCell(cx, cy) < 0.5F ? 1 : 0;
            }
        }
        io::writeFileAtomically(
            grid_gt_out_file,
            [&](const std::string& partial)
            {
                io::GzOutputStream f(partial, 1, grid_gt_out_file);
                mrpt::serialization::archiveFrom(f) << grid;
                f.close();
                return true;
            });
    }
}

}  // namespace emslam::apps
