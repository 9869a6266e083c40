// SPDX-License-Identifier: BSD-3-Clause
#include "SimulatedHall.h"

#include "TestData.h"

#include <emslam/apps/SimApp.h>
#include <emslam/io/RawlogInput.h>
#include <emslam/io/TumTrajectory.h>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace emslam::test
{
std::string simulatedHall(std::size_t frames)
{
    static const std::string dir = makeTempDir("simulated_hall");
    const std::string file = dir + "/hall" + std::to_string(frames) + ".rawlog";
    if (!mrpt::system::fileExists(file))
    {
        emslam::apps::SimApp sim;
        const std::vector<std::string> args = {
            "emslam-sim",   sourceDir() + "/config/sim/hall_double_loop.ini",
            "-o",           file,
            "--gt-out",     dir + "/hall" + std::to_string(frames) + ".tum",
            "--max-frames", std::to_string(frames),
            "--quiet"};
        std::vector<const char*> argv;
        for (const auto& a : args)
        {
            argv.push_back(a.c_str());
        }
        sim.initialize(static_cast<int>(argv.size()), argv.data());
        sim.run();
    }
    return file;
}

void writeEditedHall(
    const std::string& rawlog,
    std::size_t frames,
    const std::function<void(std::size_t, mrpt::obs::CObservationStereoImages&)>& edit)
{
    emslam::io::RawlogInput in(simulatedHall(frames));
    mrpt::io::CFileGZOutputStream out(rawlog);
    auto arch = mrpt::serialization::archiveFrom(out);
    std::vector<mrpt::obs::CObservation::Ptr> batch;
    for (std::size_t i = 0; in.next(batch); i++)
    {
        ASSERT_EQ(batch.size(), 1U);
        auto stereo = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(batch[0]);
        ASSERT_TRUE(stereo);
        edit(i, *stereo);
        arch << *stereo;
    }
}

void writeHallFrames(const std::string& rawlog, std::size_t first, std::size_t count)
{
    emslam::io::RawlogInput in(simulatedHall(first + count));
    mrpt::io::CFileGZOutputStream out(rawlog);
    auto arch = mrpt::serialization::archiveFrom(out);
    std::vector<mrpt::obs::CObservation::Ptr> batch;
    for (std::size_t i = 0; in.next(batch); i++)
    {
        for (const auto& o : batch)
        {
            if (i >= first)
            {
                arch << *o;
            }
        }
    }
}

void resizeStereoFrame(mrpt::obs::CObservationStereoImages& stereo, int width, int height)
{
    cv::Mat left, right;
    cv::resize(stereo.imageLeft.asCvMatRef(), left, cv::Size(width, height));
    cv::resize(stereo.imageRight.asCvMatRef(), right, cv::Size(width, height));
    stereo.imageLeft = mrpt::img::CImage(left, mrpt::img::DEEP_COPY);
    stereo.imageRight = mrpt::img::CImage(right, mrpt::img::DEEP_COPY);
    auto cam = stereo.getStereoCameraParams();
    cam.leftCamera.scaleToResolution(width, height);
    cam.rightCamera.scaleToResolution(width, height);
    stereo.setStereoCameraParams(cam);
}

void shrinkRightImage(mrpt::obs::CObservationStereoImages& stereo)
{
    cv::Mat small;
    cv::resize(stereo.imageRight.asCvMatRef(), small, cv::Size(160, 120));
    stereo.imageRight = mrpt::img::CImage(small, mrpt::img::DEEP_COPY);
}

std::vector<double> trajectoryTimes(const std::string& tum_file)
{
    std::vector<double> t;
    for (const auto& p : emslam::io::TumTrajectory::fromFile(tum_file).poses)
    {
        t.push_back(p.t);
    }
    return t;
}

}  // namespace emslam::test
