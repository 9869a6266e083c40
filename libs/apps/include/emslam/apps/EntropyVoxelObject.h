// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/maps/CEntropyVoxelMap.h>

#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfObjects.h>

#include <cstddef>
#include <string>

namespace emslam::apps
{
/** Name of the object entropyVoxelObject() returns (map.3Dscene,
 * entropy_map.3Dscene, the map viewer). \ingroup emslam_apps_grp */
constexpr const char* ENTROPY_VOXELS_NAME = "entropy voxels";

/** The occupied cells of the map's 3D histogram as coloured points at the
 * cell centres (map frame), the colour giving the cell's mass (weight) on
 * the HOT scale relative to the heaviest cell: dark red light, white heavy.
 * Only the `max_cells` heaviest cells are drawn (ties by cell key), which
 * bounds the drawing whatever the map's size. The returned set is named
 * ENTROPY_VOXELS_NAME. \ingroup emslam_apps_grp */
mrpt::opengl::CSetOfObjects::Ptr entropyVoxelObject(
    const emslam::CEntropyVoxelMap& map, std::size_t max_cells);

/** A scene of the map alone: entropyVoxelObject() turned so that the world's
 * up is +Z, with axes at the origin and a camera above the cells.
 * \ingroup emslam_apps_grp */
mrpt::opengl::COpenGLScene::Ptr buildEntropyMapScene(
    const emslam::CEntropyVoxelMap& map, std::size_t max_cells);

/** Writes `file` (a .3Dscene for SceneViewer3D): entropyVoxelObject() turned
 * so that the world's up is +Z, with axes at the origin and a camera above
 * the cells. Through a temporary file renamed on success; throws
 * std::runtime_error naming the file on failure. \ingroup emslam_apps_grp */
void writeEntropyMapScene(
    const emslam::CEntropyVoxelMap& map, std::size_t max_cells, const std::string& file);

}  // namespace emslam::apps
