// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/FrameMemoryPolicy.h>

#include <cstdlib>  // defines __GLIBC__ on glibc systems

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace emslam::slam
{
void keepFrameBuffersInProcess()
{
#if defined(__GLIBC__)
    // Blocks above 32 MiB (glibc's largest threshold; SGBM's 8-path cost
    // volume at full size) are still mapped on their own; freed heap memory
    // is returned to the kernel only beyond 256 MiB at the top of the heap.
    constexpr int MMAP_THRESHOLD = 32 << 20;
    constexpr int TRIM_THRESHOLD = 256 << 20;
    mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD);
    mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD);
#endif
}

}  // namespace emslam::slam
