// SPDX-License-Identifier: BSD-3-Clause
// Image headers: readImageHeader() on a file holding the input (PNG, JPEG,
// PNM and BMP headers, read before any image is decoded).
#include "FuzzFile.h"

#include <emslam/io/ImageHeader.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto& folder = emslam::fuzz::FuzzFolder::instance();
    const auto file = folder.write("image", emslam::fuzz::asText(data, size));
    try
    {
        const auto h = emslam::io::readImageHeader(file);
        if (h.width == 0 || h.height == 0)
        {
            std::abort();  // a zero side must be an error, never a result
        }
    }
    catch (const std::exception&)
    {
        // Garbled, truncated or unknown headers end in a clean error.
    }
    return 0;
}
