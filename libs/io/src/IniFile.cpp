// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/IniFile.h>
#include <emslam/io/InputFileChecks.h>

#include <mrpt/config/config_parser.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

namespace emslam::io
{
namespace
{
bool startsWith(const std::string& s, std::size_t i, const char* prefix)
{
    return s.compare(i, std::strlen(prefix), prefix) == 0;
}

/** For each line of config_parser()'s output, the line of `in` where it
 * starts. The preprocessor drops a `\` + newline (joining two lines) only
 * where its main loop meets the `\`, not inside `@define`, `${}`, `$eval{}`
 * or `$env{}`: this walk skips those the way it does. */
std::vector<unsigned> outputLineStarts(const std::string& in)
{
    std::vector<unsigned> starts{1};
    unsigned line = 1;
    const std::size_t n = in.size();
    std::size_t i = 0;
    // Skips to the end of a `${}`-like form: its '}' or the line end.
    auto skipBraced = [&]
    {
        while (i < n && in[i] != '\n' && in[i] != '\r')
        {
            if (in[i++] == '}')
            {
                break;
            }
        }
    };
    while (i < n)
    {
        const char c = in[i];
        if (c == '\\' && i + 1 < n && (in[i + 1] == '\r' || in[i + 1] == '\n'))
        {
            const bool crlf = i + 2 < n && in[i + 1] == '\r' && in[i + 2] == '\n';
            line += (crlf || in[i + 1] == '\n') ? 1 : 0;
            i += crlf ? 3 : 2;
        }
        else if (n > i + 7 && startsWith(in, i, "@define"))
        {
            while (i < n && in[i] != '\r' && in[i] != '\n')
            {
                ++i;
            }
        }
        else if (n > i + 4 && startsWith(in, i, "${"))
        {
            i += 2;
            skipBraced();
        }
        else if (
            (n > i + 7 && startsWith(in, i, "$eval{")) || (n > i + 6 && startsWith(in, i, "$env{")))
        {
            skipBraced();
        }
        else
        {
            if (c == '\n')
            {
                starts.push_back(++line);
            }
            ++i;
        }
    }
    return starts;
}

bool isBlank(char c)
{
    // SimpleIni's IsSpace(); '\r' and '\n' never reach here.
    return c == ' ' || c == '\t';
}

std::string trimmed(const std::string& s)
{
    std::size_t b = 0, e = s.size();
    while (b < e && isBlank(s[b]))
    {
        ++b;
    }
    while (e > b && isBlank(s[e - 1]))
    {
        --e;
    }
    return s.substr(b, e - b);
}

/** SimpleIni's SI_NoCase folds ASCII letters only. */
std::string folded(std::string s)
{
    for (auto& c : s)
    {
        if (c >= 'A' && c <= 'Z')
        {
            c = static_cast<char>(c - 'A' + 'a');
        }
    }
    return s;
}

struct Seen
{
    std::string spelling;
    unsigned line{0};
};

struct Section
{
    Seen header;  // line 0: keys before any section header
    std::map<std::string, Seen> keys;
};

std::string firstAt(const std::string& file, const Seen& first, const std::string& as)
{
    return "(first at " + file + ":" + std::to_string(first.line) +
           (as.empty() ? std::string() : " as " + as + "; names ignore case") + ")";
}

std::string sectionName(const std::string& s)
{
    return s.empty() ? std::string("the section before any [section]") : "[" + s + "]";
}
}  // namespace

void requireUniqueIniEntries(const std::string& text, const std::string& file)
{
    std::string pre;
    try
    {
        pre = mrpt::config::config_parser(text);
    }
    catch (const std::exception& e)
    {
        throw std::invalid_argument(file + ": " + e.what());
    }
    const std::vector<unsigned> starts = outputLineStarts(text);
    if (pre.compare(0, 3, "\xEF\xBB\xBF") == 0)
    {
        pre.erase(0, 3);  // SimpleIni skips a UTF-8 byte order mark
    }

    std::map<std::string, Section> sections;
    Section* current = &sections[""];
    std::vector<std::string> problems;
    std::size_t out_line = 0;
    std::size_t pos = 0;
    while (pos <= pre.size())
    {
        std::size_t end = pre.find('\n', pos);
        if (end == std::string::npos)
        {
            end = pre.size();
        }
        // An `$env{}` value with a newline adds output lines: stay on the last.
        const unsigned line = starts[std::min(out_line, starts.size() - 1)];
        const std::string where = file + ":" + std::to_string(line) + ": ";
        // SimpleIni also ends a line at a lone '\r'.
        std::size_t sub = pos;
        while (sub <= end)
        {
            std::size_t sub_end = pre.find('\r', sub);
            if (sub_end == std::string::npos || sub_end > end)
            {
                sub_end = end;
            }
            const std::string l = trimmed(pre.substr(sub, sub_end - sub));
            sub = sub_end + 1;
            if (l.find('\0') != std::string::npos)
            {
                throw std::invalid_argument(
                    where + "a NUL byte: not a text file (MRPT would stop reading there)");
            }
            if (l.empty() || l[0] == ';' || l[0] == '#')
            {
                continue;
            }
            if (l[0] == '[')
            {
                const std::size_t close = l.find(']');
                if (close == std::string::npos)
                {
                    throw std::invalid_argument(
                        where + "'" + l + "' has no closing ']' (MRPT would file the keys " +
                        "after it under a garbled section name)");
                }
                const std::string name = trimmed(l.substr(1, close - 1));
                Section& s = sections[folded(name)];
                if (s.header.line != 0)
                {
                    problems.push_back(
                        where + "section [" + name + "] repeated " +
                        firstAt(
                            file, s.header,
                            s.header.spelling == name ? "" : "[" + s.header.spelling + "]"));
                }
                else
                {
                    s.header = {name, line};
                }
                current = &s;
                continue;
            }
            const std::size_t eq = l.find('=');
            if (eq == std::string::npos || eq == 0)
            {
                continue;  // ignored by SimpleIni
            }
            const std::string key = trimmed(l.substr(0, eq));
            const auto [it, added] = current->keys.emplace(folded(key), Seen{key, line});
            if (!added)
            {
                const std::string& section =
                    current->header.line != 0 ? current->header.spelling : std::string();
                problems.push_back(
                    where + "key '" + key + "' repeated in " + sectionName(section) + " " +
                    firstAt(
                        file, it->second,
                        it->second.spelling == key ? "" : "'" + it->second.spelling + "'"));
            }
        }
        pos = end + 1;
        ++out_line;
    }
    if (!problems.empty())
    {
        std::string msg = problems.front();
        for (std::size_t i = 1; i < problems.size(); ++i)
        {
            msg += "\n" + problems[i];
        }
        throw std::invalid_argument(msg);
    }
}

std::string readIniFile(const std::string& file, const std::string& what)
{
    requireInputFile(file, what, MAX_INI_BYTES);
    const std::string name = what + " '" + file + "'";
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(file.c_str(), "rb"), &std::fclose);
    if (!f)
    {
        throw std::runtime_error("cannot read " + name + ": " + std::strerror(errno));
    }
    std::string text;
    char buf[1 << 16];
    while (text.size() <= MAX_INI_BYTES)
    {
        const std::size_t got = std::fread(buf, 1, sizeof(buf), f.get());
        text.append(buf, got);
        if (got < sizeof(buf))
        {
            if (std::ferror(f.get()))
            {
                throw std::runtime_error("cannot read " + name + ": " + std::strerror(errno));
            }
            break;
        }
    }
    if (text.size() > MAX_INI_BYTES)
    {
        // It grew after requireInputFile() looked at it.
        throw std::runtime_error(
            name + " has more than the " + std::to_string(MAX_INI_BYTES) + " bytes a " + what +
            " may have");
    }
    requireUniqueIniEntries(text, file);
    return text;
}

}  // namespace emslam::io
