// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/egomotion/FeatureMatcher.h>

#include <mrpt/core/exceptions.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

namespace emslam::egomotion
{
namespace
{
using RowMajorMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/** Rows of `prev` per block: the block of S (BLOCK x |cur| floats) stays
 * small even at full KITTI resolution, where the whole S would take GBs. */
constexpr Eigen::Index BLOCK = 256;
}  // namespace

MatchList matchMutual(const Descriptors& prev, const Descriptors& cur, float similarity_min)
{
    MatchList out;
    const auto np = static_cast<Eigen::Index>(prev.size());
    const auto nc = static_cast<Eigen::Index>(cur.size());
    if (np == 0 || nc == 0)
    {
        return out;
    }
    ASSERT_EQUAL_(prev.dim, cur.dim);
    const Eigen::Index dim = prev.dim;

    const Eigen::Map<const RowMajorMatrix> P(prev.data.data(), np, dim);
    const Eigen::Map<const RowMajorMatrix> C(cur.data.data(), nc, dim);

    // Best of each prev row, and best of each cur column over all blocks.
    // A score must be > 0: a zero (flat) descriptor matches nothing.
    std::vector<int> best_cur(static_cast<std::size_t>(np), -1);
    std::vector<float> best_cur_s(static_cast<std::size_t>(np), 0.0f);
    std::vector<int> best_prev(static_cast<std::size_t>(nc), -1);
    std::vector<float> best_prev_s(static_cast<std::size_t>(nc), 0.0f);

    RowMajorMatrix S;
    for (Eigen::Index i0 = 0; i0 < np; i0 += BLOCK)
    {
        const Eigen::Index rows = std::min(BLOCK, np - i0);
        S.noalias() = P.middleRows(i0, rows) * C.transpose();
        for (Eigen::Index r = 0; r < rows; ++r)
        {
            const auto i = static_cast<std::size_t>(i0 + r);
            const float* s_row = S.data() + r * nc;
            for (Eigen::Index j = 0; j < nc; ++j)
            {
                // |rho|: a contrast inversion is still the same texture.
                const float s = std::abs(s_row[j]);
                if (s > best_cur_s[i])
                {
                    best_cur_s[i] = s;
                    best_cur[i] = static_cast<int>(j);
                }
                if (s > best_prev_s[static_cast<std::size_t>(j)])
                {
                    best_prev_s[static_cast<std::size_t>(j)] = s;
                    best_prev[static_cast<std::size_t>(j)] = static_cast<int>(i);
                }
            }
        }
    }

    for (Eigen::Index i = 0; i < np; ++i)
    {
        const int j = best_cur[static_cast<std::size_t>(i)];
        if (j < 0 || best_prev[static_cast<std::size_t>(j)] != static_cast<int>(i))
        {
            continue;  // not mutual
        }
        const float s = best_cur_s[static_cast<std::size_t>(i)];
        if (s >= similarity_min)
        {
            out.push_back({static_cast<int>(i), j, std::min(s, 1.0f)});
        }
    }
    return out;
}

}  // namespace emslam::egomotion
