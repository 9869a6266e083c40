// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/slam/PlaceRecognition.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace emslam::slam
{
namespace
{
/** The seed of the hashing directions: fixed, so that every run and every
 * platform hashes alike (std::mt19937's sequence is specified). */
constexpr std::uint32_t DIRECTIONS_SEED = 0x5eedu;
}  // namespace

const std::vector<std::int8_t>& PlaceRecognition::directions(int dim) const
{
    if (dim != m_dim)
    {
        std::mt19937 bits(DIRECTIONS_SEED);
        m_directions.resize(static_cast<std::size_t>(TABLES * WORD_BITS * dim));
        for (auto& v : m_directions)
        {
            v = (bits() & 1u) != 0 ? std::int8_t{1} : std::int8_t{-1};
        }
        m_dim = dim;
    }
    return m_directions;
}

PlaceRecognition::Words PlaceRecognition::wordsOf(
    const emslam::egomotion::EgomotionEstimator::CompactDescription& c) const
{
    std::vector<std::uint32_t> words;
    if (c.dim <= 0)
    {
        return words;
    }
    const auto dim = static_cast<std::size_t>(c.dim);
    const std::size_t n = c.codes.size() / dim;
    const auto& d = directions(c.dim);
    words.reserve(n * TABLES);
    for (std::size_t f = 0; f < n; ++f)
    {
        const std::int8_t* code = c.codes.data() + f * dim;
        if (std::all_of(code, code + dim, [](std::int8_t v) { return v == 0; }))
        {
            continue;  // a flat window: it looks like nothing
        }
        for (int t = 0; t < TABLES; ++t)
        {
            std::uint32_t word = static_cast<std::uint32_t>(t) << WORD_BITS;
            for (int b = 0; b < WORD_BITS; ++b)
            {
                // The codes' common scale does not change the sign.
                const std::int8_t* dir =
                    d.data() + static_cast<std::size_t>(t * WORD_BITS + b) * dim;
                int dot = 0;
                for (std::size_t k = 0; k < dim; ++k)
                {
                    dot += dir[k] * code[k];
                }
                word |= (dot > 0 ? 1u : 0u) << b;
            }
            words.push_back(word);
        }
    }
    // A place holds a word once: repeated texture does not vote twice.
    std::sort(words.begin(), words.end());
    words.erase(std::unique(words.begin(), words.end()), words.end());
    return words;
}

void PlaceRecognition::add(std::size_t place, const Words& words)
{
    if (words.empty())
    {
        return;
    }
    for (std::uint32_t w : words)
    {
        Posting& p = m_postings[w];
        if (p.places.empty())
        {
            m_bytes += sizeof(w) + sizeof(Posting) + 2 * sizeof(void*);  // a hash node
        }
        if (p.places.size() < MAX_POSTING)
        {
            m_bytes += sizeof(std::uint32_t);
            p.places.push_back(static_cast<std::uint32_t>(place));
        }
        else
        {
            p.places[p.next] = static_cast<std::uint32_t>(place);
            p.next = (p.next + 1) % MAX_POSTING;
        }
        ++p.seen;
    }
    ++m_places;
}

std::vector<PlaceRecognition::Match> PlaceRecognition::query(
    const Words& words, std::size_t before, std::size_t count) const
{
    m_last_visited = 0;
    std::unordered_map<std::size_t, double> votes;
    for (std::uint32_t w : words)
    {
        const auto it = m_postings.find(w);
        if (it == m_postings.end())
        {
            continue;
        }
        const Posting& p = it->second;
        // Inverse document frequency: a word every place has says nothing.
        const double weight = std::log(
            static_cast<double>(m_places + 1) /
            static_cast<double>(std::max<std::size_t>(p.seen, 1)));
        m_last_visited += p.places.size();
        if (weight <= 0)
        {
            continue;
        }
        for (std::uint32_t place : p.places)
        {
            if (place < before)
            {
                votes[place] += weight;
            }
        }
    }
    std::vector<Match> ranked;
    ranked.reserve(votes.size());
    for (const auto& [place, score] : votes)
    {
        ranked.push_back({place, score});
    }
    const auto better = [](const Match& a, const Match& b)
    { return a.score > b.score || (a.score == b.score && a.place < b.place); };
    if (ranked.size() > count)
    {
        std::partial_sort(
            ranked.begin(), ranked.begin() + static_cast<long>(count), ranked.end(), better);
        ranked.resize(count);
    }
    else
    {
        std::sort(ranked.begin(), ranked.end(), better);
    }
    return ranked;
}

std::size_t PlaceRecognition::bytes() const
{
    return m_bytes + m_directions.size();
}

}  // namespace emslam::slam
