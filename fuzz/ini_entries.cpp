// SPDX-License-Identifier: BSD-3-Clause
// INI files: requireUniqueIniEntries() on arbitrary text, checked against
// MRPT: a text it accepts that MRPT reads as holding a section or a key must
// be refused when written twice (every entry then repeats).
#include "FuzzFile.h"

#include <emslam/io/IniFile.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
bool accepted(const std::string& text)
{
    try
    {
        emslam::io::requireUniqueIniEntries(text, "fuzz.ini");
        return true;
    }
    catch (const std::invalid_argument&)
    {
        return false;  // a repetition, a NUL, an unclosed '[' or a preprocessor error
    }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string text{emslam::fuzz::asText(data, size)};
    if (!accepted(text))
    {
        return 0;
    }
    std::vector<std::string> sections;
    try
    {
        mrpt::config::CConfigFileMemory(text).getAllSections(sections);
    }
    catch (const std::exception&)
    {
        return 0;
    }
    // A blank line between the copies: a `\` ending the first copy joins it.
    // A UTF-8 byte order mark is skipped only at the very start of the text
    // once lines are joined, so a copy may hold one the first did not: texts
    // with its first byte are left out of this check.
    if (text.find('\xEF') != std::string::npos)
    {
        return 0;
    }
    if (!sections.empty() && accepted(text + "\n\n" + text))
    {
        std::fprintf(stderr, "ini_entries: the text written twice was accepted\n");
        std::abort();
    }
    return 0;
}
