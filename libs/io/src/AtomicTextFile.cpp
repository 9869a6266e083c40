// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/AtomicFile.h>
#include <emslam/io/AtomicTextFile.h>
#include <emslam/io/OutputPathChecks.h>

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace emslam::io
{
AtomicTextFile::AtomicTextFile(std::string file)
    : m_file(requireOutputFile(file, "output file")), m_tmp(partialFileFor(m_file))
{
    m_out.open(m_tmp, std::ios::out | std::ios::binary | std::ios::trunc);
    if (!m_out)
    {
        throw std::runtime_error("cannot write '" + m_file + "'");
    }
}

AtomicTextFile::~AtomicTextFile()
{
    if (!m_committed)
    {
        m_out.close();
        std::error_code ignored;
        std::filesystem::remove(m_tmp, ignored);
    }
}

void AtomicTextFile::commit()
{
    m_out.flush();
    m_out.close();
    if (!m_out)
    {
        throw std::runtime_error("cannot write '" + m_file + "' (disk full?)");
    }
    commitPartialFile(m_tmp, m_file);
    m_committed = true;
}

void writeTextAtomically(const std::string& file, const std::string& text)
{
    AtomicTextFile f(file);
    f.stream() << text;
    f.commit();
}

}  // namespace emslam::io
