// SPDX-License-Identifier: BSD-3-Clause
// Test helper: image files whose header lies about their size.
#pragma once

#include <cstdint>
#include <string>

namespace emslam::test
{
/** Writes a small valid PNG to `path`, then rewrites the size in its IHDR
 * header to `width` x `height` (with the chunk's CRC recomputed, so that a
 * decoder believes it): a file of a few hundred bytes that declares a huge
 * image, as a 30000 x 30000 PNG of 875 KB does. */
void writePngDeclaring(const std::string& path, std::uint32_t width, std::uint32_t height);

}  // namespace emslam::test
