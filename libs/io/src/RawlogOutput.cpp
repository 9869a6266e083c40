// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/io/AtomicFile.h>
#include <emslam/io/OutputFile.h>
#include <emslam/io/OutputPathChecks.h>
#include <emslam/io/RawlogOutput.h>

#include <filesystem>
#include <system_error>

namespace fs = std::filesystem;

namespace emslam::io
{
namespace
{
void removeQuietly(const std::string& file)
{
    if (!file.empty())
    {
        std::error_code ec;
        fs::remove(file, ec);
    }
}
}  // namespace

void RawlogOutput::checkOutputFolders(const std::string& file, const std::string& gt_file)
{
    requireOutputFile(file, "output rawlog");
    if (!gt_file.empty())
    {
        requireOutputFile(gt_file, "ground-truth output file");
    }
}

RawlogOutput::RawlogOutput(const std::string& file, int gz_level, const std::string& gt_file)
    : m_file(requireOutputFile(file, "output rawlog")),
      m_partial(partialFileFor(m_file)),
      m_gt_file(
          gt_file.empty() ? std::string() : requireOutputFile(gt_file, "ground-truth output file")),
      m_gt_partial(m_gt_file.empty() ? std::string() : partialFileFor(m_gt_file))
{
    m_stream = std::make_unique<GzOutputStream>(m_partial, gz_level, m_file);
    m_archive =
        std::make_unique<mrpt::serialization::CArchiveStreamBase<GzOutputStream>>(*m_stream);
}

RawlogOutput::~RawlogOutput()
{
    if (!m_committed)
    {
        m_archive.reset();
        m_stream.reset();
        removeQuietly(m_partial);
        removeQuietly(m_gt_partial);
    }
}

std::size_t RawlogOutput::commit(const emslam::io::TumTrajectory& ground_truth)
{
    m_archive.reset();
    m_stream->close();
    if (!m_gt_partial.empty())
    {
        OutputFile gt(m_gt_partial, m_gt_file);
        ground_truth.writeTo(gt.text());
        gt.close();
    }
    commitPartialFile(m_partial, m_file);
    std::size_t poses = 0;
    if (!m_gt_partial.empty())
    {
        commitPartialFile(m_gt_partial, m_gt_file);
        poses = ground_truth.size();
    }
    m_committed = true;
    return poses;
}

void RawlogOutput::keepWhatWasWritten()
{
    m_archive.reset();
    try
    {
        m_stream->close();
    }
    catch (const std::exception&)
    {
        // Known to the caller already: the write that failed threw.
    }
    commitPartialFile(m_partial, m_file);
    m_committed = true;
}

}  // namespace emslam::io
