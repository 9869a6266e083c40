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
    m_out = std::make_unique<OutputFile>(m_tmp, m_file);
}

AtomicTextFile::~AtomicTextFile()
{
    if (!m_committed)
    {
        m_out.reset();
        std::error_code ignored;
        std::filesystem::remove(m_tmp, ignored);
    }
}

void AtomicTextFile::commit()
{
    m_out->close();
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
