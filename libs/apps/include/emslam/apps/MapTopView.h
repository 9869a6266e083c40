// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/MapDrawingContent.h>

#include <mrpt/math/TPoint3D.h>

#include <opencv2/core.hpp>
#include <string>

namespace emslam::apps
{
/** A floor plan of a map: the top view image and where the world lands in it.
 * \ingroup emslam_apps_grp \sa renderTopView() */
struct MapTopView
{
    /** BGR, 8 bits: point density in grey on white, trajectories in colour. */
    cv::Mat image;
    /** Scale [pixels per metre]. */
    double pixels_per_metre{1.0};
    /** Viewer-frame coordinates [m] (X = first camera's forward, Y = its left)
     * of the image's left and top edges. */
    ///@{
    double left_x{0.0}, top_y{0.0};
    ///@}

    /** Pixel (column, row) of a map-frame point, seen from above (its height
     * is ignored); may fall outside the image. */
    cv::Point2d toPixel(const mrpt::math::TPoint3D& p_map) const;
};

/** Options of renderTopView(). \ingroup emslam_apps_grp */
struct TopViewOptions
{
    /** Longest image side [px]; the scale fits the map and trajectories. */
    int max_side{1000};
    /** Blank border around the drawing [px]. */
    int margin{30};
    /** Each point is spread over a square this wide [m] (the map cloud has
     * one point per cell of `[EntropySlam] map_cell_size`): solid walls instead of
     * dotted ones. ≤ 0: one pixel per point. */
    double point_size{0.1};
    /** Legend and scale bar drawn in the image. */
    bool legend{true};
};

/** Renders the map seen from above (the world's up is −y of the first camera;
 * the first camera looks to the right of the image): every cloud point
 * (after the height cut) adds to its pixel's count, drawn in grey on a log
 * scale (white empty, black densest), so walls show as dark lines; then the
 * trajectories as 2-pixel polylines (egomotion red, SLAM green, ground truth
 * blue), a legend and a scale bar. Throws std::invalid_argument if the
 * options are out of range (max_side < 64, margin < 0).
 * \ingroup emslam_apps_grp */
MapTopView renderTopView(const MapDrawingContent& content, const TopViewOptions& options = {});

/** Writes renderTopView() as a PNG (map_top.png) through a temporary file
 * renamed on success; throws std::runtime_error naming the file on failure.
 * \ingroup emslam_apps_grp */
void writeTopView(
    const MapDrawingContent& content, const std::string& file, const TopViewOptions& options = {});

}  // namespace emslam::apps
