// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>
#include <emslam/apps/ConfigLookup.h>
#include <emslam/apps/ConfigValidation.h>
#include <emslam/apps/StereoApp.h>
#include <emslam/apps/StopSignal.h>
#include <emslam/io/CalibrationFiles.h>
#include <emslam/io/FrameStreamGuard.h>
#include <emslam/io/ImageFile.h>
#include <emslam/io/ImageOutput.h>
#include <emslam/io/InputFileChecks.h>
#include <emslam/io/InputOutputClash.h>
#include <emslam/io/OutputFile.h>
#include <emslam/io/RawlogInput.h>
#include <emslam/io/RawlogOutput.h>
#include <emslam/stereo/RangeScanConversion.h>
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/stereo/StereoFrontEnd.h>
#include <emslam/util/ExceptionMessage.h>

#include <mrpt/img/CImage.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <new>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>

namespace emslam::apps
{
namespace
{
constexpr const char* STEREO_SECTION = "StereoMatcher";
constexpr const char* PROGRAM = "emslam-stereo";
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void requireFile(const std::string& f, const std::string& what)
{
    io::requireInputFile(f, what);
}

cv::Mat readImage(const std::string& f, const std::string& what)
{
    requireFile(f, what);
    try
    {
        // The size is checked from the header before the image is decoded.
        return io::loadImageFile(f);
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error(what + ": " + emslam::util::shortExceptionMessage(e));
    }
}

void writePly(const emslam::stereo::StereoFrame& f, const std::string& file)
{
    io::OutputFile out(file);
    auto& o = out.text();
    o << "ply\nformat ascii 1.0\nelement vertex " << f.points.size()
      << "\nproperty float x\nproperty float y\nproperty float z\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
    for (std::size_t i = 0; i < f.points.size(); ++i)
    {
        const auto& p = f.points[i];
        const int g = f.intensity.at<uint8_t>(f.pixels[i].v, f.pixels[i].u);
        o << p.x << ' ' << p.y << ' ' << p.z << ' ' << g << ' ' << g << ' ' << g << '\n';
    }
    out.close();
}

void writeDisparityPng(const emslam::stereo::StereoFrame& f, const std::string& file)
{
    double mx = 0;
    cv::minMaxLoc(f.disparity, nullptr, &mx);
    cv::Mat d8, color;
    f.disparity.convertTo(d8, CV_8U, mx > 0 ? 255.0 / mx : 1.0);
    cv::applyColorMap(d8, color, cv::COLORMAP_JET);
    color.setTo(cv::Scalar(0, 0, 0), f.valid == 0);
    io::writeImageFile(file, color);
}

struct DepthStats
{
    double min{0}, median{0}, max{0};
};

DepthStats depthStats(const emslam::stereo::StereoFrame& f)
{
    DepthStats s;
    if (f.points.empty())
    {
        return s;
    }
    std::vector<float> z;
    z.reserve(f.points.size());
    for (const auto& p : f.points)
    {
        z.push_back(p.z);
    }
    std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
    s.median = z[z.size() / 2];
    const auto [mn, mx] = std::minmax_element(z.begin(), z.end());
    s.min = *mn;
    s.max = *mx;
    return s;
}
void printFrame(std::size_t index, const emslam::stereo::StereoFrame& f, double ms)
{
    const auto z = depthStats(f);
    std::printf(
        "frame %zu: %dx%d, %zu points (density %.1f %%), depth %.2f / %.2f / %.2f m "
        "(min/median/max), %.1f ms\n",
        index, f.intensity.cols, f.intensity.rows, f.points.size(), 100.0 * f.density(), z.min,
        z.median, z.max, ms);
}
/** The means over the run, and a camera change warned about. */
void printSummary(const StereoApp& app)
{
    std::printf(
        "%zu frame(s), %.0f points per frame on average (density %.1f %%), %.1f ms per frame\n",
        app.frames_processed, static_cast<double>(app.total_points) / app.frames_processed,
        100.0 * app.mean_density, app.mean_ms_per_frame);
    if (!app.camera_change.empty())
    {
        std::fflush(stdout);
        std::fprintf(stderr, "%s: warning: %s\n", PROGRAM, app.camera_change.c_str());
    }
}
}  // namespace

StereoApp::StereoApp() : App(PROGRAM) {}

bool StereoApp::parseArguments(int argc, const char** argv)
{
    TCLAP::CmdLine cmd(
        "emslam-stereo: run the emslam stereo front-end (rectification + disparity -> "
        "semi-dense 3D) on a rawlog (DATASET.rawlog) or on an image pair with its calibration "
        "(LEFT RIGHT CALIB.ini) and report what it found.",
        ' ', "0.1");
    // A multi-arg: one input (a rawlog) or three (an image pair and its calibration).
    TCLAP::UnlabeledMultiArg<std::string> inputs(
        "inputs",
        "DATASET.rawlog (CObservationStereoImages / CObservation3DRangeScan), or LEFT RIGHT "
        "CALIB.ini: the left (reference) and right images and their calibration in MRPT's "
        "TStereoCamera INI form",
        true, "DATASET.rawlog | LEFT RIGHT CALIB.ini", cmd);
    TCLAP::ValueArg<std::string> calib_section(
        "", "calib-section", withDefault("Calibration section prefix in CALIB.ini", "CAMERA"),
        false, "CAMERA", "NAME", cmd);
    addMaxFramesOption(cmd, "Stop after N frames of the rawlog (0: all)");
    TCLAP::ValueArg<std::string> config(
        "c", "config",
        withDefault(
            "INI file with a [StereoMatcher] section, or the name of a shipped one "
            "(share/emslam/config/stereo)",
            "the built-in defaults"),
        false, "", "CONFIG.ini", cmd);
    addSetOption(cmd, "Override a parameter: StereoMatcher.key=value");
    TCLAP::ValueArg<std::string> gt(
        "", "gt-disparity", "Ground-truth disparity image of the first frame (0 = unknown)", false,
        "", "PNG", cmd);
    TCLAP::ValueArg<double> gt_scale(
        "", "gt-disparity-scale", withDefault("Pixels of disparity per ground-truth unit", "1"),
        false, 1.0, "S", cmd);
    TCLAP::ValueArg<std::string> out_rawlog(
        "", "out-rawlog", "Write the frames as CObservation3DRangeScan to this rawlog", false, "",
        "FILE", cmd);
    TCLAP::ValueArg<std::string> ply(
        "", "ply", "Write the first frame's points", false, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> disp_png(
        "", "disparity-png", "Write the first frame's disparity image", false, "", "FILE", cmd);

    if (!parseCommandLine(
            cmd, argc, argv,
            {{"--rawlog", "", 0, "DATASET.rawlog"},
             {"--left", "", 0, "LEFT"},
             {"--right", "", 1, "RIGHT"},
             {"--calib", "", 2, "CALIB.ini"}}))
    {
        return false;
    }
    const auto& in = inputs.getValue();
    for (const auto& i : in)
    {
        // TCLAP's multi-arg takes any word, so an unknown option lands here.
        if (i.size() > 1 && i[0] == '-')
        {
            throw std::invalid_argument(
                "unknown option '" + i + "'; try " + std::string(PROGRAM) + " --help");
        }
    }
    if (in.size() != 1 && in.size() != 3)
    {
        throw std::invalid_argument(
            "expected DATASET.rawlog or LEFT RIGHT CALIB.ini, got " + std::to_string(in.size()) +
            " inputs; try " + PROGRAM + " --help");
    }
    m_rawlog = in.size() == 1 ? in[0] : "";
    m_left = in.size() == 3 ? in[0] : "";
    m_right = in.size() == 3 ? in[1] : "";
    m_calib = in.size() == 3 ? in[2] : "";
    m_calib_section = calib_section.getValue();
    const std::string config_file = findConfigFile(config.getValue(), "stereo");
    m_gt_disparity = gt.getValue();
    m_gt_scale = gt_scale.getValue();
    m_out_rawlog = out_rawlog.getValue();
    m_ply = ply.getValue();
    m_disparity_png = disp_png.getValue();
    io::requireOutputsAreNotInputs(
        {{"output rawlog", m_out_rawlog},
         {"output point cloud (--ply)", m_ply},
         {"output disparity image", m_disparity_png}},
        {{"the rawlog", m_rawlog},
         {"the left image", m_left},
         {"the right image", m_right},
         {"the calibration", m_calib},
         {"the ground-truth disparity", m_gt_disparity},
         {"the config file", config_file}});
    mrpt::config::CConfigFileMemory known;
    emslam::stereo::StereoMatcher::TParameters().saveToConfigFile(known, STEREO_SECTION);
    loadParameters(config_file, &known);
    checkConfig(params);
    return true;
}

void StereoApp::checkConfig(const mrpt::config::CConfigFileBase& params)
{
    mrpt::config::CConfigFileMemory known;
    emslam::stereo::StereoMatcher::TParameters().saveToConfigFile(known, STEREO_SECTION);
    requireValidConfig(params, known, {}, true);
    emslam::stereo::StereoMatcher::TParameters().loadFromConfigFile(params, STEREO_SECTION);
}

void StereoApp::execute()
{
    emslam::stereo::StereoMatcher::TParameters sp;
    sp.loadFromConfigFile(params, STEREO_SECTION);
    emslam::stereo::StereoFrontEnd front(sp);
    std::cout << "[StereoMatcher] algorithm=" << sp.algorithm << " image_scale=" << sp.image_scale
              << " num_disparities=" << sp.num_disparities << " block_size=" << sp.block_size
              << " range=[" << sp.min_range << ", " << sp.max_range << "] m\n";

    // Written to OUT.partial, renamed when the run succeeds (removed if not).
    std::optional<emslam::io::RawlogOutput> out;
    if (!m_out_rawlog.empty())
    {
        out.emplace(m_out_rawlog, 1);
    }

    frames_processed = total_points = 0;
    skipped = {};
    skipped_reasons.clear();
    camera_change.clear();
    double total_ms = 0, total_density = 0;
    auto handle = [&](const emslam::stereo::StereoFrame& f, double ms)
    {
        printFrame(frames_processed, f, ms);
        if (frames_processed == 0)
        {
            writeFirstFrameOutputs(f);
        }
        if (out)
        {
            out->archive() << *emslam::stereo::toRangeScan(f);
        }
        ++frames_processed;
        total_points += f.points.size();
        total_ms += ms;
        total_density += f.density();
    };

    try
    {
        if (m_rawlog.empty())
        {
            processImagePair(front, handle);
        }
        else
        {
            processRawlog(front, handle);
        }
    }
    catch (...)
    {
        out.reset();  // never leave a half-written output behind
        throw;
    }

    if (out)
    {
        out->commit();
    }
    if (StopSignal::requested())
    {
        std::fprintf(
            stderr, "%s: interrupted after %zu frames%s\n", PROGRAM, frames_processed,
            m_out_rawlog.empty() ? "" : ("; '" + m_out_rawlog + "' holds them").c_str());
    }
    if (frames_processed == 0)
    {
        throw std::runtime_error(
            "no usable stereo or RGB-D observation found in the input" +
            (skipped_reasons.empty() ? std::string()
                                     : " (" + std::to_string(skipped.total()) +
                                           " skipped, first: " + skipped_reasons.front() + ")"));
    }
    mean_density = total_density / frames_processed;
    mean_ms_per_frame = total_ms / frames_processed;
    printSummary(*this);
}

void StereoApp::writeFirstFrameOutputs(const emslam::stereo::StereoFrame& f)
{
    if (!m_ply.empty())
    {
        writePly(f, m_ply);
    }
    if (!m_disparity_png.empty())
    {
        writeDisparityPng(f, m_disparity_png);
    }
    if (!m_gt_disparity.empty())
    {
        cv::Mat gt = readImage(m_gt_disparity, "ground-truth disparity");
        if (gt.channels() != 1)
        {
            throw std::runtime_error("ground-truth disparity must be single-channel");
        }
        cv::Mat gtf;
        // Disparities shrink with the image: scale values and size alike.
        const double k = m_gt_scale * f.intensity.cols / static_cast<double>(gt.cols);
        gt.convertTo(gtf, CV_32F, k);
        cv::resize(gtf, gtf, f.intensity.size(), 0, 0, cv::INTER_NEAREST);
        std::size_t n_gt = 0, n_both = 0, n_bad = 0;
        for (int v = 0; v < gtf.rows; ++v)
        {
            for (int u = 0; u < gtf.cols; ++u)
            {
                const float g = gtf.at<float>(v, u);
                const float d = f.disparity.at<float>(v, u);
                n_gt += g > 0;
                if (g > 0 && d > 0)
                {
                    ++n_both;
                    n_bad += std::abs(d - g) > 1.0f;
                }
            }
        }
        bad_pixel_rate = n_both ? static_cast<double>(n_bad) / n_both : 1.0;
        gt_coverage = n_gt ? static_cast<double>(n_both) / n_gt : 0.0;
        std::printf(
            "ground truth: bad pixels (|d - d_gt| > 1 px) %.2f %% of %zu matched "
            "pixels; %.1f %% of ground-truth pixels matched\n",
            100.0 * bad_pixel_rate, n_both, 100.0 * gt_coverage);
    }
}

void StereoApp::processImagePair(
    emslam::stereo::StereoFrontEnd& front, const FrameHandler& handle) const
{
    const auto cam = io::loadStereoCameraFromIniFile(m_calib, m_calib_section);
    const cv::Mat l = readImage(m_left, "left image"), r = readImage(m_right, "right image");
    auto obs = mrpt::obs::CObservationStereoImages::Create();
    obs->sensorLabel = "STEREO";
    obs->timestamp = mrpt::Clock::now();
    obs->imageLeft = mrpt::img::CImage(l, mrpt::img::SHALLOW_COPY);
    obs->imageRight = mrpt::img::CImage(r, mrpt::img::SHALLOW_COPY);
    obs->hasImageRight = true;
    obs->setStereoCameraParams(cam);
    const auto t0 = Clock::now();
    const auto f = front.process(*obs);
    handle(f, msSince(t0));
}

void StereoApp::processRawlog(emslam::stereo::StereoFrontEnd& front, const FrameHandler& handle)
{
    io::RawlogInput in(m_rawlog);
    std::vector<mrpt::obs::CObservation::Ptr> batch;
    std::size_t ignored = 0;
    // The same frames as emslam-mapper and emslam-odometry use.
    io::FrameStreamGuard guard;
    const auto warn = [](const std::string& warning)
    {
        if (!warning.empty())
        {
            std::fflush(stdout);
            std::fprintf(stderr, "%s: warning: %s\n", PROGRAM, warning.c_str());
        }
    };
    // SIGINT / SIGTERM / SIGHUP end the loop after the current frame;
    // the frames done are kept (exit 128 + signal).
    StopSignal::clear();
    const StopSignalGuard signals;
    while ((maxFrames() == 0 || frames_processed < maxFrames()) && !StopSignal::requested() &&
           in.next(batch))
    {
        const std::size_t record = in.recordsRead() - 1;
        for (const auto& o : batch)
        {
            const auto decision = guard.check(*o, record);
            if (decision.verdict == io::FrameStreamGuard::Verdict::Skip)
            {
                warn(decision.warning);
                continue;
            }
            emslam::stereo::StereoFrame f;
            const auto t0 = Clock::now();
            try
            {
                if (decision.verdict == io::FrameStreamGuard::Verdict::NotAFrame ||
                    !front.process(*o, f))
                {
                    ++ignored;
                    continue;
                }
            }
            catch (const std::bad_alloc&)
            {
                throw;
            }
            catch (const std::exception& e)
            {
                warn(guard.skipUnusable(record, emslam::util::shortExceptionMessage(e)));
                continue;
            }
            guard.accept();
            handle(f, msSince(t0));
        }
    }
    in.warnIfEndedEarly(PROGRAM);
    if (ignored > 0)
    {
        std::printf("ignored %zu observations of other classes\n", ignored);
    }
    skipped = guard.counts();
    skipped_reasons = guard.namedSkips();
    camera_change = guard.cameraChangeWarning();
    if (skipped.total() > 0)
    {
        std::printf("%s\n", guard.skippedText().c_str());
    }
}

}  // namespace emslam::apps
