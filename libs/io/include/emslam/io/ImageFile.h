// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

namespace emslam::io
{
/** Longest side of an image the dataset readers decode [px]: pixel
 * coordinates are 16-bit downstream (StereoFrame::pixels,
 * CObservation3DRangeScan::points3D_idxs_x/y). \ingroup emslam_io_grp */
constexpr std::uint32_t MAX_IMAGE_SIDE = 65535;

/** Most pixels of an image the dataset readers decode: 2^26 = 8192 x 8192
 * (64 MiB per 8-bit channel), 8 times a 4K UHD frame and 186 times a EuRoC
 * image. OpenCV's own limit (2^30 pixels) lets a 30000 x 30000 PNG of 875 KB
 * on disk decode to 900 MB. \ingroup emslam_io_grp */
constexpr std::uint64_t MAX_IMAGE_PIXELS = std::uint64_t{1} << 26;

/** The size of the image `file` as its header declares it (readImageHeader()),
 * without decoding it. Throws std::runtime_error, naming the file, if it does
 * not exist, its header cannot be read (see readImageHeader()), or the size
 * is over MAX_IMAGE_SIDE or MAX_IMAGE_PIXELS: "Image '<file>' is 30000x30000
 * (PNG header): over the limit of 67108864 pixels (8192x8192) and 65535 per
 * side; not decoded". \ingroup emslam_io_grp */
cv::Size imageFileSize(const std::string& file);

/** Reads an image file as stored (`cv::IMREAD_UNCHANGED`: depth and channels
 * kept), after imageFileSize() has checked its header. Throws, naming the
 * file, as imageFileSize() does, or if it does not decode. Used by
 * the dataset readers and emslam-stereo. \ingroup emslam_io_grp */
cv::Mat loadImageFile(const std::string& file);

/** loadImageFile(), for an image that must be `expected` in size: one of
 * another size is refused from its header, before decoding, with
 * std::runtime_error "Image size mismatch: '<file>' is <w>x<h>, expected
 * <w>x<h> (<expected_source>)". \ingroup emslam_io_grp */
cv::Mat loadImageFile(
    const std::string& file, const cv::Size& expected, const std::string& expected_source);

}  // namespace emslam::io
