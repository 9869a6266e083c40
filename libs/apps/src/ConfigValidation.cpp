// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/ConfigValidation.h>

#include <mrpt/system/string_utils.h>

#include <algorithm>
#include <cctype>
#include <numeric>
#include <stdexcept>

namespace emslam::apps
{
namespace
{
char lower(char c)
{
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
}

bool equalNoCase(const std::string& a, const std::string& b)
{
    return a.size() == b.size() &&
           std::equal(
               a.begin(), a.end(), b.begin(), [](char x, char y) { return lower(x) == lower(y); });
}

/** The entry of `names` equal to `name` ignoring case, or nullptr. */
const std::string* findNoCase(const std::vector<std::string>& names, const std::string& name)
{
    const auto it = std::find_if(
        names.begin(), names.end(), [&](const std::string& n) { return equalNoCase(n, name); });
    return it == names.end() ? nullptr : &*it;
}

/** The closest of `candidates` to `name`, or "" if none is within
 * max(2, |name| / 3) edits (farther names are more noise than help). */
std::string closestName(const std::string& name, const std::vector<std::string>& candidates)
{
    const std::size_t max_distance = std::max<std::size_t>(2, name.size() / 3);
    std::string best;
    std::size_t best_distance = max_distance + 1;
    for (const auto& c : candidates)
    {
        const std::size_t d = editDistance(name, c);
        if (d < best_distance)
        {
            best = c;
            best_distance = d;
        }
    }
    return best;
}

std::vector<std::string> sectionsOf(const mrpt::config::CConfigFileBase& c)
{
    std::vector<std::string> v;
    c.getAllSections(v);
    return v;
}

/** Key names without surrounding blanks: saveToConfigFile() into a
 * CConfigFileMemory stores each key padded to MRPT_SAVE_NAME_PADDING(). */
std::vector<std::string> keysOf(const mrpt::config::CConfigFileBase& c, const std::string& section)
{
    std::vector<std::string> v;
    c.getAllKeys(section, v);
    for (auto& k : v)
    {
        k = mrpt::system::trim(k);
    }
    return v;
}

void appendUnknownKeys(
    const mrpt::config::CConfigFileBase& user,
    const std::string& user_section,
    const std::vector<std::string>& valid_keys,
    std::vector<ConfigProblem>& problems)
{
    for (const auto& key : keysOf(user, user_section))
    {
        if (!findNoCase(valid_keys, key))
        {
            problems.push_back({user_section, key, closestName(key, valid_keys)});
        }
    }
}

}  // namespace

std::string ConfigProblem::message() const
{
    if (key.empty())
    {
        return "unknown section [" + section + "]" +
               (suggestion.empty() ? "" : " (did you mean [" + suggestion + "]?)");
    }
    return "unknown key '" + key + "' in [" + section + "]" +
           (suggestion.empty() ? "" : " (did you mean '" + suggestion + "'?)");
}

std::vector<ConfigProblem> findUnknownConfigEntries(
    const mrpt::config::CConfigFileBase& user,
    const mrpt::config::CConfigFileBase& reference,
    const std::vector<std::string>& ignored_sections)
{
    const auto valid_sections = sectionsOf(reference);
    std::vector<ConfigProblem> problems;
    for (const auto& section : sectionsOf(user))
    {
        if (findNoCase(ignored_sections, section))
        {
            continue;
        }
        const std::string* ref_section = findNoCase(valid_sections, section);
        if (!ref_section)
        {
            problems.push_back({section, "", closestName(section, valid_sections)});
            continue;
        }
        // Ask the reference with its own spelling: not every CConfigFileBase ignores case.
        appendUnknownKeys(user, section, keysOf(reference, *ref_section), problems);
    }
    return problems;
}

void requireKnownConfigEntries(
    const mrpt::config::CConfigFileBase& user,
    const mrpt::config::CConfigFileBase& reference,
    const std::vector<std::string>& ignored_sections)
{
    const auto problems = findUnknownConfigEntries(user, reference, ignored_sections);
    if (problems.empty())
    {
        return;
    }
    std::string msg = std::to_string(problems.size()) + " unknown configuration entr" +
                      (problems.size() == 1 ? "y" : "ies") + ":";
    for (const auto& p : problems)
    {
        msg += "\n  " + p.message();
    }
    throw std::invalid_argument(msg);
}

std::size_t editDistance(const std::string& a, const std::string& b)
{
    // Two rows of the Wagner-Fischer table: row[j] = distance(a[0..i), b[0..j)).
    std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
    std::iota(prev.begin(), prev.end(), std::size_t{0});
    for (std::size_t i = 1; i <= a.size(); i++)
    {
        cur[0] = i;
        for (std::size_t j = 1; j <= b.size(); j++)
        {
            const std::size_t substitution = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + substitution});
        }
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

}  // namespace emslam::apps
