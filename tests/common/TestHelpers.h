// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <functional>
#include <initializer_list>
#include <string>

namespace emslam::test
{
/** Writes `text` to `path` as is (binary mode: a CRLF stays CRLF), replacing
 * any previous content. */
void writeFile(const std::string& path, const std::string& text);

/** Expects `fn` to throw a `std::exception` whose what() contains every one of
 * `parts`; adds a GoogleTest failure (naming the missing part and the full
 * message) otherwise, or if `fn` does not throw at all. */
void expectThrowContaining(
    const std::function<void()>& fn, std::initializer_list<std::string> parts);

/** The largest difference between two poses: the distance between their
 * positions or the largest difference of a rotation matrix entry. */
double maxPoseDifference(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b);

}  // namespace emslam::test
