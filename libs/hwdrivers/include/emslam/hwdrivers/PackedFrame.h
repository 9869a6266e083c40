// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace emslam::hwdrivers
{
/** How a multi-sensor camera packs the images of its sensors into the one
 * frame it transfers. Every sensor image is 8-bit, `width` x `height`, and
 * "channel k" is the k-th image of the packed frame (which physical camera
 * it is depends on the camera: see CDigiclopsStereoCamera's `channel_*` keys).
 *
 * - `PIXEL_INTERLEAVED_24` ("rgb24"): 3 channels, 3 bytes per pixel, pixels
 *   row-major with no row padding; byte k of a pixel belongs to channel k.
 *   This is what a trinocular head sends in an IIDC RGB8 mode, each colour
 *   plane carrying one camera. Frame size: 3 * width * height bytes.
 * - `BYTE_INTERLEAVED_16` ("interleaved16"): 2 channels, 16 bits per pixel
 *   sent as two bytes; byte k (in transfer order, not host order) belongs to
 *   channel k. This is a 2-camera head in an IIDC MONO16 / Format7 16-bit
 *   mode. Frame size: 2 * width * height bytes.
 * - `PLANAR_8` ("planar8"): `channels` (2 or 3) mono8 images stacked
 *   vertically, channel k in rows [k h, (k+1) h). Frame size:
 *   channels * width * height bytes.
 *
 * \ingroup emslam_hwdrivers_grp \sa deinterleave(), interleave() */
enum class PackedLayout
{
    PIXEL_INTERLEAVED_24,
    BYTE_INTERLEAVED_16,
    PLANAR_8
};

/** Parses "rgb24", "interleaved16" or "planar8"; throws std::invalid_argument
 * naming the accepted values otherwise. */
PackedLayout packedLayoutFromString(const std::string& s);
/** The INI name of a layout ("rgb24", "interleaved16", "planar8"). */
std::string toString(PackedLayout layout);

/** Geometry of a packed frame. \ingroup emslam_hwdrivers_grp */
struct PackedFrameFormat
{
    PackedLayout layout{
        PackedLayout::PIXEL_INTERLEAVED_24};  //!< how the images are packed in a frame
    /** Size of each sensor image [px]. */
    ///@{
    unsigned int width{0}, height{0};
    ///@}
    /** Number of sensor images in a PLANAR_8 frame (2 or 3); the interleaved
     * layouts always have 3 (rgb24) or 2 (interleaved16). */
    unsigned int planar_channels{3};

    /** Number of sensor images in one packed frame. */
    unsigned int channels() const;
    /** Expected size of one packed frame [bytes]. */
    std::size_t bytesPerFrame() const;
};

/** Splits one packed frame into its channels() sensor images (CV_8UC1,
 * `height` x `width`, owning their data), channel k at index k. Throws
 * std::invalid_argument if `size` differs from `fmt.bytesPerFrame()` or the
 * format has a zero size.
 * \ingroup emslam_hwdrivers_grp */
std::vector<cv::Mat> deinterleave(
    const std::uint8_t* data, std::size_t size, const PackedFrameFormat& fmt);

/** The inverse of deinterleave(): packs `images` (channels() CV_8UC1 images
 * of the format's size) into one frame. Used by tests and by anyone who wants
 * to replay a camera. Throws std::invalid_argument on a count or size mismatch.
 * \ingroup emslam_hwdrivers_grp */
std::vector<std::uint8_t> interleave(
    const std::vector<cv::Mat>& images, const PackedFrameFormat& fmt);

}  // namespace emslam::hwdrivers
