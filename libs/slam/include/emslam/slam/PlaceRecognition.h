// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/egomotion/EgomotionEstimator.h>

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace emslam::slam
{
/** Which earlier places a keyframe looks like, whatever the poses say: an
 * inverted index over the descriptors a keyframe keeps for registering it
 * again (EgomotionEstimator::compact()).
 *
 * Why this signature: the kept descriptors are what a registration matches
 * (their correlation, Pearson's rho, is a dot product), so a place that
 * shares many of them with the keyframe is one the egomotion can register
 * it against; no vocabulary has to be learnt beforehand from another world.
 * Each descriptor is hashed into words by the signs of its dot products with
 * fixed pseudo-random ±1 directions (random-hyperplane hashing: two
 * descriptors of correlation rho agree on each sign with probability
 * 1 - acos(rho)/π), in several independent tables; a word shared by a
 * query feature and a place votes for that place, weighted by how rare the
 * word is (its inverse document frequency).
 *
 * Cost: each word remembers only its most recent places (MAX_POSTING), so a
 * query visits at most features × tables × MAX_POSTING entries however long
 * the run; memory is a few kB per place. A word seen in more places than
 * that is common, and votes little anyway.
 * \ingroup emslam_slam_grp \sa LoopCloser */
class PlaceRecognition
{
public:
    /** Bits of a word (2^WORD_BITS words per table). */
    static constexpr int WORD_BITS = 16;
    /** Independent hash tables: more find more of the shared descriptors. */
    static constexpr int TABLES = 4;
    /** Places remembered per word, the most recent. */
    static constexpr std::size_t MAX_POSTING = 64;

    /** A place and how much it looks like the query. */
    struct Match
    {
        std::size_t place{0};
        double score{0};  //!< sum of the shared words' weights
    };

    /** A description's words, TABLES per feature (each tagged by its
     * table), each once: hashed once per keyframe for query() and add(). */
    using Words = std::vector<std::uint32_t>;
    Words wordsOf(const emslam::egomotion::EgomotionEstimator::CompactDescription& c) const;

    /** Adds a place (numbers increasing: the keyframe's index). A
     * description without features adds nothing. */
    void add(std::size_t place, const Words& words);
    void add(std::size_t place, const emslam::egomotion::EgomotionEstimator::CompactDescription& c)
    {
        add(place, wordsOf(c));
    }
    /** The `count` places numbered below `before` that look most like `c`,
     * best first (only places that share a word with it). */
    std::vector<Match> query(const Words& words, std::size_t before, std::size_t count) const;
    std::vector<Match> query(
        const emslam::egomotion::EgomotionEstimator::CompactDescription& c,
        std::size_t before,
        std::size_t count) const
    {
        return query(wordsOf(c), before, count);
    }

    /** Places added. */
    std::size_t size() const { return m_places; }
    /** Memory of the index [bytes], approximately. */
    std::size_t bytes() const;
    /** Index entries the last query visited. */
    std::size_t lastVisited() const { return m_last_visited; }

private:
    struct Posting
    {
        std::vector<std::uint32_t> places;  //!< ring of the most recent
        std::size_t next{0};                //!< where the ring writes next
        std::size_t seen{0};                //!< places ever added (for the weight)
    };
    const std::vector<std::int8_t>& directions(int dim) const;

    std::unordered_map<std::uint32_t, Posting> m_postings;
    std::size_t m_places{0};
    std::size_t m_bytes{0};                         // postings and their hash nodes
    mutable std::vector<std::int8_t> m_directions;  // TABLES * WORD_BITS rows of ±1, for m_dim
    mutable int m_dim{0};
    mutable std::size_t m_last_visited{0};
};

}  // namespace emslam::slam
