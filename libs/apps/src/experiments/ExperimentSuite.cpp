// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/ConfigValidation.h>
#include <emslam/apps/ExperimentSuite.h>
#include <emslam/io/IniFile.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace emslam::apps
{
namespace
{
constexpr const char* SUITE_SECTION = "Experiments";
constexpr const char* VARIANTS_SECTION = "Variants";
const std::vector<std::string> SUITE_KEYS{"experiments", "seeds", "quick_frames", "variants"};
const std::vector<std::string> EXPERIMENT_KEYS{
    "title",
    "figure",
    "world",
    "loop",
    "mappers",
    "set",
    "world_set",
    "paper_path_m",
    "paper_observations",
    "paper_egomotion_gap_m",
    "paper_slam_gap_m"};

std::vector<std::string> words(const std::string& s)
{
    std::vector<std::string> w;
    std::istringstream in(s);
    for (std::string x; in >> x;)
    {
        w.push_back(x);
    }
    return w;
}

/** `Section.key=value`: a dot before the first '='. */
bool isOverride(const std::string& s)
{
    const auto eq = s.find('=');
    return eq != std::string::npos && s.find('.') < eq;
}

/** "a,b c" → {a, b, c}. */
std::vector<std::string> commaOrSpaceSeparated(std::string s)
{
    std::replace(s.begin(), s.end(), ',', ' ');
    return words(s);
}

class SuiteReader
{
public:
    SuiteReader(const std::string& file, const mrpt::config::CConfigFileBase& cfg)
        : m_file(file), m_cfg(cfg), m_dir(std::filesystem::path(file).parent_path())
    {
    }

    [[noreturn]] void fail(
        const std::string& section, const std::string& key, const std::string& what) const
    {
        throw std::invalid_argument(
            "'" + m_file + "': [" + section + "] " + key + (key.empty() ? "" : ": ") + what);
    }

    std::string text(const std::string& section, const std::string& key, bool required) const
    {
        const std::string v = m_cfg.read_string(section, key, "", false);
        if (required && v.empty())
        {
            fail(section, key, "missing");
        }
        return v;
    }

    /** A finite number; "-" or an empty value is NaN (not given). */
    double number(const std::string& section, const std::string& key, const std::string& v) const
    {
        if (v.empty() || v == "-")
        {
            return std::numeric_limits<double>::quiet_NaN();
        }
        char* end = nullptr;
        errno = 0;
        const double d = std::strtod(v.c_str(), &end);
        if (end == v.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(d) || d < 0)
        {
            fail(section, key, "expected a number >= 0 or '-', got '" + v + "'");
        }
        return d;
    }

    /** A path relative to the suite file's folder, which must exist. */
    std::string path(const std::string& section, const std::string& key, const std::string& v) const
    {
        const std::filesystem::path p =
            std::filesystem::path(v).is_absolute() ? std::filesystem::path(v) : m_dir / v;
        if (!std::filesystem::is_regular_file(p))
        {
            fail(section, key, "'" + p.string() + "' is not a file");
        }
        return p.lexically_normal().string();
    }

    ExperimentSpec experiment(const std::string& name) const
    {
        ExperimentSpec e;
        e.name = name;
        e.title = text(name, "title", false);
        if (e.title.empty())
        {
            e.title = name;
        }
        e.figure = text(name, "figure", false);
        e.world = path(name, "world", text(name, "world", true));
        const std::string loop = text(name, "loop", false);
        if (loop == "true" || loop == "1" || loop.empty())
        {
            e.loop = true;
        }
        else if (loop == "false" || loop == "0")
        {
            e.loop = false;
        }
        else
        {
            fail(name, "loop", "expected true or false, got '" + loop + "'");
        }
        for (const auto& m : words(text(name, "mappers", true)))
        {
            e.mappers.push_back(path(name, "mappers", m));
        }
        e.sets = words(text(name, "set", false));
        e.world_sets = worldOverrides(name, e.world);
        e.paper_path_m = number(name, "paper_path_m", text(name, "paper_path_m", false));
        e.paper_observations =
            number(name, "paper_observations", text(name, "paper_observations", false));
        e.paper_egomotion_gap_m =
            number(name, "paper_egomotion_gap_m", text(name, "paper_egomotion_gap_m", false));
        const auto gaps = words(text(name, "paper_slam_gap_m", false));
        if (!gaps.empty() && gaps.size() != e.mappers.size())
        {
            fail(
                name, "paper_slam_gap_m",
                "needs one value per mapper (" + std::to_string(e.mappers.size()) + "), got " +
                    std::to_string(gaps.size()));
        }
        for (std::size_t i = 0; i < e.mappers.size(); ++i)
        {
            e.paper_slam_gap_m.push_back(
                gaps.empty() ? std::numeric_limits<double>::quiet_NaN()
                             : number(name, "paper_slam_gap_m", gaps[i]));
        }
        return e;
    }

private:
    /** `world_set`: each `Section.key=value` must change a key the world INI
     * has, so that a typo cannot leave the world as it was unnoticed. */
    std::vector<std::string> worldOverrides(const std::string& name, const std::string& world) const
    {
        const auto sets = words(text(name, "world_set", false));
        if (sets.empty())
        {
            return sets;
        }
        const mrpt::config::CConfigFileMemory w(io::readIniFile(world, "world"));
        for (const auto& s : sets)
        {
            if (!isOverride(s))
            {
                fail(name, "world_set", "expected Section.key=value, got '" + s + "'");
            }
            const auto eq = s.find('=');
            const auto dot = s.find('.');
            const std::string section = s.substr(0, dot);
            const std::string key = s.substr(dot + 1, eq - dot - 1);
            if (!w.keyExists(section, key))
            {
                fail(
                    name, "world_set",
                    "'" + world + "' has no key '" + key + "' in [" + section + "] to change");
            }
        }
        return sets;
    }

    std::string m_file;
    const mrpt::config::CConfigFileBase& m_cfg;
    std::filesystem::path m_dir;
};
}  // namespace

std::vector<int> parseSeedList(const std::string& text)
{
    std::vector<int> seeds;
    for (const auto& w : commaOrSpaceSeparated(text))
    {
        char* end = nullptr;
        errno = 0;
        const long v = std::strtol(w.c_str(), &end, 10);
        if (end == w.c_str() || *end != '\0' || errno == ERANGE || v < 0 ||
            v > std::numeric_limits<int>::max())
        {
            throw std::invalid_argument(
                "seeds: expected integers >= 0 separated by commas, got '" + text + "'");
        }
        seeds.push_back(static_cast<int>(v));
    }
    if (seeds.empty())
    {
        throw std::invalid_argument("seeds: the list is empty");
    }
    return seeds;
}

ExperimentSuite ExperimentSuite::load(const std::string& file)
{
    if (!std::filesystem::is_regular_file(file))
    {
        throw std::invalid_argument("experiment set '" + file + "' is not a file");
    }
    const mrpt::config::CConfigFileMemory cfg(io::readIniFile(file, "experiment set"));
    SuiteReader r(file, cfg);
    const auto names = words(r.text(SUITE_SECTION, "experiments", true));
    const auto variant_names = words(r.text(SUITE_SECTION, "variants", false));

    // Every section and key must be one we read: a typo must not go unnoticed.
    mrpt::config::CConfigFileMemory reference;
    for (const auto& k : SUITE_KEYS)
    {
        reference.write(SUITE_SECTION, k, "x");
    }
    for (const auto& n : names)
    {
        if (!cfg.sectionExists(n))
        {
            r.fail(SUITE_SECTION, "experiments", "no section [" + n + "]");
        }
        for (const auto& k : EXPERIMENT_KEYS)
        {
            reference.write(n, k, "x");
        }
    }
    std::vector<std::string> defined;
    cfg.getAllKeys(VARIANTS_SECTION, defined);
    for (const auto& v : variant_names)
    {
        if (std::find(defined.begin(), defined.end(), v) == defined.end())
        {
            r.fail(SUITE_SECTION, "variants", "no key '" + v + "' in [Variants]");
        }
        if (std::count(variant_names.begin(), variant_names.end(), v) > 1)
        {
            r.fail(SUITE_SECTION, "variants", "'" + v + "' is named twice");
        }
        reference.write(VARIANTS_SECTION, v, "x");
    }
    const auto problems = findUnknownConfigEntries(cfg, reference);
    if (!problems.empty())
    {
        throw std::invalid_argument("'" + file + "': " + problems.front().message());
    }

    ExperimentSuite suite;
    const std::string seeds = r.text(SUITE_SECTION, "seeds", false);
    if (!seeds.empty())
    {
        try
        {
            suite.seeds = parseSeedList(seeds);
        }
        catch (const std::exception& e)
        {
            r.fail(SUITE_SECTION, "seeds", e.what());
        }
    }
    const std::string quick = r.text(SUITE_SECTION, "quick_frames", false);
    if (!quick.empty())
    {
        const double q = r.number(SUITE_SECTION, "quick_frames", quick);
        if (!(q >= 2) || q != std::floor(q) || q > 1e6)
        {
            r.fail(
                SUITE_SECTION, "quick_frames", "expected a whole number >= 2, got '" + quick + "'");
        }
        suite.quick_frames = static_cast<std::size_t>(q);
    }
    for (const auto& n : names)
    {
        suite.experiments.push_back(r.experiment(n));
    }
    if (!variant_names.empty())
    {
        suite.variants.clear();
        for (const auto& v : variant_names)
        {
            ExperimentVariant variant{v, words(r.text(VARIANTS_SECTION, v, false))};
            for (const auto& s : variant.sets)
            {
                if (!isOverride(s))
                {
                    r.fail(VARIANTS_SECTION, v, "expected Section.key=value, got '" + s + "'");
                }
            }
            suite.variants.push_back(std::move(variant));
        }
    }
    if (suite.experiments.empty())
    {
        r.fail(SUITE_SECTION, "experiments", "the list is empty");
    }
    return suite;
}

namespace
{
/** The items of `all` named in `only` (comma-separated; empty: all), in
 * `all`'s order; `what` names the option in the error. */
template <class T>
std::vector<T> selectByName(
    const std::vector<T>& all,
    const std::string& only,
    const std::string& option,
    const std::string& kind)
{
    if (only.empty())
    {
        return all;
    }
    const auto wanted = commaOrSpaceSeparated(only);
    for (const auto& w : wanted)
    {
        if (std::none_of(all.begin(), all.end(), [&](const T& x) { return x.name == w; }))
        {
            std::string valid;
            for (const auto& x : all)
            {
                valid += (valid.empty() ? "" : ", ") + x.name;
            }
            throw std::invalid_argument(
                option + ": no " + kind + " '" + w + "' (valid: " + valid + ")");
        }
    }
    std::vector<T> out;
    for (const auto& x : all)
    {
        if (std::find(wanted.begin(), wanted.end(), x.name) != wanted.end())
        {
            out.push_back(x);
        }
    }
    return out;
}
}  // namespace

std::vector<ExperimentVariant> ExperimentSuite::selectVariants(const std::string& only) const
{
    return selectByName(variants, only, "--variants", "variant");
}

std::vector<ExperimentSpec> ExperimentSuite::select(const std::string& only) const
{
    return selectByName(experiments, only, "--only", "experiment");
}

}  // namespace emslam::apps
