// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace
{
enum class Shape
{
    Box,
    Ball
};

struct Params
{
    bool on{false};
    int count{3};
    float gain{0.5f};
    double length{0.1};
    std::string name{"abc"};
    Shape shape{Shape::Box};
};

void visit(Params& p, emslam::util::ConfigVisitor& v)
{
    v.field("on", p.on, "switch");
    v.field("count", p.count);
    v.field("gain", p.gain, "[-]");
    v.field("length", p.length, "[m]");
    v.field("name", p.name);
    v.text(
        "shape", p.shape, [](Shape s) { return std::string(s == Shape::Ball ? "ball" : "box"); },
        [](const std::string& t) { return t == "ball" ? Shape::Ball : Shape::Box; });
}

/** `p` saved into [S] and parsed again (MRPT pitfall: reading back from the
 * object saved into returns defaults). */
mrpt::config::CConfigFileMemory savedText(const Params& p)
{
    mrpt::config::CConfigFileMemory out;
    emslam::util::saveByVisit(p, out, "S", visit);
    return mrpt::config::CConfigFileMemory(out.getContent());
}
}  // namespace

TEST(ConfigVisitor, savedValuesLoadBackEqual)
{
    Params p;
    p.on = true;
    p.count = -7;
    p.gain = 0.25f;
    p.length = 1.0 / 3.0;
    p.name = "a b";
    p.shape = Shape::Ball;
    const auto text = savedText(p);

    Params q;
    emslam::util::loadByVisit(q, text, "S", visit);
    EXPECT_TRUE(q.on);
    EXPECT_EQ(q.count, -7);
    EXPECT_FLOAT_EQ(q.gain, 0.25f);
    // MRPT writes doubles with %f / %e: 6 decimals.
    EXPECT_NEAR(q.length, 1.0 / 3.0, 1e-6);
    EXPECT_EQ(q.name, "a b");
    EXPECT_EQ(q.shape, Shape::Ball);
}

TEST(ConfigVisitor, absentKeysKeepTheirValues)
{
    Params p;
    p.count = 11;
    p.length = 0.123456789012345;
    p.shape = Shape::Ball;
    const mrpt::config::CConfigFileMemory text("[S]\nname = xyz\n");
    emslam::util::loadByVisit(p, text, "S", visit);
    EXPECT_EQ(p.count, 11);
    EXPECT_EQ(p.length, 0.123456789012345);
    EXPECT_EQ(p.shape, Shape::Ball);
    EXPECT_EQ(p.name, "xyz");
}

TEST(ConfigVisitor, documentationIsATrailingComment)
{
    mrpt::config::CConfigFileMemory out;
    emslam::util::saveByVisit(Params{}, out, "S", visit);
    const std::string content = out.getContent();
    EXPECT_NE(content.find("// [m]"), std::string::npos) << content;
    EXPECT_NE(content.find("// switch"), std::string::npos) << content;
    // Undocumented keys are written as MRPT_SAVE_CONFIG_VAR does: unpadded.
    EXPECT_NE(content.find("count = 3"), std::string::npos) << content;
}

TEST(ConfigVisitor, loadingAndSectionAreReported)
{
    const mrpt::config::CConfigFileMemory in;
    const auto loader = emslam::util::ConfigVisitor::loader(in, "A");
    EXPECT_TRUE(loader.loading());
    EXPECT_EQ(loader.section(), "A");
    mrpt::config::CConfigFileMemory out;
    const auto saver = emslam::util::ConfigVisitor::saver(out, "B");
    EXPECT_FALSE(saver.loading());
    EXPECT_EQ(saver.section(), "B");
}
