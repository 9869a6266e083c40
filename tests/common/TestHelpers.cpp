// SPDX-License-Identifier: BSD-3-Clause
#include "TestHelpers.h"

#include <gtest/gtest.h>

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

}  // namespace emslam::test
