// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/DataFile.h>

#include <filesystem>
#include <stdexcept>

namespace emslam::io
{
std::ifstream openTextFile(const std::string& file, const std::string& what)
{
    namespace fs = std::filesystem;
    const auto fail = [&](const std::string& reason)
    { throw std::runtime_error("Cannot open " + what + " '" + file + "': " + reason); };
    std::error_code ec;
    const auto status = fs::status(file, ec);
    if (!fs::exists(status))
    {
        fail("no such file");
    }
    if (!fs::is_regular_file(status))
    {
        fail("not a regular file");
    }
    const auto size = fs::file_size(file, ec);
    if (ec)
    {
        fail(ec.message());
    }
    if (size > MAX_TEXT_FILE_BYTES)
    {
        fail(
            std::to_string(size) + " bytes, more than the " + std::to_string(MAX_TEXT_FILE_BYTES) +
            " a dataset text file may have");
    }
    std::ifstream f(file, std::ios::binary);
    if (!f.is_open())
    {
        fail("cannot be read");
    }
    return f;
}

bool readBoundedLine(
    std::istream& in, std::string& line, const std::string& file, std::size_t line_no)
{
    line.clear();
    std::streambuf* buf = in.rdbuf();
    if (buf == nullptr || !in.good())
    {
        return false;
    }
    while (true)
    {
        const auto c = buf->sbumpc();
        if (c == std::char_traits<char>::eof())
        {
            in.setstate(std::ios::eofbit);
            return !line.empty();
        }
        if (c == '\n')
        {
            return true;
        }
        if (line.size() == MAX_LINE_BYTES)
        {
            throw std::runtime_error(
                file + ":" + std::to_string(line_no) + ": line longer than " +
                std::to_string(MAX_LINE_BYTES) + " bytes (binary data?)");
        }
        line.push_back(static_cast<char>(c));
    }
}

}  // namespace emslam::io
