// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/ConfigValidation.h>

#include <mrpt/system/string_utils.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <limits>
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

/** Length of the common prefix of `a` and `b`, ignoring case. */
std::size_t commonPrefix(const std::string& a, const std::string& b)
{
    std::size_t n = 0;
    while (n < a.size() && n < b.size() && lower(a[n]) == lower(b[n]))
    {
        ++n;
    }
    return n;
}

/** The closest of `candidates` to `name`, or "" if none is within
 * max(2, |name| / 3) edits (farther names are more noise than help). Ties go
 * to the longer common prefix: a typo is likelier at the end of a name
 * ("num_disparity" means "num_disparities", not "min_disparity"). */
std::string closestName(const std::string& name, const std::vector<std::string>& candidates)
{
    const std::size_t max_distance = std::max<std::size_t>(2, name.size() / 3);
    std::string best;
    std::size_t best_distance = max_distance + 1, best_prefix = 0;
    for (const auto& c : candidates)
    {
        const std::size_t d = editDistance(name, c);
        const std::size_t prefix = commonPrefix(name, c);
        if (d < best_distance || (d == best_distance && prefix > best_prefix))
        {
            best = c;
            best_distance = d;
            best_prefix = prefix;
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
            problems.push_back({user_section, key, closestName(key, valid_keys), "", ""});
        }
    }
}

/** What a reference value is: a whole number, a number, a boolean or other text. */
enum class ValueKind
{
    Integer,
    Number,
    Boolean,
    Text
};

bool parsesAsInteger(const std::string& v)
{
    if (v.empty())
    {
        return false;
    }
    char* end = nullptr;
    errno = 0;
    (void)std::strtoll(v.c_str(), &end, 10);
    return errno == 0 && *end == '\0';
}

/** A whole number that read_int() (atoi) reads as written: decimal digits
 * within int's range. Beyond it atoi() wraps ("2147483648" reads as
 * -2147483648 in MRPT 2.5.8). */
bool parsesAsInt(const std::string& v)
{
    if (v.empty())
    {
        return false;
    }
    char* end = nullptr;
    errno = 0;
    const long long n = std::strtoll(v.c_str(), &end, 10);
    return errno == 0 && *end == '\0' && n >= std::numeric_limits<int>::min() &&
           n <= std::numeric_limits<int>::max();
}

bool parsesAsNumber(const std::string& v)
{
    if (v.empty())
    {
        return false;
    }
    char* end = nullptr;
    (void)std::strtod(v.c_str(), &end);
    return *end == '\0';
}

/** The words MRPT 2.5.8's read_bool() knows (any case). It reads any other
 * text with atoi(): "on" and "off" are both false, "2" is true. */
bool isBooleanWord(const std::string& v)
{
    for (const char* w : {"true", "false", "yes", "no"})
    {
        if (equalNoCase(v, w))
        {
            return true;
        }
    }
    return false;
}

ValueKind kindOf(const std::string& reference_value)
{
    // Written as "0x...": hexadecimal text (a camera GUID) its owner parses.
    if (reference_value.rfind("0x", 0) == 0)
    {
        return ValueKind::Text;
    }
    if (parsesAsInteger(reference_value))
    {
        return ValueKind::Integer;
    }
    if (parsesAsNumber(reference_value))
    {
        return ValueKind::Number;
    }
    return isBooleanWord(reference_value) ? ValueKind::Boolean : ValueKind::Text;
}

/** What `value` lacks to be read as `kind`, or "" when it reads fine. */
std::string valueMismatch(const std::string& value, ValueKind kind)
{
    switch (kind)
    {
        case ValueKind::Integer:
            // Double keys are saved with a decimal point (MRPT writes "%f" /
            // "%e"): a reference in integer form is an int key.
            return parsesAsInt(value) ? "" : "a whole number in [-2147483648, 2147483647]";
        case ValueKind::Number:
            return parsesAsNumber(value) ? "" : "a number";
        case ValueKind::Boolean:
            return isBooleanWord(value) || value == "0" || value == "1"
                       ? ""
                       : "true or false (or yes/no, 1/0)";
        case ValueKind::Text:
            break;
    }
    return "";
}

}  // namespace

namespace
{
/** Throws one message listing `problems`, "N <noun><one / many>:" first. */
void throwIfAny(
    const std::vector<ConfigProblem>& problems,
    const std::string& noun,
    const std::string& one,
    const std::string& many)
{
    if (problems.empty())
    {
        return;
    }
    std::string msg =
        std::to_string(problems.size()) + " " + noun + (problems.size() == 1 ? one : many) + ":";
    for (const auto& p : problems)
    {
        msg += "\n  " + p.message();
    }
    throw std::invalid_argument(msg);
}
}  // namespace

void requireWellFormedConfigValues(
    const mrpt::config::CConfigFileBase& user, const mrpt::config::CConfigFileBase& reference)
{
    const auto problems = findMalformedConfigValues(user, reference);
    if (problems.empty())
    {
        return;
    }
    std::string msg = problems.front().message();
    for (std::size_t i = 1; i < problems.size(); i++)
    {
        msg += "; " + problems[i].message();
    }
    throw std::invalid_argument(msg);
}

std::string ConfigProblem::message() const
{
    if (!expected.empty())
    {
        return "[" + section + "] " + key + " = '" + value + "' is not " + expected;
    }
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
            problems.push_back({section, "", closestName(section, valid_sections), "", ""});
            continue;
        }
        // Ask the reference with its own spelling: not every CConfigFileBase ignores case.
        appendUnknownKeys(user, section, keysOf(reference, *ref_section), problems);
    }
    return problems;
}

std::vector<ConfigProblem> findMalformedConfigValues(
    const mrpt::config::CConfigFileBase& user,
    const mrpt::config::CConfigFileBase& reference,
    const std::vector<std::string>& ignored_sections)
{
    const auto valid_sections = sectionsOf(reference);
    std::vector<ConfigProblem> problems;
    for (const auto& section : sectionsOf(user))
    {
        const std::string* ref_section = findNoCase(valid_sections, section);
        if (!ref_section || findNoCase(ignored_sections, section))
        {
            continue;
        }
        // The reference's own (padded) key spelling, to read its values back.
        std::vector<std::string> ref_keys;
        reference.getAllKeys(*ref_section, ref_keys);
        for (const auto& key : keysOf(user, section))
        {
            const auto ref_key = std::find_if(
                ref_keys.begin(), ref_keys.end(),
                [&](const std::string& k) { return equalNoCase(mrpt::system::trim(k), key); });
            if (ref_key == ref_keys.end())
            {
                continue;
            }
            const ValueKind kind = kindOf(reference.read_string(*ref_section, *ref_key, ""));
            const std::string value = user.read_string(section, key, "");
            const std::string expected = valueMismatch(value, kind);
            if (!expected.empty())
            {
                problems.push_back({section, key, "", value, expected});
            }
        }
    }
    return problems;
}

void requireValidConfig(
    const mrpt::config::CConfigFileBase& user,
    const mrpt::config::CConfigFileBase& reference,
    const std::vector<std::string>& ignored_sections,
    bool skip_unknown_sections)
{
    auto problems = findUnknownConfigEntries(user, reference, ignored_sections);
    if (skip_unknown_sections)
    {
        problems.erase(
            std::remove_if(
                problems.begin(), problems.end(), [](const auto& p) { return p.key.empty(); }),
            problems.end());
    }
    const auto malformed = findMalformedConfigValues(user, reference, ignored_sections);
    problems.insert(problems.end(), malformed.begin(), malformed.end());
    throwIfAny(problems, "invalid configuration entr", "y", "ies");
}

void requireKnownConfigEntries(
    const mrpt::config::CConfigFileBase& user,
    const mrpt::config::CConfigFileBase& reference,
    const std::vector<std::string>& ignored_sections)
{
    throwIfAny(
        findUnknownConfigEntries(user, reference, ignored_sections), "unknown configuration entr",
        "y", "ies");
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
