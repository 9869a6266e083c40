// SPDX-License-Identifier: BSD-3-Clause
#include "ImageFile.h"

#include <mrpt/core/exceptions.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <system_error>

namespace emslam::io
{
cv::Mat loadImageFile(const std::string& file)
{
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
    {
        THROW_EXCEPTION_FMT("Image file '%s' does not exist", file.c_str());
    }
    cv::Mat im = cv::imread(file, cv::IMREAD_UNCHANGED);
    if (im.empty())
    {
        THROW_EXCEPTION_FMT("Cannot read image '%s' (not a valid image file)", file.c_str());
    }
    return im;
}

}  // namespace emslam::io
