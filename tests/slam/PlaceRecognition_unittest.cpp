// SPDX-License-Identifier: BSD-3-Clause
// Places described by the egomotion (textured planes), seen again shifted and
// with new photometric noise, among places never seen before.
#include "SyntheticStereo.h"

#include <emslam/egomotion/EgomotionEstimator.h>
#include <emslam/slam/PlaceRecognition.h>

#include <gtest/gtest.h>

#include <cstddef>
#include <opencv2/core.hpp>
#include <vector>

using emslam::egomotion::EgomotionEstimator;
using emslam::slam::PlaceRecognition;

namespace
{
constexpr int W = 160, H = 120;
constexpr std::size_t KEPT = 200;

/** What a keyframe keeps of a frame showing `img` (a tilted plane). */
EgomotionEstimator::CompactDescription keep(const cv::Mat& img)
{
    auto f = emslam::test::frameWithImage(img);
    for (std::size_t i = 0; i < f.points.size(); ++i)
    {
        f.points[i].z = 3.0f + 0.01f * f.pixels[i].u;
    }
    EgomotionEstimator e;
    e.process(f);
    return EgomotionEstimator::compact(e.lastDescription(), KEPT);
}

/** Texture `seed` seen again: shifted by (dx, dy) pixels, new sensor noise. */
cv::Mat seenAgain(unsigned seed, int dx, int dy)
{
    const cv::Mat img = emslam::test::noiseImage(W + 8, H + 8, seed);
    cv::Mat view = img(cv::Rect(4 + dx, 4 + dy, W, H)).clone();
    cv::Mat noise(view.size(), CV_16S);
    cv::theRNG().state = seed * 7919u + 1;
    cv::randn(noise, 0, 2.0);
    cv::Mat out;
    view.convertTo(out, CV_16S);
    out += noise;
    out.convertTo(out, view.type());
    return out;
}

cv::Mat firstSeen(unsigned seed)
{
    return emslam::test::noiseImage(W + 8, H + 8, seed)(cv::Rect(4, 4, W, H)).clone();
}
}  // namespace

TEST(PlaceRecognition, findsThePlaceSeenAgainFirst)
{
    constexpr unsigned PLACES = 30;
    PlaceRecognition index;
    for (unsigned k = 0; k < PLACES; ++k)
    {
        index.add(k, keep(firstSeen(100 + k)));
    }
    ASSERT_EQ(index.size(), PLACES);
    double worst_margin = 1e9;
    for (unsigned k = 0; k < PLACES; k += 3)
    {
        const auto c = keep(seenAgain(100 + k, 2, -1));
        const auto m = index.query(c, PLACES, 2);
        ASSERT_EQ(m.size(), 2u);
        EXPECT_EQ(m[0].place, k);
        worst_margin = std::min(worst_margin, m[0].score / m[1].score);
        // Bounded: never more than the capped postings of the query's words.
        EXPECT_LE(
            index.lastVisited(),
            c.features.size() * PlaceRecognition::TABLES * PlaceRecognition::MAX_POSTING);
    }
    // The place seen again stands out from the best of the others.
    EXPECT_GT(worst_margin, 3.0);
}

TEST(PlaceRecognition, aNewPlaceScoresFarBelowARevisit)
{
    PlaceRecognition index;
    for (unsigned k = 0; k < 20; ++k)
    {
        index.add(k, keep(firstSeen(200 + k)));
    }
    const auto revisit = index.query(keep(seenAgain(205, -2, 1)), 20, 1);
    const auto unseen = index.query(keep(firstSeen(999)), 20, 1);
    ASSERT_EQ(revisit.size(), 1u);
    EXPECT_EQ(revisit[0].place, 5u);
    const double unseen_best = unseen.empty() ? 0.0 : unseen[0].score;
    EXPECT_GT(revisit[0].score, 3 * unseen_best);
}

TEST(PlaceRecognition, onlyPlacesBeforeTheLimitAndNothingFromAnEmptyDescription)
{
    PlaceRecognition index;
    for (unsigned k = 0; k < 10; ++k)
    {
        index.add(k, keep(firstSeen(300 + k)));
    }
    index.add(10, EgomotionEstimator::CompactDescription{});
    EXPECT_EQ(index.size(), 10u);
    // Place 7 seen again, but only places 0-4 may answer.
    for (const auto& m : index.query(keep(seenAgain(307, 1, 1)), 5, 5))
    {
        EXPECT_LT(m.place, 5u);
    }
    EXPECT_TRUE(index.query(EgomotionEstimator::CompactDescription{}, 10, 3).empty());
    EXPECT_GT(index.bytes(), 0u);
}
