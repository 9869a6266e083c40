// SPDX-License-Identifier: BSD-3-Clause
#include "TestHelpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <fstream>

namespace emslam::test
{
void writeFile(const std::string& path, const std::string& text)
{
    std::ofstream f(path, std::ios::binary);  // binary: keep CRLF as written
    f << text;
}

void expectThrowContaining(
    const std::function<void()>& fn, std::initializer_list<std::string> parts)
{
    try
    {
        fn();
        ADD_FAILURE() << "no exception thrown";
    }
    catch (const std::exception& e)
    {
        const std::string msg = e.what();
        for (const auto& p : parts)
        {
            EXPECT_NE(msg.find(p), std::string::npos) << "message lacks '" << p << "': " << msg;
        }
    }
}

double maxPoseDifference(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b)
{
    double d = (a.translation() - b.translation()).norm();
    const auto& A = a.getRotationMatrix();
    const auto& B = b.getRotationMatrix();
    for (int r = 0; r < 3; ++r)
    {
        for (int c = 0; c < 3; ++c)
        {
            d = std::max(d, std::abs(A(r, c) - B(r, c)));
        }
    }
    return d;
}

}  // namespace emslam::test
