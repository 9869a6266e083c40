// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/EurocSensorYaml.h>
#include <emslam/io/TextParsing.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>

namespace emslam::io
{
namespace
{
/** `line` without a trailing comment: a `#` at its start or after a blank. */
std::string_view withoutComment(std::string_view line)
{
    for (std::size_t i = 0; i < line.size(); ++i)
    {
        if (line[i] == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t'))
        {
            return line.substr(0, i);
        }
    }
    return line;
}

bool isKeyChar(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
}

/** Drops one pair of matching quotes around a scalar. */
std::string unquoted(std::string_view v)
{
    if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'') && v.back() == v.front())
    {
        v = v.substr(1, v.size() - 2);
    }
    return std::string(v);
}

std::string errorPrefix(const std::string& file, std::size_t line, const std::string& key)
{
    std::string s = "EuRoC sensor.yaml '" + file + "'";
    if (line > 0)
    {
        s += " line " + std::to_string(line);
    }
    s += ": ";
    if (!key.empty())
    {
        s += "key " + quotedExcerpt(key) + ": ";
    }
    return s;
}

[[noreturn]] void parseError(
    const std::string& file, std::size_t line, const std::string& key, const std::string& problem)
{
    throw std::runtime_error(errorPrefix(file, line, key) + "malformed YAML: " + problem);
}

}  // namespace

EurocSensorYaml EurocSensorYaml::load(const std::string& file)
{
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::exists(file, ec))
    {
        throw std::runtime_error(errorPrefix(file, 0, {}) + "file not found");
    }
    // Devices and FIFOs (/dev/zero, a pipe) would never end or never fit.
    if (!fs::is_regular_file(file, ec))
    {
        throw std::runtime_error(errorPrefix(file, 0, {}) + "not a regular file");
    }
    std::ifstream in(file, std::ios::binary);
    if (!in)
    {
        throw std::runtime_error(errorPrefix(file, 0, {}) + "cannot open file");
    }
    std::string text(MAX_FILE_BYTES + 1, '\0');
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    text.resize(static_cast<std::size_t>(in.gcount()));
    if (text.size() > MAX_FILE_BYTES)
    {
        throw std::runtime_error(
            errorPrefix(file, 0, {}) + "larger than " + std::to_string(MAX_FILE_BYTES) +
            " bytes: not a sensor.yaml");
    }
    if (text.empty())
    {
        throw std::runtime_error(errorPrefix(file, 0, {}) + "empty file");
    }
    return parse(text, file);
}

/** The line-by-line reader of parse(): top-level keys, one level of maps,
 * flow lists (possibly over several lines) and scalars. */
class EurocSensorYaml::Parser
{
public:
    Parser(EurocSensorYaml& y, const std::string& file) : m_y(y), m_file(file) {}

    void readLine(std::string_view line)
    {
        ++m_line_no;
        if (!line.empty() && line.back() == '\r')
        {
            line.remove_suffix(1);
        }
        for (const char c : line)
        {
            const auto u = static_cast<unsigned char>(c);
            if ((u < 0x20 && c != '\t') || u == 0x7f)
            {
                parseError(m_file, m_line_no, {}, "control character (binary data?)");
            }
        }
        if (m_line_no == 1 && line.substr(0, 5) == "%YAML")
        {
            return;
        }
        const std::string_view content = withoutComment(line);
        if (m_list_key)
        {
            // A "key:" line inside a list means its ']' is missing (numbers have no ':').
            if (content.find(':') != std::string_view::npos)
            {
                parseError(
                    m_file, m_y.m_entries.at(*m_list_key).line, *m_list_key,
                    "list not closed (missing ']') before line " + std::to_string(m_line_no));
            }
            readListText(content);
            return;
        }
        if (isBlank(content) || (m_y.m_entries.empty() && trimmed(content) == "---"))
        {
            return;
        }
        readKeyLine(content);
    }

    /** At the end of the text: no list left open, some entry read. */
    void finish() const
    {
        if (m_list_key)
        {
            parseError(
                m_file, m_y.m_entries.at(*m_list_key).line, *m_list_key,
                "list not closed (missing ']') before the end of the file");
        }
        if (m_y.m_entries.empty())
        {
            parseError(m_file, 0, {}, "no 'key: value' line");
        }
    }

private:
    /** A 'key: value' line (value empty: a map opens). */
    void readKeyLine(std::string_view content)
    {
        const auto indent = content.find_first_not_of(' ');
        if (content[indent] == '\t')
        {
            parseError(m_file, m_line_no, {}, "tab in the indentation (use spaces)");
        }
        const std::string_view body = trimmed(content);
        std::size_t key_end = 0;
        while (key_end < body.size() && isKeyChar(body[key_end]))
        {
            ++key_end;
        }
        if (key_end == 0 || key_end == body.size() || body[key_end] != ':' ||
            (key_end + 1 < body.size() && body[key_end + 1] != ' ' && body[key_end + 1] != '\t'))
        {
            parseError(m_file, m_line_no, {}, "expected 'key: value', got " + quotedExcerpt(body));
        }
        const std::string name(body.substr(0, key_end));
        const std::string_view value = trimmed(body.substr(key_end + 1));
        if (indent == 0)
        {
            m_map_key.clear();
        }
        else if (m_map_key.empty())
        {
            parseError(m_file, m_line_no, name, "indented key outside a map");
        }
        const std::string key = indent == 0 ? name : m_map_key + "." + name;

        Entry e;
        e.line = m_line_no;
        if (value.empty())
        {
            if (indent != 0)
            {
                parseError(m_file, m_line_no, key, "maps nested deeper than one level");
            }
            e.kind = Kind::Map;
            addEntry(key, e);
            m_map_key = key;
        }
        else if (value.front() == '[')
        {
            e.kind = Kind::List;
            addEntry(key, e);
            m_list_key = key;
            readListText(value.substr(1));
        }
        else if (std::string_view("{&*!|>]").find(value.front()) != std::string_view::npos)
        {
            parseError(m_file, m_line_no, key, "unsupported YAML value " + quotedExcerpt(value));
        }
        else
        {
            e.scalar = unquoted(value);
            addEntry(key, e);
        }
    }

    void addEntry(const std::string& key, Entry e)
    {
        if (const auto it = m_y.m_entries.find(key); it != m_y.m_entries.end())
        {
            parseError(
                m_file, e.line, key,
                "duplicate key (first at line " + std::to_string(it->second.line) + ")");
        }
        m_y.m_entries.emplace(key, std::move(e));
    }

    /** Appends list text up to a ']' (then closes the list). */
    void readListText(std::string_view rest)
    {
        const auto close = rest.find(']');
        const std::string_view part = rest.substr(0, close);
        if (part.find('[') != std::string_view::npos || part.find('{') != std::string_view::npos)
        {
            parseError(m_file, m_line_no, *m_list_key, "nested lists or maps are not supported");
        }
        m_list_text.append(part);
        m_list_text += ' ';
        if (close == std::string_view::npos)
        {
            return;
        }
        if (!isBlank(rest.substr(close + 1)))
        {
            parseError(
                m_file, m_line_no, *m_list_key,
                "unexpected " + quotedExcerpt(trimmed(rest.substr(close + 1))) + " after ']'");
        }
        if (!isBlank(m_list_text))
        {
            splitListItems(m_y.m_entries.at(*m_list_key).items);
        }
        m_list_key.reset();
        m_list_text.clear();
    }

    /** The comma-separated elements of the list text, none empty. */
    void splitListItems(std::vector<std::string>& items) const
    {
        std::size_t start = 0;
        while (true)
        {
            const auto comma = m_list_text.find(',', start);
            const auto item =
                trimmed(std::string_view(m_list_text)
                            .substr(start, comma == std::string::npos ? comma : comma - start));
            if (item.empty())
            {
                parseError(m_file, m_line_no, *m_list_key, "empty list element");
            }
            items.emplace_back(item);
            if (comma == std::string::npos)
            {
                break;
            }
            start = comma + 1;
        }
    }

    EurocSensorYaml& m_y;
    const std::string& m_file;
    std::string m_map_key;                  // the open map ("T_BS"), empty at top level
    std::optional<std::string> m_list_key;  // the list being read, up to its ']'
    std::string m_list_text;
    std::size_t m_line_no{0};
};

EurocSensorYaml EurocSensorYaml::parse(std::string_view text, const std::string& file)
{
    EurocSensorYaml y;
    y.m_file = file;
    Parser parser(y, file);
    std::size_t pos = 0;
    while (pos < text.size())
    {
        const auto eol = text.find('\n', pos);
        const std::string_view line =
            text.substr(pos, eol == std::string_view::npos ? eol : eol - pos);
        pos = eol == std::string_view::npos ? text.size() : eol + 1;
        parser.readLine(line);
    }
    parser.finish();
    return y;
}

bool EurocSensorYaml::has(const std::string& key) const
{
    return m_entries.count(key) > 0;
}

bool EurocSensorYaml::isMap(const std::string& key) const
{
    const auto it = m_entries.find(key);
    return it != m_entries.end() && it->second.kind == Kind::Map;
}

bool EurocSensorYaml::isList(const std::string& key) const
{
    const auto it = m_entries.find(key);
    return it != m_entries.end() && it->second.kind == Kind::List;
}

const EurocSensorYaml::Entry& EurocSensorYaml::entry(const std::string& key) const
{
    const auto it = m_entries.find(key);
    if (it == m_entries.end())
    {
        throw std::runtime_error(errorPrefix(m_file, 0, {}) + "missing key '" + key + "'");
    }
    return it->second;
}

void EurocSensorYaml::fail(
    std::size_t line, const std::string& key, const std::string& problem) const
{
    throw std::runtime_error(errorPrefix(m_file, line, key) + problem);
}

std::string EurocSensorYaml::text(const std::string& key) const
{
    const Entry& e = entry(key);
    if (e.kind != Kind::Scalar)
    {
        fail(
            e.line, key,
            e.kind == Kind::List ? "a list, expected a value" : "a map, expected a value");
    }
    return e.scalar;
}

double EurocSensorYaml::number(const std::string& key) const
{
    const std::string s = text(key);
    double v = 0;
    if (!parseDouble(s, v) || !std::isfinite(v))
    {
        fail(entry(key).line, key, quotedExcerpt(s) + " is not a finite number");
    }
    return v;
}

std::vector<double> EurocSensorYaml::numbers(
    const std::string& key, const std::vector<std::size_t>& allowed_sizes) const
{
    const Entry& e = entry(key);
    if (e.kind != Kind::List)
    {
        fail(e.line, key, "not a list of numbers [a, b, ...]");
    }
    std::vector<double> out;
    out.reserve(e.items.size());
    for (const auto& item : e.items)
    {
        double v = 0;
        if (!parseDouble(item, v))
        {
            fail(
                e.line, key,
                "element " + std::to_string(out.size()) + " " + quotedExcerpt(item) +
                    " is not a number");
        }
        if (!std::isfinite(v))
        {
            fail(e.line, key, "element " + std::to_string(out.size()) + " is not finite");
        }
        out.push_back(v);
    }
    bool size_ok = false;
    std::string expected;
    for (const auto n : allowed_sizes)
    {
        size_ok = size_ok || out.size() == n;
        expected += (expected.empty() ? "" : " or ") + std::to_string(n);
    }
    if (!size_ok)
    {
        fail(e.line, key, "has " + std::to_string(out.size()) + " numbers, expected " + expected);
    }
    return out;
}

std::size_t EurocSensorYaml::lineOf(const std::string& key) const
{
    return entry(key).line;
}

}  // namespace emslam::io
