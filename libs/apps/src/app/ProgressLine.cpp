// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/ProgressLine.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>

namespace emslam::apps
{
ProgressLine::ProgressLine(std::string program, std::size_t total, bool enabled)
    : m_program(std::move(program)),
      m_total(total),
      m_enabled(enabled),
      m_tty(::isatty(::fileno(stderr)) != 0),
      m_start(std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
                  .count())
{
}

std::size_t ProgressLine::extrapolateTotal(std::size_t done, double fraction)
{
    fraction = std::clamp(fraction, 0.0, 1.0);
    return fraction > 0
               ? static_cast<std::size_t>(std::lround(static_cast<double>(done) / fraction))
               : 0;
}

void ProgressLine::updateFraction(std::size_t done, double fraction, const std::string& extra)
{
    fraction = std::clamp(fraction, 0.0, 1.0);
    m_estimated_total = extrapolateTotal(done, fraction);
    if (!m_enabled)
    {
        return;
    }
    const int pct = static_cast<int>(100.0 * fraction);
    // Off a terminal: one line per 10 %, the 100 % line once.
    if (!m_tty && pct / 10 <= m_last_decile && (fraction < 1.0 || m_last_decile == 10))
    {
        return;
    }
    m_last_decile = pct / 10;
    const double now =
        std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    const double elapsed = now - m_start;
    const double fps = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
    const auto total = m_estimated_total;
    const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    const auto eta_s = static_cast<long>(std::lround(eta));
    std::fprintf(
        stderr, "%s%s: frame %zu/~%zu (%3d%%), %.1f fps, ETA %ld:%02ld%s%s%s", m_tty ? "\r" : "",
        m_program.c_str(), done, total, pct, fps, eta_s / 60, eta_s % 60, extra.empty() ? "" : ", ",
        extra.c_str(), m_tty ? "   " : "\n");
    std::fflush(stderr);
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
