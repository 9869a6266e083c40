// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/DatasetSequence.h>

namespace emslam::io
{
double DatasetSequence::meanFrameRate(double fallback) const
{
    const std::size_t n = size();
    if (n < 2)
    {
        return fallback;
    }
    const double span = timestamp(n - 1) - timestamp(0);
    return span > 0 ? static_cast<double>(n - 1) / span : fallback;
}

}  // namespace emslam::io
