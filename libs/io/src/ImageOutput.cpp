// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/ImageOutput.h>
#include <emslam/io/OutputFile.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <vector>

namespace emslam::io
{
void writeImageFile(const std::string& file, const cv::Mat& image, const std::string& name)
{
    const std::string shown = name.empty() ? file : name;
    std::vector<uchar> bytes;
    if (!cv::imencode(std::filesystem::path(shown).extension().string(), image, bytes))
    {
        throw std::runtime_error("cannot write '" + shown + "': the image cannot be encoded");
    }
    OutputFile f(file, shown);
    f.put(bytes.data(), bytes.size());
    f.close();
}

}  // namespace emslam::io
