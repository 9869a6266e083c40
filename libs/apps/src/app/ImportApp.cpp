// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/CommandLine.h>
#include <emslam/apps/ImportApp.h>
#include <emslam/apps/ProgressLine.h>
#include <emslam/apps/RawlogRecording.h>
#include <emslam/apps/StopSignal.h>
#include <emslam/io/DatasetSequence.h>
#include <emslam/io/EurocSequence.h>
#include <emslam/io/InputOutputClash.h>
#include <emslam/io/KittiSequence.h>
#include <emslam/io/RawlogOutput.h>
#include <emslam/io/TumRgbdSequence.h>
#include <emslam/io/TumTrajectory.h>

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/core/Clock.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/system/os.h>
#include <mrpt/system/string_utils.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace fs = std::filesystem;

namespace emslam::apps
{
namespace
{
constexpr const char* PROGRAM = "emslam-import";
/** More frames than any dataset has: a typo such as 0:999999999 fails fast. */
constexpr std::size_t MAX_LISTED_FRAMES = 10'000'000;

/** The dataset being imported, and how the messages name it. */
struct FrameSource
{
    std::shared_ptr<const emslam::io::DatasetSequence> sequence;
    std::size_t size{0};
    bool has_gt{false};
    std::string description;

    emslam::io::SequenceFrame get(std::size_t i) const { return sequence->readFrame(i); }
    /** Timestamp of frame i [s], without loading it. */
    double time(std::size_t i) const { return sequence->timestamp(i); }
};

FrameSource makeSource(
    std::shared_ptr<const emslam::io::DatasetSequence> sequence, const std::string& description)
{
    FrameSource s;
    s.size = sequence->size();
    s.has_gt = sequence->hasGroundTruth();
    s.description = description;
    s.sequence = std::move(sequence);
    return s;
}

/** Parses "fx,fy,cx,cy". */
std::vector<double> parseIntrinsics(const std::string& s)
{
    std::vector<double> v;
    std::stringstream ss(s);
    std::string tok;
    while (std::getline(ss, tok, ','))
    {
        try
        {
            std::size_t pos = 0;
            v.push_back(std::stod(tok, &pos));
            if (tok.find_first_not_of(" \t", pos) != std::string::npos)
            {
                v.clear();
                break;
            }
        }
        catch (const std::exception&)
        {
            v.clear();
            break;
        }
    }
    if (v.size() != 4 || v[0] <= 0 || v[1] <= 0)
    {
        usageError(
            PROGRAM,
            "--intrinsics expects 'fx,fy,cx,cy' (positive focal lengths), got '" + s + "'");
    }
    return v;
}

/** A frame index or range bound of --frames (digits only). */
std::size_t parseFrameIndex(
    const std::string& item, const std::string& text, const char* what = "a frame index")
{
    if (text.empty() || text.size() > 9 ||
        text.find_first_not_of("0123456789") != std::string::npos)
    {
        usageError(
            PROGRAM, "--frames item '" + item + "': '" + text + "' is not " + what +
                         " (items are N, A:B or A:B:STEP, e.g. 0:50:2,49:1:-2)");
    }
    return static_cast<std::size_t>(std::stoul(text));
}

/** The STEP of an `A:B:STEP` item: a non-zero integer that leads from A to B. */
long long parseRangeStep(const std::string& item, const std::string& text, long long a, long long b)
{
    const bool negative = !text.empty() && text[0] == '-';
    const std::string digits = text.substr(negative || (!text.empty() && text[0] == '+') ? 1 : 0);
    const long long magnitude = static_cast<long long>(parseFrameIndex(item, digits, "a STEP"));
    if (magnitude == 0)
    {
        usageError(PROGRAM, "--frames item '" + item + "': STEP must not be 0");
    }
    const long long step = negative ? -magnitude : magnitude;
    if ((b - a) * step < 0)
    {
        usageError(
            PROGRAM, "--frames item '" + item + "': STEP " + text + " leads away from " +
                         std::to_string(b) + " (use a " + (step > 0 ? "negative" : "positive") +
                         " STEP)");
    }
    return step;
}

/** Appends the indexes of one `N`, `A:B` or `A:B:STEP` item (B included when reached). */
void appendFrameItem(const std::string& item, std::vector<std::size_t>& out)
{
    std::vector<std::string> parts;
    std::stringstream ss(item);
    for (std::string p; std::getline(ss, p, ':');)
    {
        parts.push_back(p);
    }
    if (!item.empty() && item.back() == ':')
    {
        parts.emplace_back();  // getline drops a trailing empty field: "5:" is "5" and ""
    }
    if (parts.empty() || parts.size() > 3)
    {
        usageError(PROGRAM, "--frames item '" + item + "': expected N, A:B or A:B:STEP");
    }
    const auto a = static_cast<long long>(parseFrameIndex(item, parts[0]));
    if (parts.size() == 1)
    {
        out.push_back(static_cast<std::size_t>(a));
        return;
    }
    const auto b = static_cast<long long>(parseFrameIndex(item, parts[1]));
    const long long step =
        parts.size() == 3 ? parseRangeStep(item, parts[2], a, b) : (b >= a ? 1 : -1);
    if (out.size() + static_cast<std::size_t>((b - a) / step + 1) > MAX_LISTED_FRAMES)
    {
        usageError(
            PROGRAM, "--frames lists more than " + std::to_string(MAX_LISTED_FRAMES) + " frames");
    }
    for (long long i = a; step > 0 ? i <= b : i >= b; i += step)
    {
        out.push_back(static_cast<std::size_t>(i));
    }
}

/** Parses the --frames list: comma-separated items, see ImportApp::frames. */
std::vector<std::size_t> parseFrameList(const std::string& list)
{
    std::vector<std::size_t> out;
    std::stringstream ss(list);
    for (std::string item; std::getline(ss, item, ',');)
    {
        appendFrameItem(mrpt::system::trim(item), out);
    }
    if (list.empty() || list.back() == ',')
    {
        appendFrameItem("", out);  // reports the empty item
    }
    return out;
}

/** The frames `first, first+step, ...` up to `last`, checked against the sequence. */
std::vector<std::size_t> rangeIndices(
    const FrameSource& src, std::size_t first, std::optional<std::size_t> last, std::size_t step)
{
    if (first >= src.size)
    {
        THROW_EXCEPTION_FMT(
            "--first %zu is beyond the last frame (%zu) of %s", first, src.size - 1,
            src.description.c_str());
    }
    const std::size_t last_idx = last.value_or(src.size - 1);
    if (last_idx >= src.size)
    {
        THROW_EXCEPTION_FMT(
            "--last %zu is beyond the last frame (%zu) of %s", last_idx, src.size - 1,
            src.description.c_str());
    }
    std::vector<std::size_t> indices;
    for (std::size_t i = first; i <= last_idx; i += step)
    {
        indices.push_back(i);
    }
    return indices;
}

void checkFrameList(const FrameSource& src, const std::vector<std::size_t>& frames)
{
    for (const std::size_t i : frames)
    {
        if (i >= src.size)
        {
            THROW_EXCEPTION_FMT(
                "--frames: frame index %zu is out of range: %zu frames (indexes 0..%zu) in %s", i,
                src.size, src.size - 1, src.description.c_str());
        }
    }
}

/** Median time between consecutive frames of the whole sequence [s]: robust to
 * the odd dropped frame. */
double medianFramePeriod(const FrameSource& src)
{
    std::vector<double> dt;
    for (std::size_t i = 1; i < src.size; i++)
    {
        dt.push_back(src.time(i) - src.time(i - 1));
    }
    if (dt.empty())
    {
        THROW_EXCEPTION("--frames: cannot re-time frames of a one-frame sequence");
    }
    std::nth_element(dt.begin(), dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2), dt.end());
    const double period = dt[dt.size() / 2];
    ASSERTMSG_(period > 0, "--frames: the sequence's median frame period is not positive");
    return period;
}

std::string humanBytes(std::uintmax_t n)
{
    char buf[32];
    if (n >= 1024ULL * 1024ULL)
    {
        std::snprintf(buf, sizeof(buf), "%.1f MiB", static_cast<double>(n) / (1024.0 * 1024.0));
    }
    else if (n >= 1024ULL)
    {
        std::snprintf(buf, sizeof(buf), "%.1f KiB", static_cast<double>(n) / 1024.0);
    }
    else
    {
        std::snprintf(buf, sizeof(buf), "%ju B", n);
    }
    return buf;
}

/** Opens and checks the dataset the settings name. */
FrameSource openDataset(const ImportApp& app)
{
    if (app.dataset == "kitti")
    {
        auto r = std::make_shared<emslam::io::KittiSequence>();
        r->sensor_label = app.sensor_label.empty() ? "STEREO" : app.sensor_label;
        if (app.kitti_time_offset)
        {
            r->time_offset = *app.kitti_time_offset;
        }
        r->open(app.input_dir, app.kitti_poses_file);
        return makeSource(
            r, mrpt::format(
                   "KITTI sequence '%s' (%zu frames, %ux%u)", app.input_dir.c_str(), r->size(),
                   r->imageWidth(), r->imageHeight()));
    }
    if (app.dataset == "euroc")
    {
        auto r = std::make_shared<emslam::io::EurocSequence>();
        r->sensor_label = app.sensor_label.empty() ? "STEREO" : app.sensor_label;
        r->open(app.input_dir, app.euroc_gt_file);
        return makeSource(
            r, mrpt::format(
                   "EuRoC sequence '%s' (%zu stereo pairs, %ux%u, %zu unpaired)",
                   r->directory().c_str(), r->size(), r->imageWidth(), r->imageHeight(),
                   r->unpairedCount()));
    }
    if (app.dataset == "tum")
    {
        auto r = std::make_shared<emslam::io::TumRgbdSequence>();
        r->sensor_label = app.sensor_label.empty() ? "RGBD" : app.sensor_label;
        if (!app.tum_intrinsics.empty())
        {
            const auto v = parseIntrinsics(app.tum_intrinsics);
            r->intrinsics.setIntrinsicParamsFromValues(v[0], v[1], v[2], v[3]);
        }
        r->open(app.input_dir);
        FrameSource src = makeSource(
            r,
            mrpt::format(
                "TUM RGB-D sequence '%s' (%zu colour/depth pairs, %ux%u, %zu colour images without "
                "depth)",
                app.input_dir.c_str(), r->size(), r->imageWidth(), r->imageHeight(),
                r->unassociatedCount()));
        if (!app.gt_out_file.empty() && !r->hasGroundTruth())
        {
            THROW_EXCEPTION_FMT(
                "--gt-out given but '%s/groundtruth.txt' does not exist", app.input_dir.c_str());
        }
        return src;
    }
    THROW_EXCEPTION_FMT("Unknown dataset format '%s'", app.dataset.c_str());
}
/** What the import wrote, in one line on stdout. */
void printImportSummary(const ImportApp& app)
{
    std::cout << PROGRAM << ": wrote " << app.frames_written << " frames to '" << app.output_file
              << "' (" << humanBytes(app.output_bytes) << ")";
    if (!app.gt_out_file.empty())
    {
        std::cout << ", " << app.poses_written << " ground-truth poses to '" << app.gt_out_file
                  << "'";
    }
    if (app.frames_without_gt > 0)
    {
        std::cout << ", " << app.frames_without_gt << " frames without ground truth skipped";
    }
    std::cout << mrpt::format(
        ", in %.2f s (%.1f ms/frame)\n", app.elapsed_seconds,
        1e3 * app.elapsed_seconds / static_cast<double>(app.frames_written));
    std::cout.flush();
}
/** No output may replace a file of the dataset or the ground truth. */
void requireOutputsAreNotDatasetFiles(const ImportApp& app, const FrameSource& src)
{
    std::vector<io::RolePath> inputs{
        {"the ground truth (--gt)",
         app.dataset == "kitti" ? app.kitti_poses_file : app.euroc_gt_file}};
    for (const auto& f : src.sequence->inputFiles())
    {
        inputs.push_back({"a file of the dataset", f});
    }
    io::requireOutputsAreNotInputs(
        {{"output rawlog", app.output_file}, {"ground-truth output (--gt-out)", app.gt_out_file}},
        inputs);
}

void warnRetimed(double t0, double period, std::size_t first_listed)
{
    std::cerr << PROGRAM
              << mrpt::format(
                     ": the frame list is not increasing: written frame k gets time "
                     "%.6f + k * %.6f s (t of frame %zu + k * median frame period)\n",
                     t0, period, first_listed);
}
void resetResults(ImportApp& app)
{
    app.frames_written = 0;
    app.poses_written = 0;
    app.frames_without_gt = 0;
    app.output_bytes = 0;
    app.retimed = false;
}
}  // namespace

ImportApp::ImportApp() : App(PROGRAM) {}

/** The command line of emslam-import, each argument added to `cmd` in the
 * order of its help. */
struct ImportApp::Arguments
{
    TCLAP::CmdLine cmd{
        "Imports a KITTI odometry, EuRoC MAV or TUM RGB-D sequence into a gz-compressed rawlog of "
        "stock MRPT observations (CObservationStereoImages / CObservation3DRangeScan), and its "
        "ground truth into a TUM trajectory file. Outputs are written as <name>.partial and "
        "renamed only when the import succeeded; Ctrl-C keeps the frames imported so far (exit "
        "130). Examples: '" +
            std::string(PROGRAM) +
            " kitti sequences/06 --gt poses/06.txt -o k06.rawlog --gt-out k06.tum', '" + PROGRAM +
            " euroc V1_01_easy/mav0 --gt groundtruth_left_cam.csv -o v101.rawlog --gt-out "
            "v101.tum', '" +
            PROGRAM + " tum rgbd_dataset_freiburg1_xyz -o fr1xyz.rawlog --gt-out fr1xyz.tum'.",
        ' ', std::string("emslam-import (") + mrpt::system::MRPT_getVersion() + ")"};
    TCLAP::UnlabeledValueArg<std::string> arg_dataset{
        "dataset", "Dataset format: kitti, euroc or tum.", true, "", "kitti|euroc|tum", cmd};
    TCLAP::UnlabeledValueArg<std::string> arg_dir{
        "input_dir",
        "Sequence folder: KITTI 'sequences/NN', EuRoC 'mav0' (or its parent), TUM RGB-D folder "
        "with rgb.txt and depth.txt.",
        true,
        "",
        "DIR",
        cmd};
    TCLAP::ValueArg<std::string> arg_out{
        "o",          "output", "Output rawlog file (gz-compressed, observations only).", true, "",
        "OUT.rawlog", cmd};
    TCLAP::ValueArg<std::string> arg_gt{
        "",
        "gt",
        "Ground truth in the dataset's own format: kitti 'poses/NN.txt' (3x4 per frame), euroc "
        "left-camera CSV 'timestamp_ns,x,y,z,qx,qy,qz,qw' (tum: groundtruth.txt is read from the "
        "folder). --poses is its old kitti spelling.",
        false,
        "",
        "GT",
        cmd};
    TCLAP::ValueArg<std::string> arg_gt_out{
        "",
        "gt-out",
        "Write the ground truth of the imported frames here (TUM format, left/colour camera "
        "relative to the first imported frame).",
        false,
        "",
        "GT.tum",
        cmd};
    TCLAP::ValueArg<std::string> arg_intr{
        "",    "intrinsics", "tum: camera intrinsics (default 525,525,319.5,239.5).",
        false, "",           "fx,fy,cx,cy",
        cmd};
    TCLAP::ValueArg<double> arg_time_offset{
        "",
        "time-offset",
        "kitti: UNIX time [s] given to times.txt's zero (default 1317340800 = "
        "2011-09-30 00:00:00 UTC).",
        false,
        0.0,
        "SECONDS",
        cmd};
    TCLAP::ValueArg<long long> arg_first{
        "", "first", "First frame index to import (0-based, default 0).", false, 0, "N", cmd};
    TCLAP::ValueArg<long long> arg_last{
        "",  "last", "Last frame index to import (inclusive, default: the last frame).", false, -1,
        "N", cmd};
    TCLAP::ValueArg<long long> arg_step{
        "", "step", "Import every K-th frame (default 1).", false, 1, "K", cmd};
    TCLAP::ValueArg<std::string> arg_frames{
        "",
        "frames",
        "Import exactly these frames, in this order (not with --first/--last/--step): "
        "comma-separated N, A:B or A:B:STEP (B included when reached, STEP may be negative). "
        "E.g. '0:50:2,49:1:-2': forward on even frames, back on odd ones. A list that is not "
        "increasing re-times the frames: t(first listed) + k * median frame period.",
        false,
        "",
        "LIST",
        cmd};
    TCLAP::ValueArg<std::string> arg_label{
        "",    "label", "Sensor label of the observations (default STEREO, or RGBD for tum).",
        false, "",      "LABEL",
        cmd};
    TCLAP::ValueArg<int> arg_gz{
        "",     "gz-level", "gzip compression level of the rawlog, 0..9 (default 1).", false, 1,
        "0..9", cmd};
    TCLAP::SwitchArg arg_quiet{"q", "quiet", "No progress or summary output.", cmd, false};
};

bool ImportApp::parseArguments(int argc, const char** argv)
{
    Arguments args;
    m_initialized = false;
    // Usage shows the program name, not the path it was started from.
    if (!parseCommandLine(args.cmd, argc, argv, {{"--poses", "--gt", 0, "POSES.txt"}}))
    {
        return false;
    }

    takeDataset(args);
    takeSelection(args);
    m_initialized = true;
    return true;
}

void ImportApp::takeDataset(Arguments& args)
{
    dataset = args.arg_dataset.getValue();
    if (dataset != "kitti" && dataset != "euroc" && dataset != "tum")
    {
        usageError("unknown dataset format '" + dataset + "' (expected kitti, euroc or tum)");
    }
    input_dir = args.arg_dir.getValue();
    output_file = args.arg_out.getValue();
    kitti_poses_file = dataset == "kitti" ? args.arg_gt.getValue() : std::string{};
    euroc_gt_file = dataset == "euroc" ? args.arg_gt.getValue() : std::string{};
    gt_out_file = args.arg_gt_out.getValue();
    tum_intrinsics = args.arg_intr.getValue();
    sensor_label = args.arg_label.getValue();
    quiet = args.arg_quiet.getValue();
    gz_level = args.arg_gz.getValue();

    if (args.arg_gt.isSet() && dataset == "tum")
    {
        usageError("--gt is for kitti and euroc (tum: groundtruth.txt in the folder is read)");
    }
    if (args.arg_intr.isSet() && dataset != "tum")
    {
        usageError("--intrinsics is for tum only (kitti/euroc read their calibration files)");
    }
    if (args.arg_time_offset.isSet() && dataset != "kitti")
    {
        usageError("--time-offset is for kitti only (euroc and tum carry UNIX times)");
    }
    kitti_time_offset.reset();
    if (args.arg_time_offset.isSet())
    {
        kitti_time_offset = args.arg_time_offset.getValue();
    }
    if (!tum_intrinsics.empty())
    {
        parseIntrinsics(tum_intrinsics);
    }
}

void ImportApp::takeSelection(Arguments& args)
{
    if (args.arg_first.getValue() < 0)
    {
        usageError("--first must be >= 0");
    }
    if (args.arg_last.isSet() && args.arg_last.getValue() < 0)
    {
        usageError("--last must be >= 0");
    }
    if (args.arg_step.getValue() < 1)
    {
        usageError("--step must be >= 1");
    }
    if (args.arg_last.isSet() && args.arg_last.getValue() < args.arg_first.getValue())
    {
        usageError("--last must not be smaller than --first");
    }
    if (gz_level < 0 || gz_level > 9)
    {
        usageError("--gz-level must be in 0..9");
    }
    first = static_cast<std::size_t>(args.arg_first.getValue());
    last.reset();
    if (args.arg_last.isSet())
    {
        last = static_cast<std::size_t>(args.arg_last.getValue());
    }
    step = static_cast<std::size_t>(args.arg_step.getValue());
    frames.clear();
    if (args.arg_frames.isSet())
    {
        if (args.arg_first.isSet() || args.arg_last.isSet() || args.arg_step.isSet())
        {
            usageError("--frames cannot be combined with --first, --last or --step");
        }
        frames = parseFrameList(args.arg_frames.getValue());
    }
    if (!gt_out_file.empty())
    {
        if (dataset == "kitti" && kitti_poses_file.empty())
        {
            usageError("--gt-out needs --gt (poses/NN.txt) for kitti");
        }
        if (dataset == "euroc" && euroc_gt_file.empty())
        {
            usageError("--gt-out needs --gt for euroc");
        }
        if (fs::path(gt_out_file).lexically_normal() == fs::path(output_file).lexically_normal())
        {
            usageError("--gt-out and --output name the same file");
        }
    }
}

void ImportApp::execute()
{
    ASSERTMSG_(
        m_initialized || !dataset.empty(),
        "ImportApp::run(): call initialize() (or fill the settings) first");
    ASSERTMSG_(!output_file.empty(), "ImportApp: no output file");
    ASSERTMSG_(step >= 1, "ImportApp: step must be >= 1");
    const auto t_start = std::chrono::steady_clock::now();
    resetResults(*this);
    // A bad output path must not cost a whole import.
    io::RawlogOutput::checkOutputFolders(output_file, gt_out_file);

    const FrameSource src = openDataset(*this);

    requireOutputsAreNotDatasetFiles(*this, src);

    // Frame selection, and new times if the list goes back in time.
    checkFrameList(src, frames);
    const std::vector<std::size_t> indices =
        frames.empty() ? rangeIndices(src, first, last, step) : frames;
    ASSERTMSG_(!indices.empty(), "ImportApp: no frame selected");
    // Any step back (or repeat) would put the rawlog out of time order.
    retimed =
        std::adjacent_find(indices.begin(), indices.end(), std::greater_equal<>()) != indices.end();
    const double period = retimed ? medianFramePeriod(src) : 0.0;
    const double t0 = src.time(indices.front());

    if (!quiet)
    {
        std::cerr << PROGRAM << ": importing " << indices.size() << " of " << src.description
                  << " into '" << output_file << "'\n";
        if (retimed)
        {
            warnRetimed(t0, period, indices.front());
        }
    }

    std::optional<mrpt::poses::CPose3D> T_world_ref;
    const RawlogRecording rec = recordRawlog(
        PROGRAM, output_file, gz_level, gt_out_file, indices.size(), !quiet,
        [&](std::size_t k, mrpt::serialization::CArchive& out, emslam::io::TumTrajectory& gt)
        {
            auto fr = src.get(indices[k]);
            if (retimed)
            {
                fr.t = t0 + static_cast<double>(k) * period;
                fr.obs->timestamp = mrpt::Clock::fromDouble(fr.t);
            }
            out << *fr.obs;
            if (fr.ground_truth)
            {
                if (!T_world_ref)
                {
                    T_world_ref = *fr.ground_truth;
                    gt.add(fr.t, mrpt::poses::CPose3D());  // exactly the identity
                }
                else
                {
                    // T_ref_cam = inv(T_world_ref) * T_world_cam
                    gt.add(fr.t, *fr.ground_truth - *T_world_ref);
                }
            }
            else if (src.has_gt)
            {
                ++frames_without_gt;
            }
        });
    frames_written = rec.frames_written;
    poses_written = rec.poses_written;

    output_bytes = fs::file_size(output_file);
    elapsed_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    if (!quiet)
    {
        printImportSummary(*this);
    }
}

}  // namespace emslam::apps
