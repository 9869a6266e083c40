// SPDX-License-Identifier: BSD-3-Clause
// associateByTimestamp(): the greedy one-to-one pairing of TUM's associate.py
// (all pairs within max_dt, taken by increasing |dt|), computed over
// neighbouring clusters of equal stamps only, so that time and memory stay
// O(N log N) / O(N) even when thousands of poses share a stamp or a window.
#include <emslam/eval/TrajectoryMetrics.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <queue>
#include <tuple>
#include <vector>

namespace emslam::eval
{
namespace
{
constexpr std::size_t NONE = static_cast<std::size_t>(-1);

/** Poses of one file sharing one timestamp, a node of the time-ordered list
 * of both files' clusters. Its members are used in order: file order for an
 * estimate cluster, time rank (stable: file order) for a ground-truth one,
 * the tie order of associate.py's sort of all pairs. */
struct Cluster
{
    double t{0};
    bool is_gt{false};
    std::size_t head{0}, end{0};  //!< free members: order[head, end) of its file
    std::size_t prev{NONE}, next{NONE};
    bool alive() const { return head < end; }
};

/** Pose indices of a file in time order (stable: file order at one stamp). */
std::vector<std::size_t> timeOrder(const emslam::io::TumTrajectory& t)
{
    std::vector<std::size_t> order(t.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(
        order.begin(), order.end(),
        [&](std::size_t a, std::size_t b) { return t.poses[a].t < t.poses[b].t; });
    return order;
}

/** Both files' clusters in time order, linked; at one stamp the ground truth first. */
std::vector<Cluster> timeOrderedClusters(
    const emslam::io::TumTrajectory& gt,
    const std::vector<std::size_t>& og,
    const emslam::io::TumTrajectory& est,
    const std::vector<std::size_t>& oe)
{
    std::vector<Cluster> clusters;
    clusters.reserve(og.size() + oe.size());
    std::size_t ig = 0, ie = 0;
    while (ig < og.size() || ie < oe.size())
    {
        const bool take_gt =
            ie == oe.size() || (ig < og.size() && gt.poses[og[ig]].t <= est.poses[oe[ie]].t);
        const auto& order = take_gt ? og : oe;
        const auto& poses = take_gt ? gt.poses : est.poses;
        std::size_t& i = take_gt ? ig : ie;
        Cluster c;
        c.t = poses[order[i]].t;
        c.is_gt = take_gt;
        c.head = i;
        while (i < order.size() && poses[order[i]].t == c.t)
        {
            ++i;
        }
        c.end = i;
        c.prev = clusters.empty() ? NONE : clusters.size() - 1;
        if (!clusters.empty())
        {
            clusters.back().next = clusters.size();
        }
        clusters.push_back(c);
    }
    return clusters;
}

/** The greedy matching over neighbouring clusters: (estimate index,
 * ground-truth rank) pairs in the order associate.py takes them. */
class NeighbourMatcher
{
public:
    NeighbourMatcher(
        std::vector<Cluster> clusters, const std::vector<std::size_t>& oe, double max_dt)
        : m_clusters(std::move(clusters)), m_oe(oe), m_max_dt(max_dt)
    {
    }

    std::vector<std::pair<std::size_t, std::size_t>> match()
    {
        for (std::size_t c = 0; c + 1 < m_clusters.size(); ++c)
        {
            pushPair(c);
        }
        std::vector<std::pair<std::size_t, std::size_t>> pairs;
        while (!m_queue.empty())
        {
            const auto [dt, e, r, left] = m_queue.top();
            m_queue.pop();
            Cluster& a = m_clusters[left];
            if (!a.alive() || a.next == NONE)
            {
                continue;  // no longer a pair of neighbours: its successor was queued
            }
            Cluster& b = m_clusters[a.next];
            if (a.is_gt == b.is_gt)
            {
                continue;
            }
            Cluster& cg = a.is_gt ? a : b;
            Cluster& ce = a.is_gt ? b : a;
            if (m_oe[ce.head] != e || cg.head != r)
            {
                pushPair(left);  // a member was used by another pair: queue the next ones
                continue;
            }
            pairs.emplace_back(e, r);
            ++cg.head;
            ++ce.head;
            removeUsedUp(left);
        }
        return pairs;
    }

private:
    /** After a match of `left` and its right neighbour: clusters with no
     * free member leave the list, and the new neighbour pair is queued. */
    void removeUsedUp(std::size_t left)
    {
        Cluster& a = m_clusters[left];
        const std::size_t right = a.next;
        std::size_t before = a.prev;
        if (!m_clusters[right].alive())
        {
            unlink(right);
        }
        if (!a.alive())
        {
            before = unlink(left);
        }
        if (a.alive())
        {
            pushPair(left);  // the same neighbours, their next members
        }
        else
        {
            pushPair(before);  // new neighbours around the removed cluster(s)
        }
    }

    /** Queues the first free members of `left` and its right neighbour, if
     * they are of different files and within max_dt. */
    void pushPair(std::size_t left)
    {
        if (left == NONE || m_clusters[left].next == NONE)
        {
            return;
        }
        const Cluster& a = m_clusters[left];
        const Cluster& b = m_clusters[a.next];
        if (a.is_gt == b.is_gt)
        {
            return;
        }
        const Cluster& cg = a.is_gt ? a : b;
        const Cluster& ce = a.is_gt ? b : a;
        // The same window tests as a scan of all pairs.
        if (cg.t < ce.t - m_max_dt || !(cg.t <= ce.t + m_max_dt))
        {
            return;
        }
        m_queue.emplace(std::abs(cg.t - ce.t), m_oe[ce.head], cg.head, left);
    }

    /** Takes cluster c out of the list; returns its left neighbour. */
    std::size_t unlink(std::size_t c)
    {
        const std::size_t p = m_clusters[c].prev, n = m_clusters[c].next;
        if (p != NONE)
        {
            m_clusters[p].next = n;
        }
        if (n != NONE)
        {
            m_clusters[n].prev = p;
        }
        return p;
    }

    std::vector<Cluster> m_clusters;
    const std::vector<std::size_t>& m_oe;
    double m_max_dt;
    // (|dt|, estimate index, ground-truth rank, left cluster of the pair):
    // the order of associate.py's sort. Entries go stale when a cluster's
    // first member or neighbour changes; they are checked when popped.
    using Entry = std::tuple<double, std::size_t, std::size_t, std::size_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> m_queue;
};
}  // namespace

// Why adjacent clusters suffice: let (e, g) be the pair associate.py takes
// next (least |dt|, then estimate index, then ground-truth rank) among the
// free poses. A free cluster between theirs in time order would either lie
// strictly between (then it is nearer to one of them, of the other kind: a
// pair with smaller |dt|) or share a stamp with one of them (then it is the
// other file's cluster at that stamp, |dt| = 0, and the pair would be it).
// So the next pair always joins two clusters adjacent among the free ones,
// and their first free members. Each match removes at most two clusters and
// links one new neighbour pair: O((N + M) log(N + M)) time, O(N + M) memory,
// however many poses share a stamp or fall within max_dt of each other.
AssociatedPoses associateByTimestamp(
    const emslam::io::TumTrajectory& gt, const emslam::io::TumTrajectory& est, double max_dt)
{
    AssociatedPoses out;
    if (!(max_dt >= 0.0))
    {
        return out;  // no pair is within a negative (or NaN) max_dt
    }
    const std::vector<std::size_t> og = timeOrder(gt), oe = timeOrder(est);
    // (est index, gt rank) -> (est index, gt index)
    std::vector<std::pair<std::size_t, std::size_t>> pairs =
        NeighbourMatcher(timeOrderedClusters(gt, og, est, oe), oe, max_dt).match();
    for (auto& pr : pairs)
    {
        pr.second = og[pr.second];
    }
    std::sort(
        pairs.begin(), pairs.end(),
        [&](const auto& x, const auto& y)
        {
            return std::make_pair(est.poses[x.first].t, x.first) <
                   std::make_pair(est.poses[y.first].t, y.first);
        });
    out.t_est.reserve(pairs.size());
    out.est.reserve(pairs.size());
    out.t_gt.reserve(pairs.size());
    out.gt.reserve(pairs.size());
    for (const auto& [e, g] : pairs)
    {
        out.t_est.push_back(est.poses[e].t);
        out.est.push_back(est.poses[e].pose);
        out.t_gt.push_back(gt.poses[g].t);
        out.gt.push_back(gt.poses[g].pose);
    }
    return out;
}

}  // namespace emslam::eval
