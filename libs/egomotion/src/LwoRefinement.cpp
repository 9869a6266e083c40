// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/egomotion/LwoRefinement.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace emslam::egomotion
{
namespace
{
/** Segments shorter than this [m] count as degenerate (two points at the
 * same place): their ratio says nothing about the structure. */
constexpr double MIN_SEGMENT = 1e-6;
/** Upper bound of D_ijkl. A degenerate segment matched to a real one would
 * otherwise give an unbounded ratio that swamps the mean of Eq. 3; the cap
 * still makes such a pair maximally inconsistent. */
constexpr double MAX_D = 1e3;

double segmentRatio(double d_prev, double d_cur)
{
    const double lo = std::min(d_prev, d_cur), hi = std::max(d_prev, d_cur);
    if (hi < MIN_SEGMENT)
    {
        return 1.0;  // both degenerate: consistent
    }
    if (lo < MIN_SEGMENT)
    {
        return MAX_D;
    }
    return std::min(hi / lo, MAX_D);
}

double dist(const mrpt::math::TPoint3Df& p, const mrpt::math::TPoint3Df& q)
{
    const double dx = double(p.x) - q.x, dy = double(p.y) - q.y, dz = double(p.z) - q.z;
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}
}  // namespace

LwoResult refineLwo(
    const std::vector<mrpt::math::TPoint3Df>& a,
    const std::vector<mrpt::math::TPoint3Df>& b,
    double sigma_min)
{
    ASSERT_EQUAL_(a.size(), b.size());
    const std::size_t m = a.size();
    LwoResult res;
    if (m < 3)
    {
        // Fewer than three pairs carry no structural information to test.
        for (std::size_t i = 0; i < m; ++i)
        {
            res.kept.push_back(static_cast<int>(i));
        }
        return res;
    }

    // The O(M^2) pass: D_ik of Eq. 2 (float storage halves the memory of a
    // ~2000^2 matrix) and the row sums S_i = sum_k D_ik.
    std::vector<float> d(m * m, 1.0f);
    std::vector<double> s(m, 0.0);
    for (std::size_t i = 0; i < m; ++i)
    {
        for (std::size_t k = i + 1; k < m; ++k)
        {
            const float dik = static_cast<float>(segmentRatio(dist(a[i], a[k]), dist(b[i], b[k])));
            d[i * m + k] = dik;
            d[k * m + i] = dik;
            s[i] += dik;
            s[k] += dik;
        }
    }

    std::vector<char> alive(m, 1);
    std::size_t n = m;
    for (;;)
    {
        // D_i = S_i / (n - 1) (Eq. 3) and its spread over the survivors, O(n).
        const double inv = 1.0 / static_cast<double>(n - 1);
        double sum = 0, sum2 = 0, worst_val = -1;
        std::size_t worst = 0;
        for (std::size_t i = 0; i < m; ++i)
        {
            if (!alive[i])
            {
                continue;
            }
            const double di = s[i] * inv;
            sum += di;
            sum2 += di * di;
            if (di > worst_val)
            {
                worst_val = di;
                worst = i;
            }
        }
        const double mean = sum / static_cast<double>(n);
        res.final_sigma = std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - mean * mean));
        // Two matches always have equal D_i (sigma = 0): stop at three.
        if (res.final_sigma <= sigma_min || n < 3)
        {
            break;
        }

        // Leave the worst out and update every running sum, O(n).
        alive[worst] = 0;
        --n;
        ++res.iterations;
        const float* row = &d[worst * m];
        for (std::size_t i = 0; i < m; ++i)
        {
            if (alive[i])
            {
                s[i] -= row[i];
            }
        }
        if (n < 3)
        {
            res.final_sigma = 0;
            break;
        }
    }

    for (std::size_t i = 0; i < m; ++i)
    {
        if (alive[i])
        {
            res.kept.push_back(static_cast<int>(i));
        }
    }
    return res;
}

}  // namespace emslam::egomotion
