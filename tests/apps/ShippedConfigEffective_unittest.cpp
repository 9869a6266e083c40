// SPDX-License-Identifier: BSD-3-Clause
// The effective parameters of every shipped mapper and odometry config (the
// file over the code's defaults, as effective.ini writes them) against a
// golden table: moving a value between a config and the defaults must not
// change what any shipped config runs with.
#include "TestData.h"

#include <emslam/slam/EntropySlam.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/vector_loadsave.h>
#include <mrpt/system/string_utils.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace
{
namespace fs = std::filesystem;

/** The golden table, beside this file. */
const char* GOLDEN = "/tests/apps/ShippedConfigEffective.txt";
/** The config folders whose files are tabled, and the sections each reads
 * (empty: every section of EntropySlam::TParameters). */
const std::map<std::string, std::set<std::string>> FOLDERS = {
    {"mapper", {}}, {"odometry", {"StereoMatcher", "EgomotionEstimator"}}};

/** Row "Section.key" → column "folder/name" → value. */
using Table = std::map<std::string, std::map<std::string, std::string>>;

/** A value as saveToConfigFile() wrote it, without its trailing comment. */
std::string valueOf(
    const mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& k)
{
    std::string v = c.read_string(s, k, "");
    const auto comment = v.find("//");
    return mrpt::system::trim(comment == std::string::npos ? v : v.substr(0, comment));
}

/** The effective parameters of every shipped config of FOLDERS. */
Table effectiveTable()
{
    Table t;
    const std::string config = emslam::test::sourceDir() + "/config";
    for (const auto& [folder, sections] : FOLDERS)
    {
        std::vector<fs::path> files;
        for (const auto& e : fs::directory_iterator(config + "/" + folder))
        {
            if (e.path().extension() == ".ini")
            {
                files.push_back(e.path());
            }
        }
        std::sort(files.begin(), files.end());
        for (const auto& file : files)
        {
            const std::string column = folder + "/" + file.stem().string();
            emslam::slam::EntropySlam::TParameters p;
            p.loadFromConfigFile(
                mrpt::config::CConfigFileMemory(mrpt::io::file_get_contents(file.string())));
            mrpt::config::CConfigFileMemory saved;
            p.saveToConfigFile(saved);
            // Re-parsed: a CConfigFileMemory reads back defaults of what it wrote.
            const mrpt::config::CConfigFileMemory effective(saved.getContent());
            std::vector<std::string> all_sections;
            effective.getAllSections(all_sections);
            for (const auto& s : all_sections)
            {
                std::vector<std::string> keys;
                effective.getAllKeys(s, keys);
                for (const auto& k : keys)
                {
                    t[s + "." + k][column] =
                        sections.empty() || sections.count(s) ? valueOf(effective, s, k) : ".";
                }
            }
        }
    }
    return t;
}

/** The table as text: a header of columns, then one row per key. */
std::string toText(const Table& t)
{
    std::set<std::string> columns;
    for (const auto& row : t)
    {
        for (const auto& cell : row.second)
        {
            columns.insert(cell.first);
        }
    }
    std::ostringstream out;
    out << "# The effective parameters of each shipped config (tests/apps/"
           "ShippedConfigEffective_unittest.cpp);\n# '.': a section that config's app does "
           "not read.\nkey";
    for (const auto& c : columns)
    {
        out << ' ' << c;
    }
    out << '\n';
    for (const auto& [key, cells] : t)
    {
        out << key;
        for (const auto& c : columns)
        {
            const auto v = cells.find(c);
            out << ' ' << (v == cells.end() ? "?" : v->second);
        }
        out << '\n';
    }
    return out.str();
}

Table fromText(const std::string& text)
{
    Table t;
    std::istringstream in(text);
    std::string line;
    std::vector<std::string> columns;
    while (std::getline(in, line))
    {
        if (line.empty() || line[0] == '#')
        {
            continue;
        }
        std::istringstream words(line);
        std::string key;
        words >> key;
        std::vector<std::string> cells;
        for (std::string w; words >> w;)
        {
            cells.push_back(w);
        }
        if (columns.empty())
        {
            columns = cells;
            continue;
        }
        for (std::size_t i = 0; i < cells.size() && i < columns.size(); ++i)
        {
            t[key][columns[i]] = cells[i];
        }
    }
    return t;
}
}  // namespace

TEST(ShippedConfigEffective, everyShippedConfigRunsWithTheGoldenParameters)
{
    const Table now = effectiveTable();
    const std::string golden_file = emslam::test::sourceDir() + GOLDEN;
    const Table golden =
        fs::exists(golden_file) ? fromText(mrpt::io::file_get_contents(golden_file)) : Table();
    EXPECT_FALSE(golden.empty()) << GOLDEN;
    std::size_t cells = 0;
    for (const auto& [key, row] : now)
    {
        for (const auto& [column, value] : row)
        {
            ++cells;
            const auto g = golden.find(key);
            const std::string expected =
                g == golden.end() || !g->second.count(column) ? "(absent)" : g->second.at(column);
            EXPECT_EQ(value, expected) << column << ": " << key;
        }
    }
    for (const auto& [key, row] : golden)
    {
        for (const auto& [column, value] : row)
        {
            EXPECT_TRUE(now.count(key) && now.at(key).count(column))
                << column << ": " << key << " is in the golden table only";
        }
    }
    if (HasFailure())
    {
        // What the configs run with now: the new golden table, once every
        // difference above is meant.
        const std::string file = emslam::test::makeTempDir("effective") + "/effective.txt";
        std::ofstream(file) << toText(now);
        std::printf("the effective table now: %s\n", file.c_str());
    }
    EXPECT_GT(cells, 700U);  // 7 mapper configs x ~110 keys at least
}
