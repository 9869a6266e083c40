// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstddef>
#include <string>

namespace emslam::apps
{
/** Progress of a frame loop on stderr: one line updated in place on a
 * terminal, otherwise one line per ~10 % (and one at the end), each as
 * `PROGRAM: frame DONE/TOTAL (PCT%)`.
 * \ingroup emslam_apps_grp \sa io::RawlogOutput */
class ProgressLine
{
public:
    /** `program` prefixes every line; nothing is printed when `enabled` is
     * false or `total` is 0. */
    ProgressLine(std::string program, std::size_t total, bool enabled);

    /** Reports that `done` of the `total` frames are finished. */
    void update(std::size_t done);

    /** For loops whose total is not known in advance (a streamed rawlog):
     * `fraction` of the input is consumed after `done` frames. Prints
     * `PROGRAM: frame DONE/~TOTAL (PCT%), F fps, ETA M:SS[, extra]`, with the
     * total and the ETA extrapolated from the fraction. */
    void updateFraction(std::size_t done, double fraction, const std::string& extra = {});

    /** The total of the last updateFraction() (even when printing is
     * disabled): extrapolateTotal() of its arguments; 0 before any. */
    std::size_t estimatedTotal() const { return m_estimated_total; }

    /** round(done / fraction): the frame count at which the input ends if
     * the frames still to come are the size of those done; 0 if `fraction`
     * is 0. */
    static std::size_t extrapolateTotal(std::size_t done, double fraction);

    /** Ends the in-place line on a terminal (call once, after the loop). */
    void finish();

private:
    std::string m_program;
    std::size_t m_total;
    bool m_enabled;
    bool m_tty;
    int m_last_decile{0};
    std::size_t m_estimated_total{0};
    double m_start{0.0};  //!< [s] steady clock at construction
};

}  // namespace emslam::apps
