// SPDX-License-Identifier: BSD-3-Clause
// Maps a rawlog with emslam's SLAM pipeline from C++, as emslam-mapper does
// without its outputs: every stereo / RGB-D observation goes through
// EntropySlam::process(), then finish() runs the final rectification.
//   map_rawlog CONFIG.ini DATASET.rawlog [MAX_FRAMES]
#include <emslam/io/RawlogInput.h>
#include <emslam/slam/EntropySlam.h>
#include <emslam/slam/registerAllClasses.h>

#include <mrpt/config/CConfigFile.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

int main(int argc, char** argv)
{
    if (argc < 3)
    {
        std::fprintf(stderr, "usage: %s CONFIG.ini DATASET.rawlog [MAX_FRAMES]\n", argv[0]);
        return 2;
    }
    try
    {
        emslam::slam::registerAllClasses();
        mrpt::config::CConfigFile ini(argv[1]);
        emslam::slam::EntropySlam::TParameters p;
        p.loadFromConfigFile(ini);  // throws naming a bad key
        const std::size_t max_frames = argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 0;

        emslam::slam::EntropySlam mapper(p);
        emslam::io::RawlogInput in(argv[2]);
        std::vector<mrpt::obs::CObservation::Ptr> batch;
        while ((max_frames == 0 || mapper.frameCount() < max_frames) && in.next(batch))
        {
            for (const auto& o : batch)
            {
                if (max_frames == 0 || mapper.frameCount() < max_frames)
                {
                    mapper.process(*o);
                }
            }
        }
        in.warnIfEndedEarly(argv[0]);
        if (mapper.frameCount() == 0)
        {
            std::fprintf(stderr, "%s: no stereo or RGB-D observation in '%s'\n", argv[0], argv[2]);
            return 1;
        }
        mapper.finish();
        const auto& last = mapper.slamPoses().back().T_world_frame;
        std::printf(
            "%zu frames, %zu keyframes, %zu egomotion failures, final energy %.4f\n"
            "last SLAM pose: x %.3f y %.3f z %.3f m\n",
            mapper.frameCount(), mapper.keyframes().size(), mapper.egomotionFailures(),
            mapper.finalEnergy(), last.x(), last.y(), last.z());
        return 0;
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "%s: error: %s\n", argv[0], e.what());
        return 1;
    }
}
