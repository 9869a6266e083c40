// SPDX-License-Identifier: BSD-3-Clause
#include "RaySearch.h"

#include "VoxelKey.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>
#include <utility>
#include <vector>

namespace emslam::slam
{
namespace
{
/** The search along a ray reaches ±this many σ. */
constexpr double RAY_SEARCH_SIGMAS = 2.0;
/** The width of the preference for nearer cells, in sigmas. */
constexpr double PREFERENCE_SIGMAS = 2.0;

/** The voxels met sampling the ray from `o` through `p` every half voxel
 * within ±`steps` samples, none behind the camera, into `samples` as (key,
 * k), t = k · half a voxel from p (a voxel met on consecutive samples counts
 * once), each one's slot in `voxels` asked of the cache ahead of its
 * lookup. */
void sampleRay(
    const mrpt::math::TPoint3Df& p,
    const mrpt::math::TPoint3D& o,
    int steps,
    double voxel_size,
    const VoxelTable& voxels,
    std::vector<std::pair<std::uint64_t, int>>& samples)
{
    samples.clear();
    const double step = 0.5 * voxel_size;
    double dx = p.x - o.x, dy = p.y - o.y, dz = p.z - o.z;
    const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (!(r > 1e-6))
    {
        return;
    }
    dx /= r;
    dy /= r;
    dz /= r;
    const double inv_voxel = 1.0 / voxel_size;
    std::uint64_t last = VoxelTable::EMPTY;
    for (int k = -steps; k <= steps; ++k)
    {
        const double t = k * step;
        if (t < -r)
        {
            continue;  // not behind the camera
        }
        const std::uint64_t key = voxelKey(p.x + t * dx, p.y + t * dy, p.z + t * dz, inv_voxel);
        if (key != last)
        {
            voxels.prefetch(key);
            samples.emplace_back(key, k);
            last = key;
        }
    }
}

/** The samples a point's search reaches on each side. */
double searchSteps(double sigma, double voxel_size)
{
    return std::ceil(RAY_SEARCH_SIGMAS * sigma / (0.5 * voxel_size));
}

/** The best voxel along one ray so far: the one with the most evidence,
 * nearer ones preferred softly (a Gaussian of PREFERENCE_SIGMAS σ) so that
 * ties stay near; the point's voxel now (`own`) is scored at t = 0, so that
 * ties stay put. */
class BestAlongRay
{
public:
    BestAlongRay(std::uint32_t own, double sigma, double voxel_size)
        : m_best(own),
          m_own(own),
          m_step(0.5 * voxel_size),
          m_inv_two_var(0.5 / (PREFERENCE_SIGMAS * PREFERENCE_SIGMAS * sigma * sigma))
    {
    }

    /** The voxel numbered `slot`, met at sample k, holding `weight`. */
    void consider(std::uint32_t slot, int k, double weight)
    {
        if (!(weight > 0) || !(weight > m_best_score))
        {
            return;  // empty, or cannot win: the preference is at most 1
        }
        const double t = slot == m_own ? 0.0 : k * m_step;
        const double score = t == 0.0 ? weight : weight * std::exp(-t * t * m_inv_two_var);
        if (score > m_best_score)
        {
            m_best_score = score;
            m_best = slot;
        }
    }

    std::uint32_t best() const { return m_best; }

private:
    std::uint32_t m_best, m_own;
    double m_step, m_inv_two_var;
    double m_best_score{-1.0};
};

/** The voxels holding points along the rays of a range of points, in the
 * order the search meets them, each packed as its slot in the table (24 bits)
 * and its sample k + 128 (8 bits): 4 bytes, as the hall's 8 laps hold 9 per
 * point. A point whose search reaches beyond MAX_STEPS samples on a side (σ
 * above 31 voxels), or all of them in a table beyond 2^24 slots, is marked
 * WALKS and searches its ray again in each pass. The words are kept in chunks (a point's in one),
 * so that growing never holds two copies. */
class RayCandidates
{
public:
    /** Samples on each side a recorded search reaches at most: k + 128 fits
     * 8 bits, and a point's at most 2 · 126 + 1 words never count WALKS. */
    static constexpr int MAX_STEPS = 126;
    static constexpr std::uint8_t WALKS = 255;

    explicit RayCandidates(std::size_t points) : m_count(points, 0) {}

    /** Before point `i`'s words: room for as many as a point can have. */
    void beginPoint()
    {
        if (m_chunks.empty() || m_chunks.back().size() + 255 > CHUNK)
        {
            m_chunks.emplace_back().reserve(CHUNK);
        }
    }
    void add(std::uint32_t slot, int k)
    {
        m_chunks.back().push_back((slot << 8) | static_cast<std::uint32_t>(k + 128));
    }
    void setCount(std::size_t i, std::uint8_t count) { m_count[i] = count; }
    std::uint8_t count(std::size_t i) const { return m_count[i]; }

    /** Replaces each word's slot s by id(s). */
    template <typename Id>
    void renumber(const Id& id)
    {
        for (auto& chunk : m_chunks)
        {
            for (auto& word : chunk)
            {
                word = (id(voxelOf(word)) << 8) | (word & 255);
            }
        }
    }

    /** A word's voxel: its table slot, or its dense number once renumbered. */
    static std::uint32_t voxelOf(std::uint32_t word) { return word >> 8; }
    static int stepOf(std::uint32_t word) { return static_cast<int>(word & 255) - 128; }

    /** The words of the points in order: next(count) gives a point's. */
    class Reader
    {
    public:
        explicit Reader(const RayCandidates& c) : m_c(c) {}
        const std::uint32_t* next(std::uint8_t count)
        {
            if (m_offset + count > m_c.m_chunks[m_chunk].size())
            {
                ++m_chunk;
                m_offset = 0;
            }
            const std::uint32_t* words = m_c.m_chunks[m_chunk].data() + m_offset;
            m_offset += count;
            return words;
        }

    private:
        const RayCandidates& m_c;
        std::size_t m_chunk{0}, m_offset{0};
    };

private:
    static constexpr std::size_t CHUNK = std::size_t{1} << 20;
    std::vector<std::uint8_t> m_count;  //!< per point of the range
    std::vector<std::vector<std::uint32_t>> m_chunks;
};

/** visit(range, begin, end) over [0, n) in contiguous ranges, one per
 * thread, on up to as many threads as the machine has cores (one below
 * 20,000 items: not worth a thread). The same n gives the same ranges. */
std::size_t rangesFor(std::size_t n)
{
    return n < 20000 ? 1 : std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, 8);
}

template <typename Visit>
void forEachRangeInParallel(std::size_t n, const Visit& visit)
{
    const std::size_t ranges = rangesFor(n);
    const auto run = [&](std::size_t t) { visit(t, n * t / ranges, n * (t + 1) / ranges); };
    std::vector<std::thread> workers;
    for (std::size_t t = 1; t < ranges; ++t)
    {
        workers.emplace_back(run, t);
    }
    run(0);
    for (auto& w : workers)
    {
        w.join();
    }
}

}  // namespace

void assignAlongRays(
    const RayPoints& rays, const VoxelTable& voxels, std::vector<std::uint32_t>& slot, int passes)
{
    const std::size_t n = rays.points.size();
    // A point only ever joins a voxel holding points, so the voxels holding
    // points at first hold every later assignment: each ray is searched once,
    // and the passes only weigh the voxels found on it (a hash lookup per
    // sample, mostly a cache miss, made the search 90 % of the fusion).
    const bool packable = voxels.capacity() <= (std::size_t{1} << 24);
    // A point within half a voxel of its depth has nowhere else to go.
    const auto searches = [&](std::size_t i)
    { return slot[i] != NO_VOXEL && rays.sigma[i] > 0.5 * rays.voxel_size; };
    const auto steps = [&](std::size_t i)
    { return static_cast<int>(searchSteps(rays.sigma[i], rays.voxel_size)); };
    const auto walks = [&](std::size_t i) {
        return !packable ||
               !(searchSteps(rays.sigma[i], rays.voxel_size) <= RayCandidates::MAX_STEPS);
    };
    using Samples = std::vector<std::pair<std::uint64_t, int>>;
    const auto sample = [&](std::size_t i, Samples& samples)
    {
        sampleRay(
            rays.points[i], rays.origins[rays.view[i]], steps(i), rays.voxel_size, voxels, samples);
    };

    std::vector<RayCandidates> candidates;
    for (std::size_t range = 0, ranges = rangesFor(n); range < ranges; ++range)
    {
        candidates.emplace_back(n * (range + 1) / ranges - n * range / ranges);
    }
    forEachRangeInParallel(
        n,
        [&](std::size_t range, std::size_t begin, std::size_t end)
        {
            RayCandidates& c = candidates[range];
            const auto record = [&](std::size_t i, const Samples& samples)
            {
                c.beginPoint();
                std::uint8_t count = 0;  // at most 2 · MAX_STEPS + 1 samples
                for (const auto& [key, k] : samples)
                {
                    if (const std::size_t s = voxels.slotOf(key); s != VoxelTable::NONE)
                    {
                        c.add(static_cast<std::uint32_t>(s), k);
                        ++count;
                    }
                }
                c.setCount(i - begin, count);
            };
            // One point ahead: its voxels are fetched while the last point's
            // are looked up.
            Samples ahead, now;
            std::size_t last = end;
            for (std::size_t i = begin; i < end; ++i)
            {
                if (!searches(i))
                {
                    continue;
                }
                if (walks(i))
                {
                    c.setCount(i - begin, RayCandidates::WALKS);
                    continue;
                }
                sample(i, ahead);
                if (last != end)
                {
                    record(last, now);
                }
                std::swap(ahead, now);
                last = i;
            }
            if (last != end)
            {
                record(last, now);
            }
        });

    // The voxels numbered densely in the order the rays meet them: the
    // passes' weights then fit the cache, and a ray's voxels sit together.
    std::vector<std::uint32_t> id_of(voxels.capacity(), NO_VOXEL);
    std::vector<std::uint32_t> slot_of_id;
    const auto id = [&](std::uint32_t s)
    {
        if (id_of[s] == NO_VOXEL)
        {
            id_of[s] = static_cast<std::uint32_t>(slot_of_id.size());
            slot_of_id.push_back(s);
        }
        return id_of[s];
    };
    for (auto& c : candidates)
    {
        c.renumber(id);
    }
    for (auto& s : slot)
    {
        s = s == NO_VOXEL ? NO_VOXEL : id(s);
    }

    std::vector<double> weight(slot_of_id.size());
    for (int pass = 0; pass < passes; ++pass)
    {
        // The evidence of the last assignment, summed in the points' order.
        std::fill(weight.begin(), weight.end(), 0.0);
        for (std::size_t i = 0; i < n; ++i)
        {
            if (slot[i] != NO_VOXEL)
            {
                weight[slot[i]] += inverseVariance(rays.sigma[i]);
            }
        }
        // Each point reads the evidence and writes its own voxel: the points
        // split between threads give the same result as one thread.
        forEachRangeInParallel(
            n,
            [&](std::size_t range, std::size_t begin, std::size_t end)
            {
                const RayCandidates& c = candidates[range];
                RayCandidates::Reader reader(c);
                Samples samples;
                for (std::size_t i = begin; i < end; ++i)
                {
                    if (!searches(i))
                    {
                        continue;
                    }
                    BestAlongRay best(slot[i], rays.sigma[i], rays.voxel_size);
                    const std::uint8_t count = c.count(i - begin);
                    if (count == RayCandidates::WALKS)
                    {
                        sample(i, samples);
                        for (const auto& [key, k] : samples)
                        {
                            // Every voxel holding points is some point's: numbered.
                            if (const std::size_t s = voxels.slotOf(key); s != VoxelTable::NONE)
                            {
                                best.consider(id_of[s], k, weight[id_of[s]]);
                            }
                        }
                    }
                    else
                    {
                        const std::uint32_t* words = reader.next(count);
                        for (std::uint8_t j = 0; j < count; ++j)
                        {
                            const std::uint32_t s = RayCandidates::voxelOf(words[j]);
                            best.consider(s, RayCandidates::stepOf(words[j]), weight[s]);
                        }
                    }
                    slot[i] = best.best();
                }
            });
    }
    for (auto& s : slot)
    {
        s = s == NO_VOXEL ? NO_VOXEL : slot_of_id[s];
    }
}

}  // namespace emslam::slam
