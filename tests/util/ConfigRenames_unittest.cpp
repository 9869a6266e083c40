// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/util/ConfigRenames.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

namespace
{
const std::vector<emslam::util::ConfigRename> RENAMES = {
    {"Stereo", "", "StereoMatcher", ""},
    {"LoopCloser", "vertical_patch_px", "VerticalFromPlanes", "patch_px"},
};

/** The lines of `text`. */
std::vector<std::string> lines(const std::string& text)
{
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);)
    {
        out.push_back(l);
    }
    return out;
}
}  // namespace

TEST(ConfigRenames, oldNamesReadAsTheNewOnesWithOneWarningEach)
{
    const mrpt::config::CConfigFileMemory old_names(
        "[Stereo]\nblock_size = 7\nmax_range = 12.5\n"
        "[LoopCloser]\nenabled = false\nvertical_patch_px = 24\n");
    const mrpt::config::CConfigFileMemory new_names(
        "[StereoMatcher]\nblock_size = 7\nmax_range = 12.5\n"
        "[LoopCloser]\nenabled = false\n[VerticalFromPlanes]\npatch_px = 24\n");
    std::ostringstream warnings;
    const auto a = emslam::util::withCurrentNames(old_names, RENAMES, warnings);
    std::ostringstream none;
    const auto b = emslam::util::withCurrentNames(new_names, RENAMES, none);

    for (const auto* c : {&a, &b})
    {
        EXPECT_EQ(c->read_int("StereoMatcher", "block_size", 0), 7);
        EXPECT_DOUBLE_EQ(c->read_double("StereoMatcher", "max_range", 0), 12.5);
        EXPECT_FALSE(c->read_bool("LoopCloser", "enabled", true));
        EXPECT_EQ(c->read_int("VerticalFromPlanes", "patch_px", 0), 24);
        EXPECT_FALSE(c->sectionExists("Stereo"));
        EXPECT_FALSE(c->keyExists("LoopCloser", "vertical_patch_px"));
    }
    const auto w = lines(warnings.str());
    ASSERT_EQ(w.size(), 2U) << warnings.str();
    EXPECT_NE(w[0].find("[StereoMatcher]"), std::string::npos) << w[0];
    EXPECT_NE(w[1].find("[VerticalFromPlanes] patch_px"), std::string::npos) << w[1];
    EXPECT_TRUE(none.str().empty()) << none.str();
}

TEST(ConfigRenames, theNewNameWinsOverTheOld)
{
    const mrpt::config::CConfigFileMemory both(
        "[Stereo]\nblock_size = 7\n[StereoMatcher]\nblock_size = 9\n");
    std::ostringstream warnings;
    const auto c = emslam::util::withCurrentNames(both, RENAMES, warnings);
    EXPECT_EQ(c.read_int("StereoMatcher", "block_size", 0), 9);
    EXPECT_EQ(lines(warnings.str()).size(), 1U);
}

TEST(ConfigRenames, namesCompareIgnoringCase)
{
    const mrpt::config::CConfigFileMemory lower("[stereo]\nblock_size = 5\n");
    std::ostringstream warnings;
    const auto c = emslam::util::withCurrentNames(lower, RENAMES, warnings);
    EXPECT_EQ(c.read_int("StereoMatcher", "block_size", 0), 5);
    EXPECT_EQ(lines(warnings.str()).size(), 1U);
}
