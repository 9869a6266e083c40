// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/PlyFile.h>
#include <emslam/io/AtomicFile.h>
#include <emslam/io/OutputFile.h>

#include <cstdint>

namespace emslam::apps
{
void savePly(const emslam::slam::IntensityCloud& cloud, const std::string& file)
{
    emslam::io::writeFileAtomically(
        file,
        [&](const std::string& partial)
        {
            emslam::io::OutputFile f(partial, file);
            auto& out = f.text();
            out << "ply\nformat binary_little_endian 1.0\ncomment emslam map\nelement vertex "
                << cloud.size()
                << "\nproperty float x\nproperty float y\nproperty float z\n"
                   "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
            for (std::size_t i = 0; i < cloud.size(); ++i)
            {
                const auto& p = cloud.points[i];
                const float xyz[3] = {p.x, p.y, p.z};
                const std::uint8_t g = cloud.intensity[i];
                const std::uint8_t rgb[3] = {g, g, g};
                f.put(xyz, sizeof(xyz));
                f.put(rgb, sizeof(rgb));
            }
            f.close();
            return true;
        });
}

}  // namespace emslam::apps
