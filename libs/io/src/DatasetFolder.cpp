// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/DatasetFolder.h>
#include <emslam/io/EurocSequence.h>
#include <emslam/io/KittiSequence.h>
#include <emslam/io/TumRgbdSequence.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace fs = std::filesystem;

namespace emslam::io
{
namespace
{
bool isFile(const fs::path& p)
{
    std::error_code ec;
    return fs::is_regular_file(p, ec);
}

bool isDir(const fs::path& p)
{
    std::error_code ec;
    return fs::is_directory(p, ec);
}

bool isKittiSequence(const fs::path& dir)
{
    return isFile(dir / "calib.txt") && isFile(dir / "times.txt") && isDir(dir / "image_0") &&
           isDir(dir / "image_1");
}

bool isEurocMav0(const fs::path& dir)
{
    return isFile(dir / "cam0" / "data.csv") && isFile(dir / "cam1" / "data.csv");
}

/** The KITTI sequences in `dir`/sequences, sorted. */
std::vector<fs::path> kittiSequencesIn(const fs::path& dir)
{
    std::vector<fs::path> found;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir / "sequences", ec))
    {
        if (isKittiSequence(e.path()))
        {
            found.push_back(e.path());
        }
    }
    std::sort(found.begin(), found.end());
    return found;
}

DatasetFolder kitti(const fs::path& sequence)
{
    DatasetFolder f;
    f.format = DatasetFolder::Format::Kitti;
    f.sequence_dir = sequence.string();
    // sequences/NN -> poses/NN.txt, as the official layout has it.
    const fs::path seq = sequence.lexically_normal();
    const fs::path name = seq.has_filename() ? seq.filename() : seq.parent_path().filename();
    const fs::path poses =
        fs::absolute(sequence) / ".." / ".." / "poses" / (name.string() + ".txt");
    if (isFile(poses))
    {
        f.ground_truth_file = poses.lexically_normal().string();
    }
    return f;
}

DatasetFolder euroc(const fs::path& mav0)
{
    DatasetFolder f;
    f.format = DatasetFolder::Format::Euroc;
    f.sequence_dir = mav0.string();
    for (const fs::path& dir : {mav0, fs::absolute(mav0) / ".."})
    {
        const fs::path gt = dir / "groundtruth_left_cam.csv";
        if (isFile(gt))
        {
            f.ground_truth_file = gt.lexically_normal().string();
            break;
        }
    }
    return f;
}
}  // namespace

std::string DatasetFolder::formatName() const
{
    switch (format)
    {
        case Format::Kitti:
            return "KITTI odometry";
        case Format::Euroc:
            return "EuRoC MAV";
        case Format::TumRgbd:
            return "TUM RGB-D";
    }
    return "";
}

bool DatasetFolder::isFolder(const std::string& path)
{
    return isDir(path);
}

DatasetFolder DatasetFolder::detect(const std::string& dir)
{
    const fs::path d(dir);
    if (isKittiSequence(d))
    {
        return kitti(d);
    }
    if (isEurocMav0(d))
    {
        return euroc(d);
    }
    if (isEurocMav0(d / "mav0"))
    {
        return euroc(d / "mav0");
    }
    if (isFile(d / "rgb.txt") && isFile(d / "depth.txt"))
    {
        DatasetFolder f;
        f.format = Format::TumRgbd;
        f.sequence_dir = dir;
        return f;
    }
    const auto sequences = kittiSequencesIn(d);
    if (sequences.size() == 1)
    {
        return kitti(sequences.front());
    }
    if (sequences.size() > 1)
    {
        std::string names;
        for (const auto& s : sequences)
        {
            names += (names.empty() ? "" : ", ") + s.string();
        }
        throw std::invalid_argument(
            "'" + dir + "' holds " + std::to_string(sequences.size()) +
            " KITTI sequences; give one of them: " + names);
    }
    throw std::invalid_argument(
        "'" + dir +
        "' is a folder but no dataset this program reads: expected a KITTI odometry sequence "
        "(calib.txt, times.txt, image_0/, image_1/; or a folder with sequences/NN), a EuRoC "
        "MAV 'mav0' folder or its parent (cam0/data.csv, cam1/data.csv), or a TUM RGB-D folder "
        "(rgb.txt, depth.txt)");
}

std::shared_ptr<DatasetSequence> DatasetFolder::open() const
{
    switch (format)
    {
        case Format::Kitti:
        {
            auto r = std::make_shared<KittiSequence>();
            r->open(sequence_dir, ground_truth_file);
            return r;
        }
        case Format::Euroc:
        {
            auto r = std::make_shared<EurocSequence>();
            r->open(sequence_dir, ground_truth_file);
            return r;
        }
        case Format::TumRgbd:
        {
            auto r = std::make_shared<TumRgbdSequence>();
            r->open(sequence_dir);
            return r;
        }
    }
    throw std::logic_error("DatasetFolder: unknown format");
}

}  // namespace emslam::io
