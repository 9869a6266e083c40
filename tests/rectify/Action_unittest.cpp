// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/Action.h>

#include <mrpt/core/bits_math.h>
#include <mrpt/poses/Lie/SO.h>

#include <gtest/gtest.h>

using namespace emslam::rectify;
using mrpt::poses::CPose3D;

TEST(Action, perturbationAddsTranslationAndTurnsAboutTheEndCameraAxes)
{
    const CPose3D a(1.0, 2.0, 3.0, mrpt::DEG2RAD(30.0), mrpt::DEG2RAD(-10.0), mrpt::DEG2RAD(5.0));
    const ActionDelta d{0.01, -0.02, 0.03, 0.0, mrpt::DEG2RAD(2.0), 0.0};
    const CPose3D p = perturbAction(a, d);
    EXPECT_NEAR(p.x(), 1.01, 1e-12);
    EXPECT_NEAR(p.y(), 1.98, 1e-12);
    EXPECT_NEAR(p.z(), 3.03, 1e-12);
    // R_a^T R_p is a 2° turn about y.
    const auto Ra = a.getRotationMatrix();
    const auto Rp = p.getRotationMatrix();
    mrpt::math::CMatrixDouble33 D;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            D(r, c) = Ra(0, r) * Rp(0, c) + Ra(1, r) * Rp(1, c) + Ra(2, r) * Rp(2, c);
    const auto log = mrpt::poses::Lie::SO<3>::log(D);
    EXPECT_NEAR(log[0], 0.0, 1e-12);
    EXPECT_NEAR(log[1], mrpt::DEG2RAD(2.0), 1e-12);
    EXPECT_NEAR(log[2], 0.0, 1e-12);
}

TEST(Action, planarProjectionKeepsXZAndTheTurnAboutY)
{
    // Pure rotation about y of 170°: no Euler-angle singularity.
    mrpt::math::CVectorFixedDouble<3> w;
    w[0] = 0;
    w[1] = mrpt::DEG2RAD(170.0);
    w[2] = 0;
    mrpt::math::CVectorFixedDouble<3> t;
    t[0] = 1.5;
    t[1] = 0.3;
    t[2] = -2.0;
    const CPose3D a = CPose3D::FromRotationAndTranslation(mrpt::poses::Lie::SO<3>::exp(w), t);
    const CPose3D p = planarAction(a);
    EXPECT_NEAR(p.x(), 1.5, 1e-12);
    EXPECT_NEAR(p.y(), 0.0, 1e-12);
    EXPECT_NEAR(p.z(), -2.0, 1e-12);
    EXPECT_NEAR(
        mrpt::poses::Lie::SO<3>::log(p.getRotationMatrix())[1], mrpt::DEG2RAD(170.0), 1e-12);
}

TEST(Action, rotationAngleIsTheAngleOfTheRotation)
{
    const mrpt::poses::CPose3D T(
        1.0, -2.0, 0.5, mrpt::DEG2RAD(20.0), mrpt::DEG2RAD(-10.0), mrpt::DEG2RAD(5.0));
    EXPECT_NEAR(
        emslam::rectify::rotationAngle(T),
        mrpt::poses::Lie::SO<3>::log(T.getRotationMatrix()).norm(), 1e-12);
    EXPECT_NEAR(
        emslam::rectify::rotationAngle(mrpt::poses::CPose3D(0, 0, 0, mrpt::DEG2RAD(179.0), 0, 0)),
        mrpt::DEG2RAD(179.0), 1e-12);
    // acos((trace - 1) / 2) would be off by ~1e-8 here.
    EXPECT_NEAR(
        emslam::rectify::rotationAngle(mrpt::poses::CPose3D(0, 0, 0, 1e-9, 0, 0)), 1e-9, 1e-15);
}

TEST(Action, actionsBetweenComposeBackToTheElementPoses)
{
    const std::vector<CPose3D> poses = {
        CPose3D(1, 2, 3, 0.1, 0.2, 0.3), CPose3D(2, 2, 4, 0.2, 0.1, 0.3),
        CPose3D(0, -1, 5, -0.4, 0.0, 0.1)};
    const auto a = actionsBetween(poses);
    ASSERT_EQ(a.size(), poses.size());
    CPose3D composed = a[0];  // a_0 is the first element's world pose
    EXPECT_NEAR(composed.distanceTo(poses[0]), 0.0, 1e-12);
    for (std::size_t i = 1; i < poses.size(); ++i)
    {
        composed = composed + a[i];
        EXPECT_NEAR(composed.distanceTo(poses[i]), 0.0, 1e-12);
        EXPECT_NEAR(rotationAngle(composed - poses[i]), 0.0, 1e-12);
    }
    EXPECT_TRUE(actionsBetween({}).empty());
}
