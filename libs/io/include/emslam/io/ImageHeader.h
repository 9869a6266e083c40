// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstdint>
#include <string>

namespace emslam::io
{
/** The size an image file declares in its header. \ingroup emslam_io_grp */
struct ImageHeader
{
    std::uint32_t width{0};   //!< [px]
    std::uint32_t height{0};  //!< [px]
    /** "PNG", "JPEG", "BMP" or "PNM". */
    const char* format{""};
};

/** Reads the width and height of the image `file` from its header alone (a
 * few bytes; for JPEG, the segment headers up to the frame header), so that
 * an image too large to decode is refused before it is decoded: a 30000 x
 * 30000 PNG takes 875 KB on disk and 900 MB once decoded. Formats: PNG
 * (IHDR), JPEG (SOF0 to SOF15), PNM (P1 to P6: PBM, PGM, PPM) and BMP, which
 * cover the images of the KITTI, EuRoC and TUM RGB-D datasets. Throws
 * std::runtime_error "Cannot read image '<file>': <reason>" if the file cannot
 * be read, is in another format, or its header is truncated or declares a
 * zero side. \ingroup emslam_io_grp */
ImageHeader readImageHeader(const std::string& file);

}  // namespace emslam::io
