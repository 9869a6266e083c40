// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cctype>
#include <ostream>
#include <string>
#include <vector>

namespace emslam::util
{
/** A section (empty keys) or a key that took a new name; the old one is
 * still read. \ingroup emslam_util_grp */
struct ConfigRename
{
    std::string old_section;  //!< the former section
    std::string old_key;      //!< the former key; empty: the whole section
    std::string new_section;  //!< the section it is read as
    std::string new_key;      //!< the key it is read as (with old_key)
};

namespace detail
{
inline bool sameName(const std::string& a, const std::string& b)
{
    if (a.size() != b.size())
    {
        return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i)
    {
        if (std::tolower(static_cast<unsigned char>(a[i])) !=
            std::tolower(static_cast<unsigned char>(b[i])))
        {
            return false;
        }
    }
    return true;
}
}  // namespace detail

/** A copy of `in` in which every entry found under an old name of `renames`
 * is read under its new name. A value already under the new name wins.
 * Writes one line per old name found to `warnings`, naming the new one.
 * Names compare case-insensitively, as MRPT reads them. Values are copied as
 * read_string() gives them ($env{}, $eval{} done, comments dropped). */
inline mrpt::config::CConfigFileMemory withCurrentNames(
    const mrpt::config::CConfigFileBase& in,
    const std::vector<ConfigRename>& renames,
    std::ostream& warnings)
{
    mrpt::config::CConfigFileMemory out;
    std::vector<std::string> sections;
    in.getAllSections(sections);
    for (const auto& section : sections)
    {
        std::vector<std::string> keys;
        in.getAllKeys(section, keys);
        for (const auto& key : keys)
        {
            std::string new_section = section, new_key = key;
            const ConfigRename* used = nullptr;
            for (const auto& r : renames)
            {
                if (!detail::sameName(r.old_section, section))
                {
                    continue;
                }
                if (r.old_key.empty())
                {
                    new_section = r.new_section;
                    used = &r;
                }
                else if (detail::sameName(r.old_key, key))
                {
                    new_section = r.new_section;
                    new_key = r.new_key;
                    used = &r;
                    break;
                }
            }
            if (used != nullptr && in.keyExists(new_section, new_key))
            {
                continue;  // the new name is set too: it wins
            }
            out.write(new_section, new_key, in.read_string(section, key, {}));
        }
    }
    for (const auto& r : renames)
    {
        const bool found = r.old_key.empty() ? in.sectionExists(r.old_section)
                                             : in.keyExists(r.old_section, r.old_key);
        if (!found)
        {
            continue;
        }
        if (r.old_key.empty())
        {
            warnings << "warning: section [" << r.old_section << "] is now [" << r.new_section
                     << "]; read as such\n";
        }
        else
        {
            warnings << "warning: [" << r.old_section << "] " << r.old_key << " is now ["
                     << r.new_section << "] " << r.new_key << "; read as such\n";
        }
    }
    return out;
}

}  // namespace emslam::util
