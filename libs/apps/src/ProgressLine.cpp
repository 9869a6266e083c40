// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/ProgressLine.h>

#include <unistd.h>

#include <cstdio>
#include <utility>

namespace emslam::apps
{
ProgressLine::ProgressLine(std::string program, std::size_t total, bool enabled)
    : m_program(std::move(program)),
      m_total(total),
      m_enabled(enabled),
      m_tty(::isatty(::fileno(stderr)) != 0)
{
}

void ProgressLine::update(std::size_t done)
{
    if (!m_enabled || m_total == 0)
    {
        return;
    }
    const auto pct = static_cast<int>((100 * done) / m_total);
    if (m_tty)
    {
        std::fprintf(stderr, "\r%s: frame %zu/%zu (%3d%%)", m_program.c_str(), done, m_total, pct);
        std::fflush(stderr);
    }
    else if (pct / 10 > m_last_decile || done == m_total)
    {
        m_last_decile = pct / 10;
        std::fprintf(stderr, "%s: frame %zu/%zu (%d%%)\n", m_program.c_str(), done, m_total, pct);
    }
}

void ProgressLine::finish()
{
    if (m_enabled && m_tty)
    {
        std::fprintf(stderr, "\n");
    }
}

}  // namespace emslam::apps
