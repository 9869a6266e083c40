// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/MapDrawingContent.h>

#include <mrpt/opengl/COpenGLScene.h>

#include <string>

namespace emslam::apps
{
/** @name Names of the objects of a map scene (COpenGLScene::getByName())
 * \ingroup emslam_apps_grp
 * @{ */
constexpr const char* MAP_CLOUD_NAME = "map cloud";
constexpr const char* EGOMOTION_NAME = "egomotion trajectory";
constexpr const char* SLAM_NAME = "SLAM trajectory";
constexpr const char* GROUND_TRUTH_NAME = "ground truth trajectory";
constexpr const char* LOOPS_NAME = "loop closures";
constexpr const char* LEGEND_NAME = "legend";
/** @} */

/** The 3D scene of a map for the stock SceneViewer3D (map.3Dscene): the
 * cloud coloured by height above the first camera (blue low, red high; cut
 * at `max_height`), the egomotion (red), SLAM (green) and ground-truth
 * (blue) trajectories, the entropy cells (entropyVoxelObject()), a legend
 * of text labels naming each object and colour, axes at the first camera,
 * and a ground grid. Everything is turned so that the world's up (−y of the
 * first camera) is the viewer's +Z, and the scene's camera (followed by
 * SceneViewer3D) looks down at the trajectory from above.
 * \ingroup emslam_apps_grp \sa writeMapScene() */
mrpt::opengl::COpenGLScene::Ptr buildMapScene(const MapDrawingContent& content);

/** Saves `scene` to `file` as the stock tools read it (COpenGLScene's gzip
 * format), through a temporary file renamed on success; a write error names
 * the file and the OS reason. Every .3Dscene output goes through it.
 * \ingroup emslam_apps_grp */
void writeSceneFile(const mrpt::opengl::COpenGLScene& scene, const std::string& file);

/** Saves buildMapScene() to `file` through a temporary file renamed on
 * success. Throws std::runtime_error naming the file on failure.
 * \ingroup emslam_apps_grp */
void writeMapScene(const MapDrawingContent& content, const std::string& file);

}  // namespace emslam::apps
