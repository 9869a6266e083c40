// SPDX-License-Identifier: BSD-3-Clause
#pragma once

namespace emslam::slam
{
/** Makes glibc keep the frame-sized buffers (up to 32 MiB: images, gradients,
 * disparities, clouds) that every frame allocates and frees in the heap
 * instead of returning them to the kernel, so the next frame reuses them
 * without page faults. By default glibc maps such blocks with mmap and
 * unmaps them on free: at KITTI's full resolution that cost more than the
 * work itself (GLM features 25.9 -> 1.2 ms per frame, doc/apps/emslam-odometry.md).
 * The peak memory is the same; only its release at the end is deferred.
 * Call it once, before the first frame; appMain() and the benchmarks do.
 * A no-op where the C library is not glibc.
 * \ingroup emslam_slam_grp */
void keepFrameBuffersInProcess();

}  // namespace emslam::slam
