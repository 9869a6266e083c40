// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/apps/App.h>

#include <mrpt/opengl/COpenGLScene.h>

#include <string>

namespace emslam::apps
{
/** `emslam-mapview`: opens a map file of emslam in a 3D window, where the
 * stock SceneViewer3D cannot (it takes entropy_map.bin for a mesh).
 *
 * \code
 * emslam-mapview FILE [--max-cells N] [--screenshot IMAGE]
 * \endcode
 * FILE: `entropy_map.bin` (a serialized CEntropyVoxelMap: its heaviest N
 * cells, default 50000), any other serialized MRPT metric map (its own
 * drawing), or a `.3Dscene` (map.3Dscene, entropy_map.3Dscene). The window
 * stays until it is closed. Without a display it fails naming the cause;
 * `--screenshot` needs none: it draws the view off-screen into IMAGE
 * instead of opening the window.
 * \ingroup emslam_apps_grp \sa entropyVoxelObject(), LiveViewer */
class MapViewApp : public App
{
public:
    MapViewApp();

    /** The scene shown for `file` (see the class comment). Throws
     * std::runtime_error naming the file if it is missing, unreadable or of
     * a class that cannot be drawn. */
    static mrpt::opengl::COpenGLScene::Ptr loadScene(
        const std::string& file, std::size_t max_cells);

protected:
    bool parseArguments(int argc, const char** argv) override;
    /** Loads the file, opens the window and returns when it is closed. */
    void execute() override;

private:
    /** Draws `scene` off-screen from its camera into m_screenshot. */
    void saveScreenshot(const mrpt::opengl::COpenGLScene& scene) const;

    std::string m_file;
    std::string m_screenshot;
    std::size_t m_max_cells{50000};
};

}  // namespace emslam::apps
