// SPDX-License-Identifier: BSD-3-Clause
// associateByTimestamp(): the greedy one-to-one pairing of TUM's associate.py
// (all pairs within max_dt, taken by increasing |dt|), computed lazily so that
// memory stays linear even when thousands of poses share one timestamp.
#include <emslam/apps/TrajectoryMetrics.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <queue>
#include <tuple>
#include <vector>

namespace emslam::apps
{
namespace
{
/** The free ranks of a sorted list, with "nearest free rank at or after / at
 * or before r" queries (union-find with path halving, no recursion). */
class FreeRanks
{
public:
    explicit FreeRanks(std::size_t n) : m_after(n + 1), m_before(n + 1)
    {
        std::iota(m_after.begin(), m_after.end(), std::size_t{0});
        std::iota(m_before.begin(), m_before.end(), std::size_t{0});
    }

    /** Smallest free rank >= r; size() if none. */
    std::size_t firstFreeFrom(std::size_t r) { return find(m_after, r); }

    /** Largest free rank <= r, as r + 1 (0 if none: keeps the index unsigned). */
    std::size_t lastFreeUpToPlusOne(std::size_t r_plus_one) { return find(m_before, r_plus_one); }

    bool isFree(std::size_t r) const { return m_after[r] == r; }

    void take(std::size_t r)
    {
        m_after[r] = r + 1;
        m_before[r + 1] = r;
    }

    std::size_t size() const { return m_after.size() - 1; }

private:
    static std::size_t find(std::vector<std::size_t>& parent, std::size_t i)
    {
        while (parent[i] != i)
        {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        return i;
    }

    std::vector<std::size_t> m_after, m_before;
};

constexpr std::size_t NONE = static_cast<std::size_t>(-1);

/** The first index in [0, n) where the monotone predicate `is_after` holds; n if none. */
template <typename Pred>
std::size_t firstRankWhere(std::size_t n, Pred&& is_after)
{
    std::size_t a = 0, b = n;
    while (a < b)
    {
        const std::size_t m = a + (b - a) / 2;
        if (is_after(m))
        {
            b = m;
        }
        else
        {
            a = m + 1;
        }
    }
    return a;
}

}  // namespace

AssociatedPoses associateByTimestamp(
    const emslam::stereo::TumTrajectory& gt,
    const emslam::stereo::TumTrajectory& est,
    double max_dt)
{
    AssociatedPoses out;
    if (!(max_dt >= 0.0))
    {
        return out;  // no pair is within a negative (or NaN) max_dt
    }
    // Ground truth in time order; "rank" indexes this order (stable: equal
    // stamps keep file order, as the candidate order of associate.py).
    std::vector<std::size_t> og(gt.size());
    std::iota(og.begin(), og.end(), std::size_t{0});
    std::stable_sort(
        og.begin(), og.end(),
        [&](std::size_t a, std::size_t b) { return gt.poses[a].t < gt.poses[b].t; });
    const auto tg = [&](std::size_t r) { return gt.poses[og[r]].t; };

    // Estimated poses with one timestamp share every candidate: they form a
    // group whose members are used in file order (the tie order of the sort
    // by |dt| over all pairs). Groups keep the work linear in such runs.
    std::vector<std::size_t> oe(est.size());
    std::iota(oe.begin(), oe.end(), std::size_t{0});
    std::stable_sort(
        oe.begin(), oe.end(),
        [&](std::size_t a, std::size_t b) { return est.poses[a].t < est.poses[b].t; });
    struct Group
    {
        double t{0};
        std::size_t first{0}, end{0};      // members: oe[first, end), next free one at `first`
        std::size_t lo{0}, mid{0}, hi{0};  // candidate ranks [lo, hi); [mid, hi) at or after t
        std::size_t right{NONE};           // head of the later candidates
        std::size_t left{NONE}, left_group_begin{0}, left_group_last{0};  // head of the earlier
    };
    std::vector<Group> groups;
    for (std::size_t i = 0; i < oe.size();)
    {
        Group g;
        g.t = est.poses[oe[i]].t;
        g.first = i;
        while (i < oe.size() && est.poses[oe[i]].t == g.t)
        {
            ++i;
        }
        g.end = i;
        // The same window tests as a scan of all pairs: t_gt >= t - max_dt, t_gt <= t + max_dt.
        g.lo = firstRankWhere(og.size(), [&](std::size_t r) { return !(tg(r) < g.t - max_dt); });
        g.mid =
            std::max(g.lo, firstRankWhere(og.size(), [&](std::size_t r) { return tg(r) >= g.t; }));
        g.hi = std::max(
            g.mid,
            firstRankWhere(og.size(), [&](std::size_t r) { return !(tg(r) <= g.t + max_dt); }));
        groups.push_back(g);
    }

    FreeRanks free_gt(og.size());
    const auto dtOf = [&](const Group& g, std::size_t r) { return std::abs(tg(r) - g.t); };

    // Later candidates come in rank order (|dt| grows with the rank).
    const auto advanceRightFrom = [&](Group& g, std::size_t from)
    {
        const std::size_t r = free_gt.firstFreeFrom(from);
        g.right = r < g.hi ? r : NONE;
    };
    // Earlier candidates: |dt| shrinks with the rank, so they come from the
    // latest one back, but ranks with equal |dt| in increasing rank order.
    const auto enterLeftGroupAtOrBefore = [&](Group& g, std::size_t r_plus_one)
    {
        const std::size_t c1 = r_plus_one == 0 ? 0 : free_gt.lastFreeUpToPlusOne(r_plus_one);
        if (c1 == 0 || c1 - 1 < g.lo)
        {
            g.left = NONE;
            return;
        }
        const std::size_t c = c1 - 1;
        const double d = dtOf(g, c);
        // Ranks before c have |dt| >= d: find where |dt| == d starts.
        g.left_group_begin =
            g.lo + firstRankWhere(c - g.lo, [&](std::size_t i) { return dtOf(g, g.lo + i) <= d; });
        g.left_group_last = c;
        g.left = free_gt.firstFreeFrom(g.left_group_begin);
    };
    const auto advanceLeft = [&](Group& g)
    {
        const std::size_t r = free_gt.firstFreeFrom(g.left);
        if (r <= g.left_group_last)
        {
            g.left = r;
            return;
        }
        enterLeftGroupAtOrBefore(g, g.left_group_begin);
    };

    // Queue of (|dt|, est index, gt rank, group, side): the lexicographic order
    // of the sort of all pairs. Each group has at most one entry per side.
    using Entry = std::tuple<double, std::size_t, std::size_t, std::size_t, bool>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    const auto push = [&](std::size_t gi, bool right)
    {
        const Group& g = groups[gi];
        const std::size_t r = right ? g.right : g.left;
        if (r != NONE && g.first < g.end)
        {
            queue.emplace(dtOf(g, r), oe[g.first], r, gi, right);
        }
    };
    for (std::size_t gi = 0; gi < groups.size(); ++gi)
    {
        advanceRightFrom(groups[gi], groups[gi].mid);
        enterLeftGroupAtOrBefore(groups[gi], groups[gi].mid);  // the rank before mid, plus one
        push(gi, true);
        push(gi, false);
    }

    std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (est index, gt index)
    while (!queue.empty())
    {
        const std::size_t e = std::get<1>(queue.top());
        const std::size_t r = std::get<2>(queue.top());
        const std::size_t gi = std::get<3>(queue.top());
        const bool right = std::get<4>(queue.top());
        queue.pop();
        Group& g = groups[gi];
        if (g.first == g.end)
        {
            continue;  // every member is paired
        }
        if (e != oe[g.first])
        {
            push(gi, right);  // its member was paired: same head, next member
            continue;
        }
        if (!free_gt.isFree(r))
        {
            if (right)
            {
                advanceRightFrom(g, r);
            }
            else
            {
                advanceLeft(g);
            }
            push(gi, right);
            continue;
        }
        pairs.emplace_back(e, og[r]);
        free_gt.take(r);
        ++g.first;
        if (g.first < g.end)
        {
            if (right)
            {
                advanceRightFrom(g, r);
            }
            else
            {
                advanceLeft(g);
            }
            push(gi, right);
        }
    }

    std::sort(
        pairs.begin(), pairs.end(),
        [&](const auto& a, const auto& b) { return est.poses[a.first].t < est.poses[b.first].t; });
    for (const auto& [e, g] : pairs)
    {
        out.t_est.push_back(est.poses[e].t);
        out.est.push_back(est.poses[e].pose);
        out.t_gt.push_back(gt.poses[g].t);
        out.gt.push_back(gt.poses[g].pose);
    }
    return out;
}

}  // namespace emslam::apps
