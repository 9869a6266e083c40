// SPDX-License-Identifier: BSD-3-Clause
// io::FrameStreamGuard: which frames are skipped, why (exact warnings), how
// many, and what the end of a run says about a camera change.
#include "SyntheticStereo.h"

#include <emslam/io/FrameStreamGuard.h>

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationStereoImages.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

using emslam::io::FrameStreamGuard;
using Verdict = FrameStreamGuard::Verdict;

namespace
{
FrameStreamGuard::Camera camera(std::uint32_t w, std::uint32_t h, double f, double baseline)
{
    FrameStreamGuard::Camera c;
    c.width = w;
    c.height = h;
    c.fx = c.fy = c.right_fx = c.right_fy = f;
    c.cx = c.right_cx = w / 2.0;
    c.cy = c.right_cy = h / 2.0;
    c.baseline = baseline;
    return c;
}

const FrameStreamGuard::Camera SMALL = camera(320, 240, 200, 0.1);
const FrameStreamGuard::Camera LARGE = camera(640, 480, 400, 0.1);

/** Feeds (stamp, camera) frames from record 0 on, accepting every one the
 * guard lets through; returns the warnings, "" for a frame used. */
std::vector<std::string> feed(
    FrameStreamGuard& g, const std::vector<std::pair<double, FrameStreamGuard::Camera>>& frames)
{
    std::vector<std::string> out;
    for (std::size_t i = 0; i < frames.size(); ++i)
    {
        const auto d = g.check(frames[i].first, frames[i].second, i);
        if (d.verdict == Verdict::Use)
        {
            g.accept();
        }
        out.push_back(d.verdict == Verdict::Use ? "" : d.warning);
    }
    return out;
}

mrpt::obs::CObservationStereoImages::Ptr stereoObservation(int w, int h, double stamp)
{
    auto o = mrpt::obs::CObservationStereoImages::Create();
    o->timestamp = mrpt::Clock::fromDouble(stamp);
    o->imageLeft = mrpt::img::CImage(w, h, mrpt::img::CH_GRAY);
    o->imageRight = mrpt::img::CImage(w, h, mrpt::img::CH_GRAY);
    o->hasImageRight = true;
    o->setStereoCameraParams(emslam::test::idealStereoCamera(w, h, w * 0.625, 0.1));
    return o;
}
}  // namespace

TEST(FrameStreamGuard, badAndOutOfOrderStampsAreSkippedWithTheirReason)
{
    FrameStreamGuard g;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const auto w = feed(
        g, {{1700000000.0, SMALL},
            {1700000000.2, SMALL},
            {1700000000.2, SMALL},  // duplicated
            {1699999999.2, SMALL},  // 1 s back
            {nan, SMALL},
            {1e300, SMALL},
            {0.0, SMALL},
            {1700000000.4, SMALL}});
    const std::vector<std::string> expected = {
        "",
        "",
        "skipping frame at record 2: its timestamp 1700000000.200000000 is the same as record 1's "
        "(the last frame used)",
        "skipping frame at record 3: its timestamp 1699999999.200000000 is 1 s before record 1's "
        "(the last frame used)",
        "skipping frame at record 4: its timestamp nan is not finite",
        "skipping frame at record 5: its timestamp 1e+300 s is after 2100",
        "skipping frame at record 6: its timestamp 0 s is not after 1970-01-01 (further ones are "
        "only counted)",
        ""};
    EXPECT_EQ(w, expected);
    EXPECT_EQ(g.counts().bad_stamps, 5U);
    EXPECT_EQ(g.counts().camera_changes, 0U);
    EXPECT_EQ(g.counts().total(), 5U);
    EXPECT_EQ(g.accepted(), 3U);
    ASSERT_EQ(g.namedSkips().size(), 5U);
    EXPECT_EQ(g.namedSkips()[0].rfind("record 2: its timestamp", 0), 0U);
    EXPECT_EQ(g.skippedText(), "5 frames skipped (5 with a bad timestamp)");
    EXPECT_EQ(g.cameraChangeWarning(), "");
}

TEST(FrameStreamGuard, invalidStampReasons)
{
    EXPECT_EQ(FrameStreamGuard::invalidStampReason(1700000000.0), "");
    EXPECT_EQ(FrameStreamGuard::invalidStampReason(1e-3), "");
    EXPECT_EQ(
        FrameStreamGuard::invalidStampReason(-std::numeric_limits<double>::infinity()),
        "its timestamp -inf is not finite");
    EXPECT_EQ(
        FrameStreamGuard::invalidStampReason(0.0), "its timestamp 0 s is not after 1970-01-01");
    EXPECT_EQ(
        FrameStreamGuard::invalidStampReason(-1.5), "its timestamp -1.5 s is not after 1970-01-01");
    EXPECT_EQ(
        FrameStreamGuard::invalidStampReason(4102444800.0),
        "its timestamp 4102444800 s is after 2100");
}

TEST(FrameStreamGuard, unsetStampOfAnObservationIsNamed)
{
    FrameStreamGuard g;
    auto o = stereoObservation(64, 48, 1700000000.0);
    EXPECT_EQ(g.check(*o, 0).verdict, Verdict::Use);
    g.accept();
    o->timestamp = INVALID_TIMESTAMP;
    const auto d = g.check(*o, 1);
    EXPECT_EQ(d.verdict, Verdict::Skip);
    EXPECT_EQ(
        d.warning, "skipping frame at record 1: its timestamp is INVALID_TIMESTAMP (never set)");
    // What Clock::fromDouble(NaN) stores on x86-64: year 31198.
    o->timestamp = mrpt::Clock::time_point(
        mrpt::Clock::duration(std::numeric_limits<std::int64_t>::min() + 116444736000000000LL));
    EXPECT_EQ(
        g.check(*o, 2).warning,
        "skipping frame at record 2: its timestamp 9.223372037e+11 s is after 2100");
    EXPECT_EQ(g.counts().bad_stamps, 2U);
}

TEST(FrameStreamGuard, cameraChangedForGoodIsReportedOnce)
{
    FrameStreamGuard g;
    std::vector<std::pair<double, FrameStreamGuard::Camera>> frames;
    for (int i = 0; i < 10; ++i)
    {
        frames.push_back({1700000000.0 + i, i < 4 ? SMALL : LARGE});
    }
    const auto w = feed(g, frames);
    EXPECT_EQ(w[3], "");
    EXPECT_EQ(
        w[4],
        "skipping frame at record 4: its camera 640x480 (fx 400, fy 400, cx 320, cy 240, baseline "
        "0.1 m) differs from the session's 320x240 (fx 200, fy 200, cx 160, cy 120, baseline 0.1 "
        "m)");
    EXPECT_NE(w[8].find("(further ones are only counted)"), std::string::npos) << w[8];
    EXPECT_EQ(w[9], "");
    EXPECT_EQ(g.counts().camera_changes, 6U);
    EXPECT_EQ(g.accepted(), 4U);
    ASSERT_TRUE(g.cameraChange());
    EXPECT_TRUE(g.cameraChange()->for_good);
    EXPECT_EQ(g.cameraChange()->record, 4U);
    EXPECT_EQ(g.cameraChange()->runs, 1U);
    EXPECT_EQ(
        g.cameraChangeWarning(),
        "6 frames skipped: camera changed from 320x240 (fx 200, fy 200, cx 160, cy 120, baseline "
        "0.1 m) to 640x480 (fx 400, fy 400, cx 320, cy 240, baseline 0.1 m) at record 4; only the "
        "4 frames before it were used");
    EXPECT_EQ(g.skippedText(), "6 frames skipped (6 with another camera)");
}

TEST(FrameStreamGuard, interleavedCamerasAreSkippedAndReportedAsSuch)
{
    FrameStreamGuard g;
    auto wide = SMALL;
    wide.baseline = 0.12;  // the same images, another rig
    const auto w = feed(
        g, {{1.0, SMALL},
            {2.0, LARGE},
            {3.0, SMALL},
            {4.0, wide},
            {5.0, LARGE},
            {6.0, SMALL},
            {6.0, SMALL}});
    EXPECT_EQ(g.accepted(), 3U);
    EXPECT_EQ(g.counts().camera_changes, 3U);
    EXPECT_EQ(g.counts().bad_stamps, 1U);
    EXPECT_NE(w[3].find("baseline 0.12 m) differs"), std::string::npos) << w[3];
    ASSERT_TRUE(g.cameraChange());
    EXPECT_FALSE(g.cameraChange()->for_good);
    EXPECT_EQ(g.cameraChange()->runs, 2U);
    EXPECT_EQ(
        g.cameraChangeWarning(),
        "3 frames skipped: their camera differed from the session's 320x240 (fx 200, fy 200, cx "
        "160, cy 120, baseline 0.1 m) in 2 runs (the first at record 1: 640x480 (fx 400, fy 400, "
        "cx 320, cy 240, baseline 0.1 m)); the frames with the session's camera were used");
    EXPECT_EQ(g.skippedText(), "4 frames skipped (1 with a bad timestamp, 3 with another camera)");
}

// A frame the app could not use changes nothing: neither the stamp to pass
// nor the session's camera.
TEST(FrameStreamGuard, unusableFrameIsCountedAndChangesNothing)
{
    FrameStreamGuard g;
    ASSERT_EQ(g.check(10.0, LARGE, 0).verdict, Verdict::Use);
    EXPECT_EQ(
        g.skipUnusable(0, "left image is 640x480 but right image is 160x120"),
        "skipping unusable observation at record 0: left image is 640x480 but right image is "
        "160x120");
    EXPECT_FALSE(g.sessionCamera());
    g.accept();  // nothing pending: no effect
    EXPECT_EQ(g.accepted(), 0U);
    ASSERT_EQ(g.check(10.0, SMALL, 1).verdict, Verdict::Use);
    g.accept();
    ASSERT_TRUE(g.sessionCamera());
    EXPECT_TRUE(g.sessionCamera()->sameAs(SMALL));
    // A frame without a usable camera (the front-end will say why) passes on its stamp.
    EXPECT_EQ(g.check(11.0, std::nullopt, 2).verdict, Verdict::Use);
    EXPECT_EQ(
        g.skipUnusable(2, "no calibration"),
        "skipping unusable observation at record 2: no calibration");
    EXPECT_EQ(g.check(11.0, SMALL, 3).verdict, Verdict::Use);
    EXPECT_EQ(g.counts().unusable, 2U);
    EXPECT_EQ(
        g.namedSkips(), (std::vector<std::string>{
                            "record 0: left image is 640x480 but right image is 160x120",
                            "record 2: no calibration"}));
    EXPECT_EQ(g.skippedText(), "2 frames skipped (2 unusable)");
}

TEST(FrameStreamGuard, otherObservationsAreNoFrames)
{
    FrameStreamGuard g;
    mrpt::obs::CObservationOdometry odo;
    odo.timestamp = INVALID_TIMESTAMP;
    EXPECT_EQ(g.check(odo, 0).verdict, Verdict::NotAFrame);
    EXPECT_EQ(g.counts().total(), 0U);
}

TEST(FrameStreamGuard, cameraOfObservations)
{
    const auto o = stereoObservation(64, 48, 1700000000.0);
    const auto c = FrameStreamGuard::cameraOf(*o);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->toString(), "64x48 (fx 40, fy 40, cx 31.5, cy 23.5, baseline 0.1 m)");
    // A calibration that does not fit the images is no camera to compare.
    o->rightCamera.ncols = o->leftCamera.ncols = 320;
    EXPECT_FALSE(FrameStreamGuard::cameraOf(*o));
    o->hasImageRight = false;
    EXPECT_FALSE(FrameStreamGuard::cameraOf(*o));

    mrpt::obs::CObservation3DRangeScan r;
    r.hasIntensityImage = true;
    r.intensityImage = mrpt::img::CImage(64, 48, mrpt::img::CH_GRAY);
    r.cameraParamsIntensity.setIntrinsicParamsFromValues(40, 40, 32, 24);
    r.cameraParams.setIntrinsicParamsFromValues(50, 50, 32, 24);
    const auto rc = FrameStreamGuard::cameraOf(r);
    ASSERT_TRUE(rc);
    EXPECT_EQ(
        rc->toString(), "64x48 (fx 40, fy 40, cx 32, cy 24; depth fx 50, fy 50, cx 32, cy 24)");
    EXPECT_FALSE(rc->sameAs(*c));
}
