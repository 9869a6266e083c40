// SPDX-License-Identifier: BSD-3-Clause
#include "TestHelpers.h"

#include <emslam/apps/ConfigValidation.h>
#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/hwdrivers/CStereoImageFolderCamera.h>
#include <emslam/maps/CEntropyVoxelMap.h>
#include <emslam/rectify/RectifierOptions.h>
#include <emslam/rectify/SpaceSampler.h>
#include <emslam/slam/EntropySlam.h>
#include <emslam/stereo/StereoMatcher.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

using emslam::apps::ConfigProblem;
using emslam::apps::editDistance;
using emslam::apps::findUnknownConfigEntries;
using emslam::apps::requireKnownConfigEntries;
using mrpt::config::CConfigFileMemory;

namespace
{
const char* REFERENCE =
    "[Rectifier]\n"
    "eps_xyz = 0.01\n"
    "eps_rot_deg = 0.5\n"
    "mode = serial\n"
    "[SpaceSampler]\n"
    "t_min = 0.1\n";

std::vector<ConfigProblem> problemsOf(
    const std::string& user_text, const std::vector<std::string>& ignored = {})
{
    return findUnknownConfigEntries(
        CConfigFileMemory(user_text), CConfigFileMemory(REFERENCE), ignored);
}

/** Wraps a configuration and records every (section, key) that is read from
 * it: the keys a loadFromConfigFile() really reads. */
class KeyRecorder : public mrpt::config::CConfigFileBase
{
public:
    explicit KeyRecorder(const mrpt::config::CConfigFileBase& inner) : m_inner(inner) {}

    std::vector<std::pair<std::string, std::string>> read_keys;

    void getAllSections(std::vector<std::string>& s) const override { m_inner.getAllSections(s); }
    void getAllKeys(const std::string& section, std::vector<std::string>& k) const override
    {
        m_inner.getAllKeys(section, k);
    }
    void clear() override {}

protected:
    void writeString(const std::string&, const std::string&, const std::string&) override
    {
        throw std::logic_error("KeyRecorder is read-only");
    }
    std::string readString(
        const std::string& section,
        const std::string& name,
        const std::string& default_str,
        bool fail_if_not_found) const override
    {
        const_cast<KeyRecorder*>(this)->read_keys.emplace_back(section, name);
        return m_inner.read_string(section, name, default_str, fail_if_not_found);
    }

private:
    const mrpt::config::CConfigFileBase& m_inner;
};

/** The text of a config holding every key `opts.loadFromConfigFile()` reads
 * from `section`, with the values of `reference`. */
std::string keysReadByLoad(
    mrpt::config::CLoadableOptions& opts,
    const std::string& section,
    const mrpt::config::CConfigFileBase& reference)
{
    KeyRecorder recorder(reference);
    opts.loadFromConfigFile(recorder, section);
    EXPECT_FALSE(recorder.read_keys.empty()) << section;
    CConfigFileMemory user;
    for (const auto& [s, k] : recorder.read_keys)
    {
        user.write(s, k, reference.read_string(s, k, "0"));
    }
    return user.getContent();
}

/** A struct whose save forgets one key its load reads. */
struct Asymmetric : public mrpt::config::CLoadableOptions
{
    double kept{1.0};
    double forgotten{2.0};
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override
    {
        MRPT_LOAD_CONFIG_VAR(kept, double, c, s);
        MRPT_LOAD_CONFIG_VAR(forgotten, double, c, s);
    }
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override
    {
        MRPT_SAVE_CONFIG_VAR_COMMENT(kept, "");
    }
};

using Options = std::shared_ptr<mrpt::config::CLoadableOptions>;

/** The parameter structs of a mapping run and the section each one is saved to. */
std::vector<std::pair<std::string, Options>> realParameterStructs()
{
    return {
        {"Rectifier", std::make_shared<emslam::rectify::TRectifierOptions>()},
        {"SpaceSampler", std::make_shared<emslam::rectify::SpaceSampler::TParameters>()},
        {"StereoMatcher", std::make_shared<emslam::stereo::StereoMatcher::TParameters>()},
        {"EgomotionEstimator",
         std::make_shared<emslam::egomotion::EgomotionEstimator::TParameters>()},
        {"EntropyVoxelMap", std::make_shared<emslam::CEntropyVoxelMap::TCreationOptions>()},
        {"EntropyVoxelMap", std::make_shared<emslam::CEntropyVoxelMap::TInsertionOptions>()},
    };
}
}  // namespace

TEST(ConfigValidation, editDistance)
{
    EXPECT_EQ(editDistance("", ""), 0U);
    EXPECT_EQ(editDistance("", "abc"), 3U);
    EXPECT_EQ(editDistance("abc", ""), 3U);
    EXPECT_EQ(editDistance("kitten", "sitting"), 3U);
    EXPECT_EQ(editDistance("esp_xyz", "eps_xyz"), 2U);  // a swap is two substitutions
    EXPECT_EQ(editDistance("Rectifer", "Rectifier"), 1U);
    EXPECT_EQ(editDistance("EPS_XYZ", "eps_xyz"), 0U);
}

TEST(ConfigValidation, typoInKeyGetsSuggestion)
{
    const auto p = problemsOf("[Rectifier]\neps_xyz = 1\nesp_xyz = 0.02\n");
    ASSERT_EQ(p.size(), 1U);
    EXPECT_EQ(p[0].section, "Rectifier");
    EXPECT_EQ(p[0].key, "esp_xyz");
    EXPECT_EQ(p[0].suggestion, "eps_xyz");
    EXPECT_EQ(p[0].message(), "unknown key 'esp_xyz' in [Rectifier] (did you mean 'eps_xyz'?)");
}

TEST(ConfigValidation, typoInSectionReportsOnlyTheSection)
{
    const auto p = problemsOf("[Rectifer]\nesp_xyz = 0.02\nmode = serial\n");
    ASSERT_EQ(p.size(), 1U);
    EXPECT_EQ(p[0].section, "Rectifer");
    EXPECT_TRUE(p[0].key.empty());
    EXPECT_EQ(p[0].suggestion, "Rectifier");
    EXPECT_EQ(p[0].message(), "unknown section [Rectifer] (did you mean [Rectifier]?)");
}

TEST(ConfigValidation, unrelatedNamesGetNoSuggestion)
{
    const auto p = problemsOf("[Rectifier]\ncolour = red\n[Logging]\nlevel = 3\n");
    std::set<std::string> messages;
    for (const auto& q : p)
    {
        EXPECT_TRUE(q.suggestion.empty()) << q.message();
        messages.insert(q.message());
    }
    EXPECT_EQ(
        messages, (std::set<std::string>{
                      "unknown section [Logging]", "unknown key 'colour' in [Rectifier]"}));
}

TEST(ConfigValidation, caseDifferencesAreAccepted)
{
    const std::string user =
        "[rectifier]\nEPS_XYZ = 0.02\nMode = anytime\n[SPACESAMPLER]\nT_Min=1\n";
    EXPECT_TRUE(problemsOf(user).empty());
    // ... because MRPT itself reads them so (SimpleIni's SI_NoCase comparator).
    const CConfigFileMemory c(user);
    EXPECT_DOUBLE_EQ(c.read_double("Rectifier", "eps_xyz", 0.0), 0.02);
    EXPECT_EQ(c.read_string("Rectifier", "mode", ""), "anytime");
    EXPECT_DOUBLE_EQ(c.read_double("SpaceSampler", "t_min", 0.0), 1.0);
}

TEST(ConfigValidation, ignoredSectionsAreSkipped)
{
    const std::string user = "[Rectifier]\neps_xyz = 1\n[EntropySlam]\nanything = 1\n";
    EXPECT_EQ(problemsOf(user).size(), 1U);
    EXPECT_TRUE(problemsOf(user, {"entropyslam"}).empty());
}

TEST(ConfigValidation, requireListsEveryProblemOnItsOwnLine)
{
    const CConfigFileMemory reference(REFERENCE);
    EXPECT_NO_THROW(
        requireKnownConfigEntries(CConfigFileMemory("[Rectifier]\nmode=serial\n"), reference));
    const CConfigFileMemory user("[Rectifier]\nesp_xyz = 1\n[Rectifer]\nx = 1\n");
    EXPECT_THROW(requireKnownConfigEntries(user, reference), std::invalid_argument);
    emslam::test::expectThrowContaining(
        [&] { requireKnownConfigEntries(user, reference); },
        {"2 unknown configuration entries:",
         "\n  unknown section [Rectifer] (did you mean [Rectifier]?)",
         "\n  unknown key 'esp_xyz' in [Rectifier] (did you mean 'eps_xyz'?)"});
}

// The reference of a real run is every parameter struct saved with its
// defaults. A config holding every key that each loadFromConfigFile() reads
// must pass, i.e. each saveToConfigFile() writes all the keys its load reads
// (and, checked too, no key its load ignores).
TEST(ConfigValidation, savedParameterStructsAcceptEveryKeyTheirLoadReads)
{
    CConfigFileMemory saved;
    for (const auto& [section, opts] : realParameterStructs())
    {
        opts->saveToConfigFile(saved, section);
    }
    const CConfigFileMemory reference(saved.getContent());  // unpadded keys, see the .h

    for (const auto& [section, opts] : realParameterStructs())
    {
        const CConfigFileMemory user(keysReadByLoad(*opts, section, reference));
        for (const auto& p : findUnknownConfigEntries(user, reference))
        {
            ADD_FAILURE() << "[" << section
                          << "]: load reads a key save does not write: " << p.message();
        }
        CConfigFileMemory own;
        opts->saveToConfigFile(own, section);
        for (const auto& p : findUnknownConfigEntries(own, user))
        {
            ADD_FAILURE() << "[" << section
                          << "]: save writes a key load does not read: " << p.message();
        }
    }
    // The very object saved into (padded key names) works as the reference too.
    EXPECT_TRUE(findUnknownConfigEntries(reference, saved).empty());
    EXPECT_EQ(
        findUnknownConfigEntries(CConfigFileMemory("[StereoMatcher]\nblock_siz = 5\n"), saved)
            .at(0)
            .suggestion,
        "block_size");
}

// The check above does catch a save that forgets a key.
TEST(ConfigValidation, keyRecorderCatchesAnAsymmetricSave)
{
    Asymmetric opts;
    CConfigFileMemory saved;
    opts.saveToConfigFile(saved, "S");
    const CConfigFileMemory user(keysReadByLoad(opts, "S", saved));
    const auto p = findUnknownConfigEntries(user, saved);
    ASSERT_EQ(p.size(), 1U);
    EXPECT_EQ(p[0].key, "forgotten");
}

// MRPT reads "abc" as 0, "64x" as 64 and "5.5" into an int as 5 without a
// word: such values are problems.
TEST(ConfigValidation, malformedNumbersAndBooleansAreFound)
{
    CConfigFileMemory reference;
    emslam::stereo::StereoMatcher::TParameters().saveToConfigFile(reference, "StereoMatcher");
    const CConfigFileMemory user(
        "[StereoMatcher]\n"
        "num_disparities = abc\n"
        "block_size = 5.5\n"
        "max_range = 40 // metres, a trailing comment is fine\n"
        "min_range = 0.3x\n"
        "algorithm = sgbm\n"
        "[Other]\n"
        "x = y\n");
    const auto p = emslam::apps::findMalformedConfigValues(user, reference);
    std::set<std::string> messages;  // in the order MRPT lists the keys
    for (const auto& q : p)
    {
        messages.insert(q.message());
    }
    const std::string whole = " is not a whole number in [-2147483648, 2147483647]";
    EXPECT_EQ(
        messages, (std::set<std::string>{
                      "[StereoMatcher] num_disparities = 'abc'" + whole,
                      "[StereoMatcher] block_size = '5.5'" + whole,
                      "[StereoMatcher] min_range = '0.3x' is not a number"}));

    emslam::test::expectThrowContaining(
        [&] { emslam::apps::requireValidConfig(user, reference); },
        {"4 invalid configuration entries", "unknown section [Other]", "'abc'"});
    // With unknown sections allowed (an app reading part of a shared INI file).
    emslam::test::expectThrowContaining(
        [&] { emslam::apps::requireValidConfig(user, reference, {}, true); },
        {"3 invalid configuration entries"});
    EXPECT_NO_THROW(emslam::apps::requireValidConfig(
        CConfigFileMemory("[StereoMatcher]\nnum_disparities = 64\nmax_range = 1e2\n"), reference));
}

// An int key takes a whole number that fits an int (atoi() wraps beyond it);
// a boolean key only the words MRPT knows (it reads "on" as false) or 1/0.
TEST(ConfigValidation, intKeysTakeWholeNumbersInRangeAndBooleansTheirWords)
{
    CConfigFileMemory reference;
    emslam::egomotion::EgomotionEstimator::TParameters().saveToConfigFile(
        reference, "EgomotionEstimator");
    const auto problems = [&](const std::string& key, const std::string& value)
    {
        return emslam::apps::findMalformedConfigValues(
                   CConfigFileMemory("[EgomotionEstimator]\n" + key + " = " + value + "\n"),
                   reference)
            .size();
    };
    for (const char* ok : {"8", "-3", "2147483647", "-2147483648", "+5"})
    {
        EXPECT_EQ(problems("window_size", ok), 0U) << ok;
    }
    for (const char* bad : {"64.9", "2147483648", "-2147483649", "1e3", "nan", "inf", "12abc", ""})
    {
        EXPECT_EQ(problems("window_size", bad), 1U) << bad;
    }
    for (const char* ok : {"0.5", "1e-3", "nan", "inf", "-inf", "7"})
    {
        EXPECT_EQ(problems("lwo_sigma_min", ok), 0U) << ok;  // validate() judges the value
    }
    for (const char* ok : {"true", "False", "YES", "no", "1", "0"})
    {
        EXPECT_EQ(problems("euclidean_init", ok), 0U) << ok;
    }
    for (const char* bad : {"maybe", "on", "off", "2", "-1", "", "1.0"})
    {
        EXPECT_EQ(problems("euclidean_init", bad), 1U) << bad;
    }
}

// A reference value in integer form marks an int key: no double parameter may
// save its value in that form, or a fractional value would be refused.
TEST(ConfigValidation, noDoubleParameterIsSavedInIntegerForm)
{
    emslam::slam::EntropySlam::TParameters p;
    CConfigFileMemory saved;
    p.saveToConfigFile(saved);
    const CConfigFileMemory reference(saved.getContent());
    std::vector<std::string> sections;
    reference.getAllSections(sections);
    for (const auto& s : sections)
    {
        std::vector<std::string> keys;
        reference.getAllKeys(s, keys);
        for (const auto& k : keys)
        {
            const std::string v = reference.read_string(s, k, "");
            if (v.empty() || v.find_first_not_of("0123456789-+") != std::string::npos)
            {
                continue;
            }
            // Load "v.5": an int key reads it as v (and saves "v"), a double one as v.5.
            CConfigFileMemory edited(saved.getContent());
            edited.write(s, k, v + ".5");
            emslam::slam::EntropySlam::TParameters q;
            try
            {
                q.loadFromConfigFile(CConfigFileMemory(edited.getContent()));
            }
            catch (const std::exception&)
            {
                continue;  // out of range: not this test's business
            }
            CConfigFileMemory back;
            q.saveToConfigFile(back);
            EXPECT_EQ(CConfigFileMemory(back.getContent()).read_string(s, k, ""), v)
                << "[" << s << "] " << k << " is a double saved as '" << v << "'";
        }
    }
}

// The saved defaults are the reference of the grabber's value checks: a
// fractional time_offset (a UNIX time) must not read as an int key.
TEST(CStereoImageFolderCamera, savedTimeOffsetIsANumberKey)
{
    mrpt::config::CConfigFileMemory reference;
    emslam::hwdrivers::CStereoImageFolderCamera::TParameters().saveToConfigFile(reference, "F");
    const mrpt::config::CConfigFileMemory user("[F]\ntime_offset = 1317340800.5\n");
    EXPECT_TRUE(emslam::apps::findMalformedConfigValues(user, reference).empty());
    const mrpt::config::CConfigFileMemory typo("[F]\ntime_offset = 13e\n");
    EXPECT_EQ(emslam::apps::findMalformedConfigValues(typo, reference).size(), 1U);
}
