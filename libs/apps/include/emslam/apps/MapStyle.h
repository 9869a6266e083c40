// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/io/TumTrajectory.h>

#include <mrpt/img/TColor.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>

namespace emslam::apps
{
/** How one trajectory is drawn: its legend label and colour (RGB in [0,1]).
 * \ingroup emslam_apps_grp */
struct TrajectoryStyle
{
    const char* label;  //!< legend text
    /** Colour, RGB in [0, 1]. */
    ///@{
    float r, g, b;
    ///@}
};

/** The colours every map drawing shares (map.3Dscene, map_top.png, the live
 * viewer), so one legend reads them all. \ingroup emslam_apps_grp */
constexpr TrajectoryStyle EGOMOTION_STYLE{"egomotion", 0.9f, 0.1f, 0.1f};
constexpr TrajectoryStyle SLAM_STYLE{"SLAM (rectified)", 0.1f, 0.8f, 0.1f};
constexpr TrajectoryStyle GROUND_TRUTH_STYLE{"ground truth", 0.2f, 0.45f, 1.0f};
/** Loop closures: a segment between the two keyframes each one joins. */
constexpr TrajectoryStyle LOOP_STYLE{"loop closures", 1.0f, 0.55f, 0.0f};

/** Pose of the map (first camera) frame in the viewer frame of the drawings:
 * camera forward (+z) → viewer +X, right (+x) → −Y, down (+y) → −Z, so the
 * world's up (−y of the first camera) is the viewer's +Z.
 * \ingroup emslam_apps_grp */
mrpt::poses::CPose3D viewerFromCamera();

/** Height of a map point above the first camera [m]: up is −y. */
inline double heightAboveFirstCamera(const mrpt::math::TPoint3Df& p)
{
    return -static_cast<double>(p.y);
}

/** Colour of a height in [lo, hi] on the JET scale (blue low, red high);
 * values outside are clamped. \ingroup emslam_apps_grp */
mrpt::img::TColorf heightColor(double h, double lo, double hi);

/** The ground truth moved into the map frame, to draw it beside the
 * estimates: the rigid transform (Horn / Umeyama, positions paired by
 * timestamp within 0.05 s) that best lays the ground truth on `estimate`.
 * With fewer than 3 pairs the ground truth is anchored at its pose nearest
 * the estimate's first timestamp instead. Empty if either is empty.
 * \ingroup emslam_apps_grp */
emslam::io::TumTrajectory groundTruthInMapFrame(
    const emslam::io::TumTrajectory& ground_truth, const emslam::io::TumTrajectory& estimate);

}  // namespace emslam::apps
