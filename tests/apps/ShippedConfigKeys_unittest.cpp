// SPDX-License-Identifier: BSD-3-Clause
// Every key of every shipped config/**/*.ini set to hostile values and run
// through the configuration check of the app that reads the file: each value
// is accepted or refused with a message naming the key, never a crash.
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/ExperimentSuite.h>
#include <emslam/apps/GrabberApp.h>
#include <emslam/apps/MapperApp.h>
#include <emslam/apps/OdometryApp.h>
#include <emslam/apps/SimApp.h>
#include <emslam/apps/StereoApp.h>
#include <emslam/maps/CEntropyVoxelMap.h>
#include <emslam/slam/EntropySlam.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/TMetricMapInitializer.h>
#include <mrpt/system/string_utils.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace
{
/** The `../shared/data/...` path a config names as a value (the real test
 * data, next to the repository), or "" if it names none. */
std::string sharedDataNamedIn(const std::string& text)
{
    const auto at = text.find("= ../shared/data/");
    if (at == std::string::npos)
    {
        return {};
    }
    const auto begin = at + 2;
    const auto end = text.find_first_of(" \t\r\n;#", begin);
    return text.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
}

namespace fs = std::filesystem;
using mrpt::config::CConfigFileMemory;

/** The values every key gets. */
const std::vector<std::string> HOSTILE = {"0",     "-1",     "2147483647", "-2147483648",
                                          "1e300", "-1e300", "nan",        "inf",
                                          "-inf",  "abc",    "12abc",      ""};

/** What a key's shipped value says it is. */
enum class Kind
{
    Integer,
    Number,
    Boolean,
    Text
};

Kind kindOf(const std::string& v)
{
    if (v.empty())
    {
        return Kind::Text;
    }
    char* end = nullptr;
    (void)std::strtoll(v.c_str(), &end, 10);
    if (*end == '\0')
    {
        return Kind::Integer;
    }
    (void)std::strtod(v.c_str(), &end);
    if (*end == '\0')
    {
        return Kind::Number;
    }
    const std::string l = mrpt::system::lowerCase(v);
    return l == "true" || l == "false" || l == "yes" || l == "no" ? Kind::Boolean : Kind::Text;
}

/** The configuration check of the app that reads a config folder, given the
 * file's text and where the file would be (suites resolve paths from it). */
using Check = std::function<void(const std::string& text, const std::string& path)>;

std::string readText(const std::string& file)
{
    std::ifstream in(file, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/** How observations2map / emslam-run build the entropy map of
 * config/maps/entropy-map.ini: through MRPT's CMultiMetricMap. */
void checkEntropyMapIni(const CConfigFileMemory& cfg)
{
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(cfg, "EntropyVoxelMap");
    const mrpt::maps::CMultiMetricMap mm(inits);
    if (!mm.mapByClass<emslam::CEntropyVoxelMap>())
    {
        throw std::runtime_error("no entropy map");
    }
}

/** config/<folder> → its check. A folder missing here fails the test. */
std::map<std::string, Check> checks(const std::string& copy_of_config)
{
    const auto inMemory = [](void (*f)(const mrpt::config::CConfigFileBase&))
    { return [f](const std::string& text, const std::string&) { f(CConfigFileMemory(text)); }; };
    return {
        {"mapper", inMemory(&emslam::apps::MapperApp::checkConfig)},
        {"odometry", inMemory(&emslam::apps::OdometryApp::checkConfig)},
        {"stereo", inMemory(&emslam::apps::StereoApp::checkConfig)},
        {"sim", inMemory(&emslam::apps::SimApp::checkConfig)},
        {"grabber",
         [](const std::string& text, const std::string&)
         {
             // The shipped sensors name their files relative to the source tree.
             const fs::path cwd = fs::current_path();
             fs::current_path(emslam::test::sourceDir());
             try
             {
                 emslam::apps::GrabberApp::checkConfig(CConfigFileMemory(text));
             }
             catch (...)
             {
                 fs::current_path(cwd);
                 throw;
             }
             fs::current_path(cwd);
         }},
        {"maps", [](const std::string& text, const std::string&)
         { checkEntropyMapIni(CConfigFileMemory(text)); }},
        {"experiments",
         [copy_of_config](const std::string& text, const std::string& path)
         {
             // Written beside a copy of config/: the suite's paths are relative.
             const std::string file =
                 copy_of_config + "/experiments/" + fs::path(path).filename().string();
             emslam::test::writeFile(file, text);
             (void)emslam::apps::ExperimentSuite::load(file);
         }},
    };
}

/** MRPT's own keys, read by MRPT's code (not ours) without checks:
 * `<map>_count` makes that many maps (CMultiMetricMap), the generic map
 * flags are read_bool(), and the stock rawlog-grabber's launch delay is
 * not read by emslam-grabber at all. */
bool isMrptOwnKey(const std::string& folder, const std::string& key)
{
    return (folder == "maps" &&
            (key == "entropyVoxelMap_count" || key == "enableSaveAs3DObject")) ||
           (folder == "grabber" && key == "time_between_launches");
}

bool containsNoCase(const std::string& text, const std::string& word)
{
    return mrpt::system::lowerCase(text).find(mrpt::system::lowerCase(word)) != std::string::npos;
}

/** `text` with `section.key` set to `value`. */
std::string withValue(
    const std::string& text,
    const std::string& section,
    const std::string& key,
    const std::string& value)
{
    CConfigFileMemory c(text);
    c.write(section, key, value);
    return c.getContent();
}

/** The sections an app reads of a config folder whose files list only what
 * differs from the defaults, with every key at its effective value (the
 * file over the defaults); empty for the other folders, whose files list
 * every key they set. */
CConfigFileMemory effectiveConfig(const std::string& folder, const std::string& text)
{
    if (folder != "mapper" && folder != "odometry")
    {
        return CConfigFileMemory();
    }
    emslam::slam::EntropySlam::TParameters p;
    p.loadFromConfigFile(CConfigFileMemory(text));
    CConfigFileMemory saved;
    p.saveToConfigFile(saved);
    CConfigFileMemory all(saved.getContent());
    if (folder == "odometry")
    {
        // emslam-odometry reads [StereoMatcher] and [EgomotionEstimator] only.
        CConfigFileMemory read;
        for (const std::string section : {"StereoMatcher", "EgomotionEstimator"})
        {
            std::vector<std::string> keys;
            all.getAllKeys(section, keys);
            for (const auto& k : keys)
            {
                read.write(section, k, all.read_string(section, k, ""));
            }
        }
        return CConfigFileMemory(read.getContent());
    }
    return all;
}

/** A value as saveToConfigFile() wrote it, without a trailing comment. */
std::string withoutComment(const std::string& v)
{
    return mrpt::system::trim(v.substr(0, v.find("//")));
}

struct Tally
{
    std::size_t keys{0}, runs{0}, refused{0};
};
}  // namespace

TEST(ShippedConfigKeys, everyKeyAcceptsOrRefusesEveryHostileValueByName)
{
    const auto t0 = std::chrono::steady_clock::now();
    const std::string config_dir = emslam::test::sourceDir() + "/config";
    const std::string copy = emslam::test::makeTempDir("config_keys") + "/config";
    fs::copy(config_dir, copy, fs::copy_options::recursive);
    const auto by_folder = checks(copy);

    Tally tally;
    std::set<std::string> walked;
    for (const auto& entry : fs::recursive_directory_iterator(config_dir))
    {
        if (entry.path().extension() != ".ini")
        {
            continue;
        }
        const std::string folder = fs::relative(entry.path(), config_dir).begin()->string();
        const auto check = by_folder.find(folder);
        ASSERT_NE(check, by_folder.end()) << "no check for config/" << folder << "/";
        const std::string path = entry.path().string();
        const std::string text = readText(path);
        SCOPED_TRACE(path);
        if (const std::string data = sharedDataNamedIn(text);
            !data.empty() && !fs::exists(emslam::test::sourceDir() + "/" + data))
        {
            // A replay config of the real data: checked where the data is.
            std::printf("skipped %s: '%s' is absent\n", path.c_str(), data.c_str());
            continue;
        }
        try
        {
            check->second(text, path);
        }
        catch (const std::exception& e)
        {
            ADD_FAILURE() << "the shipped file itself: " << e.what();
            continue;
        }

        // The file's keys, and the keys it leaves at their defaults.
        const CConfigFileMemory original(text);
        const CConfigFileMemory effective = effectiveConfig(folder, text);
        std::map<std::string, std::map<std::string, std::string>> values;
        for (const auto* c : {&effective, &original})
        {
            std::vector<std::string> sections;
            c->getAllSections(sections);
            for (const auto& section : sections)
            {
                std::vector<std::string> keys;
                c->getAllKeys(section, keys);
                for (const auto& key : keys)
                {
                    const std::string v = c->read_string(section, key, "");
                    values[section][key] = c == &effective ? withoutComment(v) : v;
                }
            }
        }
        for (const auto& [section, keys] : values)
        {
            for (const auto& [key, shipped_value] : keys)
            {
                // A key shared by files of one folder is walked once, in the first.
                if (isMrptOwnKey(folder, key) ||
                    !walked.insert(mrpt::system::lowerCase(folder + "/" + section + "/" + key))
                         .second)
                {
                    continue;
                }
                ++tally.keys;
                const Kind kind = kindOf(shipped_value);
                for (const auto& value : HOSTILE)
                {
                    ++tally.runs;
                    const std::string where = "[" + section + "] " + key + " = '" + value + "'";
                    bool refused = false;
                    const auto t_check = std::chrono::steady_clock::now();
                    try
                    {
                        check->second(withValue(text, section, key, value), path);
                    }
                    catch (const std::exception& e)
                    {
                        refused = true;
                        EXPECT_TRUE(containsNoCase(e.what(), key))
                            << where << ": the message does not name the key: " << e.what();
                    }
                    tally.refused += refused;
                    // A check that takes this long is on its way to a hang.
                    EXPECT_LT(
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_check)
                            .count(),
                        1.0)
                        << where;
                    // What a key's kind can never take (the shipped value tells a number
                    // from a boolean, not an int key from a double one written "5").
                    // (An experiment suite reads an empty value as "not given".)
                    // (A camera GUID is hexadecimal: "abc" and "12abc" are GUIDs.)
                    const bool hexadecimal = key == "camera_guid";
                    const bool not_a_number =
                        ((value == "abc" || value == "12abc") && !hexadecimal) || value == "nan" ||
                        (value.empty() && folder != "experiments");
                    if (kind != Kind::Text && not_a_number)
                    {
                        EXPECT_TRUE(refused) << where << " accepted";
                    }
                    if (kind == Kind::Boolean && value != "0" &&
                        !(value.empty() && folder == "experiments"))
                    {
                        EXPECT_TRUE(refused) << where << " accepted";
                    }
                }
            }
        }
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf(
        "%zu keys x %zu values = %zu checks, %zu refused, %.1f s\n", tally.keys, HOSTILE.size(),
        tally.runs, tally.refused, seconds);
    EXPECT_GT(tally.keys, 300U);  // distinct keys: 326 when written
}
