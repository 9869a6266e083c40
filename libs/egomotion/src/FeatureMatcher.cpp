// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/egomotion/DescriptorProducts.h>
#include <emslam/egomotion/FeatureMatcher.h>

#include <mrpt/core/exceptions.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

namespace emslam::egomotion
{
namespace
{
using RowMajorMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/** Rows of `prev` per block: the block of S (BLOCK x |cur| floats) stays
 * small even at full KITTI resolution, where the whole S would take GBs. */
constexpr Eigen::Index BLOCK = 256;

/** The runners-up of Distinctiveness: per prev row, the best score among
 * current features away from its best; per cur column, likewise among
 * previous features. Fed every candidate pair (i, j, s) after the bests are
 * known. */
class RunnersUp
{
public:
    RunnersUp(
        const Distinctiveness& d,
        const std::vector<int>& best_cur,
        const std::vector<int>& best_prev)
        : m_d(d),
          m_best_cur(best_cur),
          m_best_prev(best_prev),
          m_cur_s(best_cur.size(), 0.0f),
          m_prev_s(best_prev.size(), 0.0f),
          m_r2(d.same_place_px * d.same_place_px)
    {
    }

    void add(std::size_t i, std::size_t j, float s)
    {
        const int bc = m_best_cur[i];
        if (bc >= 0 && s > m_cur_s[i] &&
            apart((*m_d.cur_features)[j], (*m_d.cur_features)[static_cast<std::size_t>(bc)]))
        {
            m_cur_s[i] = s;
        }
        const int bp = m_best_prev[j];
        if (bp >= 0 && s > m_prev_s[j] &&
            apart((*m_d.prev_features)[i], (*m_d.prev_features)[static_cast<std::size_t>(bp)]))
        {
            m_prev_s[j] = s;
        }
    }

    /** Whether the match (i, j) of score s stands clear on both sides. */
    bool clear(std::size_t i, std::size_t j, float s) const
    {
        return m_d.clear(s, m_cur_s[i]) && m_d.clear(s, m_prev_s[j]);
    }

private:
    bool apart(const Feature& a, const Feature& b) const
    {
        const float du = static_cast<float>(a.u) - static_cast<float>(b.u);
        const float dv = static_cast<float>(a.v) - static_cast<float>(b.v);
        return du * du + dv * dv > m_r2;
    }

    const Distinctiveness& m_d;
    const std::vector<int>& m_best_cur;
    const std::vector<int>& m_best_prev;
    std::vector<float> m_cur_s, m_prev_s;
    float m_r2;
};

void checkDistinctiveness(const Distinctiveness& d, std::size_t np, std::size_t nc)
{
    if (d.enabled())
    {
        ASSERT_EQUAL_(d.prev_features->size(), np);
        ASSERT_EQUAL_(d.cur_features->size(), nc);
    }
}

/** Current features bucketed in square cells of `cell` px: a disc of that
 * radius around any point touches at most the 3x3 cells around its own. */
class FeatureGrid
{
public:
    FeatureGrid(const FeatureList& features, float cell) : m_features(features), m_cell(cell)
    {
        int max_u = 0, max_v = 0;
        for (const auto& f : features)
        {
            max_u = std::max<int>(max_u, f.u);
            max_v = std::max<int>(max_v, f.v);
        }
        m_cols = static_cast<int>(static_cast<float>(max_u) / cell) + 1;
        m_rows = static_cast<int>(static_cast<float>(max_v) / cell) + 1;
        // Counting sort by cell: m_in_cell[m_start[c] .. m_start[c + 1]) are cell c's.
        m_start.assign(static_cast<std::size_t>(m_cols * m_rows) + 1, 0);
        m_in_cell.resize(features.size());
        for (std::size_t j = 0; j < features.size(); ++j)
        {
            ++m_start[cellOf(j) + 1];
        }
        for (std::size_t c = 1; c < m_start.size(); ++c)
        {
            m_start[c] += m_start[c - 1];
        }
        std::vector<std::size_t> fill(m_start.begin(), m_start.end() - 1);
        for (std::size_t j = 0; j < features.size(); ++j)
        {
            m_in_cell[fill[cellOf(j)]++] = j;
        }
        // The positions in the same order: a search reads them in one sweep.
        m_u_in_cell.resize(features.size());
        m_v_in_cell.resize(features.size());
        for (std::size_t k = 0; k < features.size(); ++k)
        {
            m_u_in_cell[k] = static_cast<float>(features[m_in_cell[k]].u);
            m_v_in_cell[k] = static_cast<float>(features[m_in_cell[k]].v);
        }
    }

    /** Calls visit(j) for every feature j within `radius` px of p. */
    template <typename Visit>
    void forEachNear(const cv::Point2f& p, float radius, const Visit& visit) const
    {
        const float r2 = radius * radius;
        const int cu = static_cast<int>(std::floor(p.x / m_cell));
        const int cv_ = static_cast<int>(std::floor(p.y / m_cell));
        const int x0 = std::max(cu - 1, 0), x1 = std::min(cu + 1, m_cols - 1);
        if (x0 > x1)
        {
            return;
        }
        for (int y = std::max(cv_ - 1, 0); y <= std::min(cv_ + 1, m_rows - 1); ++y)
        {
            // Cells x0 .. x1 of a row are one run of the cell order.
            const auto first = m_start[static_cast<std::size_t>(y * m_cols + x0)];
            const auto last = m_start[static_cast<std::size_t>(y * m_cols + x1) + 1];
            for (std::size_t k = first; k < last; ++k)
            {
                const float du = m_u_in_cell[k] - p.x;
                const float dv = m_v_in_cell[k] - p.y;
                if (du * du + dv * dv <= r2)
                {
                    visit(m_in_cell[k]);
                }
            }
        }
    }

private:
    std::size_t cellOf(std::size_t j) const
    {
        const auto& f = m_features[j];
        return static_cast<std::size_t>(
            static_cast<int>(static_cast<float>(f.v) / m_cell) * m_cols +
            static_cast<int>(static_cast<float>(f.u) / m_cell));
    }

    const FeatureList& m_features;
    float m_cell;
    int m_cols{0}, m_rows{0};
    std::vector<std::size_t> m_start;
    std::vector<std::size_t> m_in_cell;
    std::vector<float> m_u_in_cell, m_v_in_cell;
};

/** Calls visit(i, j, s) for every previous feature i with a finite
 * prediction and every current feature j within `radius_px` of it, s the
 * |similarity| of their descriptors. */
template <typename Visit>
void forEachGuidedCandidate(
    const Descriptors& prev,
    const Descriptors& cur,
    const std::vector<cv::Point2f>& predicted,
    const FeatureGrid& grid,
    float radius_px,
    const Visit& visit)
{
    const auto dim = static_cast<Eigen::Index>(prev.dim);
    std::vector<std::uint32_t> near;
    std::vector<float> sims;
    for (std::size_t i = 0; i < prev.size(); ++i)
    {
        const cv::Point2f p = predicted[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
        {
            continue;
        }
        near.clear();
        grid.forEachNear(
            p, radius_px, [&](std::size_t j) { near.push_back(static_cast<std::uint32_t>(j)); });
        // All candidates of i at once: the products run four by four.
        sims.resize(near.size());
        DescriptorProducts::dotRows(
            prev.row(i), cur.row(0), near.data(), near.size(), dim, sims.data());
        for (std::size_t k = 0; k < near.size(); ++k)
        {
            // |rho|: a contrast inversion is still the same texture.
            visit(i, static_cast<std::size_t>(near[k]), std::abs(sims[k]));
        }
    }
}

/** The best partner of each previous and of each current feature. */
struct BestPartners
{
    BestPartners(std::size_t np, std::size_t nc)
        : best_cur(np, -1), best_cur_s(np, 0.0f), best_prev(nc, -1), best_prev_s(nc, 0.0f)
    {
    }

    void add(std::size_t i, std::size_t j, float s)
    {
        // Ties: the lowest index wins, as in matchMutual().
        if (s > best_cur_s[i] || (s == best_cur_s[i] && s > 0 && static_cast<int>(j) < best_cur[i]))
        {
            best_cur_s[i] = s;
            best_cur[i] = static_cast<int>(j);
        }
        if (s > best_prev_s[j] ||
            (s == best_prev_s[j] && s > 0 && static_cast<int>(i) < best_prev[j]))
        {
            best_prev_s[j] = s;
            best_prev[j] = static_cast<int>(i);
        }
    }

    std::vector<int> best_cur;  //!< per previous feature, -1: none
    std::vector<float> best_cur_s;
    std::vector<int> best_prev;  //!< per current feature, -1: none
    std::vector<float> best_prev_s;
};
}  // namespace

MatchList matchMutual(
    const Descriptors& prev,
    const Descriptors& cur,
    float similarity_min,
    const Distinctiveness& distinct)
{
    MatchList out;
    const auto np = static_cast<Eigen::Index>(prev.size());
    const auto nc = static_cast<Eigen::Index>(cur.size());
    if (np == 0 || nc == 0)
    {
        return out;
    }
    ASSERT_EQUAL_(prev.dim, cur.dim);
    checkDistinctiveness(distinct, prev.size(), cur.size());
    const Eigen::Index dim = prev.dim;

    const DescriptorProducts products(cur.data.data(), nc, dim);

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
        products.multiply(prev.row(static_cast<std::size_t>(i0)), rows, S);
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

    std::optional<RunnersUp> runners_up;
    if (distinct.enabled())
    {
        // Second pass: S again (storing it whole would not fit), now that
        // the bests are known.
        runners_up.emplace(distinct, best_cur, best_prev);
        for (Eigen::Index i0 = 0; i0 < np; i0 += BLOCK)
        {
            const Eigen::Index rows = std::min(BLOCK, np - i0);
            products.multiply(prev.row(static_cast<std::size_t>(i0)), rows, S);
            for (Eigen::Index r = 0; r < rows; ++r)
            {
                const auto i = static_cast<std::size_t>(i0 + r);
                const float* s_row = S.data() + r * nc;
                for (Eigen::Index j = 0; j < nc; ++j)
                {
                    runners_up->add(i, static_cast<std::size_t>(j), std::abs(s_row[j]));
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
        if (s >= similarity_min &&
            (!runners_up ||
             runners_up->clear(static_cast<std::size_t>(i), static_cast<std::size_t>(j), s)))
        {
            out.push_back({static_cast<int>(i), j, std::min(s, 1.0f)});
        }
    }
    return out;
}

MatchList matchMutualGuided(
    const Descriptors& prev,
    const Descriptors& cur,
    const std::vector<cv::Point2f>& predicted,
    const FeatureList& cur_features,
    float radius_px,
    float similarity_min,
    const Distinctiveness& distinct)
{
    MatchList out;
    const std::size_t np = prev.size(), nc = cur.size();
    ASSERT_EQUAL_(predicted.size(), np);
    ASSERT_EQUAL_(cur_features.size(), nc);
    if (np == 0 || nc == 0 || !(radius_px > 0))
    {
        return out;
    }
    ASSERT_EQUAL_(prev.dim, cur.dim);
    checkDistinctiveness(distinct, np, nc);

    const FeatureGrid grid(cur_features, radius_px);
    BestPartners bests(np, nc);
    forEachGuidedCandidate(
        prev, cur, predicted, grid, radius_px,
        [&](std::size_t i, std::size_t j, float s) { bests.add(i, j, s); });
    std::optional<RunnersUp> runners_up;
    if (distinct.enabled())
    {
        runners_up.emplace(distinct, bests.best_cur, bests.best_prev);
        forEachGuidedCandidate(
            prev, cur, predicted, grid, radius_px,
            [&](std::size_t i, std::size_t j, float s) { runners_up->add(i, j, s); });
    }
    for (std::size_t i = 0; i < np; ++i)
    {
        const int j = bests.best_cur[i];
        const float s = bests.best_cur_s[i];
        if (j >= 0 && bests.best_prev[static_cast<std::size_t>(j)] == static_cast<int>(i) &&
            s >= similarity_min &&
            (!runners_up || runners_up->clear(i, static_cast<std::size_t>(j), s)))
        {
            out.push_back({static_cast<int>(i), j, std::min(s, 1.0f)});
        }
    }
    return out;
}

}  // namespace emslam::egomotion
