// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/sim/ProceduralTexture.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace emslam::sim
{
/** A 3-vector in the scene frame. */
using Vec3 = std::array<double, 3>;

/** One textured primitive of a World, in the **scene frame** (X, Z
 * horizontal, Y **up**, metres; the ground floor at Y = 0).
 * \ingroup emslam_sim_grp \sa World */
struct Element
{
    /** Primitive kind. */
    enum class Kind
    {
        Plane,       //!< axis-aligned rectangle: lo[axis] == hi[axis]
        Box,         //!< axis-aligned box [lo, hi], possibly moving
        HeightField  //!< World::heightField() over [lo.x, hi.x] x [lo.z, hi.z]
    };
    Kind kind{Kind::Plane};  //!< plane, box or height field
    /** Axis-aligned bounds (for a moving box: at time t0). */
    ///@{
    Vec3 lo{0, 0, 0}, hi{0, 0, 0};
    ///@}
    /** Normal axis of a Plane (0: X, 1: Y, 2: Z). */
    int axis{0};
    /** Index into World::textures(). */
    int texture{0};
    /** Texel edge [m] when tiled; ignored when `stretch`. */
    double texel_size{0.01};
    /** Stretch the texture once over a Plane (posters, doors) instead of tiling it. */
    bool stretch{false};
    /** Velocity of a moving Box [m/s]; position at time t is lo + velocity * (t - t0). */
    Vec3 velocity{0, 0, 0};
    /** Reference time of a moving Box [s, from the first frame]. */
    double t0{0.0};
    /** True if velocity is not zero. */
    bool moving() const { return velocity[0] != 0 || velocity[1] != 0 || velocity[2] != 0; }
};

/** A regular grid of heights (scene Y, metres) with bilinear interpolation.
 * \ingroup emslam_sim_grp */
struct HeightField
{
    /** Scene coordinates of sample (0,0) [m]. */
    ///@{
    double x0{0}, z0{0};
    ///@}
    double cell{0.1};     //!< sample spacing [m]
    cv::Mat heights;      //!< CV_32FC1, rows along Z, columns along X
    float max_height{0};  //!< largest height [m]
    float min_height{0};  //!< smallest height [m]
    double max_slope{1};  //!< bound of |dh/dx|, |dh/dz| (for ray marching)
    cv::Mat shade;        //!< CV_32FC1 Lambert factor per sample (same size as heights)
    /** Block edge [samples] of block_max. */
    static constexpr int BLOCK = 8;
    /** CV_32FC1 maximum height over each BLOCK x BLOCK block of cells (filled by
     * World::setHeightField(); lets the renderer skip empty space). */
    cv::Mat block_max;
    /** Coarse level edge [blocks] of coarse_max. */
    static constexpr int COARSE = 4;
    /** CV_32FC1 maximum of block_max over each COARSE x COARSE group of blocks
     * (long rays over the field skip it in fewer, larger jumps). */
    cv::Mat coarse_max;
    /** Height at scene (x, z), bilinear, clamped at the borders. */
    double at(double x, double z) const
    {
        const double fx = std::clamp((x - x0) / cell, 0.0, heights.cols - 1.001);
        const double fz = std::clamp((z - z0) / cell, 0.0, heights.rows - 1.001);
        const int ix = static_cast<int>(fx);
        const int iz = static_cast<int>(fz);
        const double ax = fx - ix;
        const double az = fz - iz;
        const float* r0 = heights.ptr<float>(iz);
        const float* r1 = heights.ptr<float>(iz + 1);
        return (r0[ix] * (1 - ax) + r0[ix + 1] * ax) * (1 - az) +
               (r1[ix] * (1 - ax) + r1[ix + 1] * ax) * az;
    }
};

/** A synthetic world: textured planes, boxes and one optional height field,
 * built from an INI file by one of the generators, plus explicit elements.
 *
 * \code
 * [World]
 * type = building          ; building | ground | terrain | empty
 * seed = 1                 ; textures and random placement
 *
 * [Building]               ; type = building: Manhattan floor plan(s)
 * cell_size = 2.0          ; [m] edge of one map cell
 * wall_height = 2.8        ; [m]
 * level_height = 3.2       ; [m] floor-to-floor (levels > 1)
 * levels = 1               ; 1 or 2
 * map_0 = #####/#...#/#####  ; rows separated by '/': '#' solid, '.' free, 'S' stairs
 * map_1 =                  ; level 1 plan (levels = 2)
 * stairs_dir = +x          ; stairs ascend along +x, -x, +z or -z; one value for
 *                          ; every staircase, or one per staircase (a 4-connected
 *                          ; group of level-0 'S' cells), in row-major order
 * door_probability = 0.15  ; per wall cell face
 * poster_probability = 0.25
 * wall_texture = noise     ; ProceduralTexture kind
 * floor_texture = tiles
 * ceiling_texture = noise
 * texel_size = 0.01        ; [m]
 *
 * [Ground]                 ; type = ground: flat floor + scattered boxes (paper Exp. 9)
 * extent = 40              ; [m] square side, centred at the origin
 * objects = 60             ; number of boxes
 * min_size = 0.3  max_size = 1.5   ; [m]
 * clearance = 1.0          ; [m] kept free around the trajectory way-points
 * ground_texture = gravel  object_texture = noise
 *
 * [Terrain]                ; type = terrain: height field + rocks + bushes
 * extent = 40  cell = 0.1  amplitude = 0.25  channel_depth = 0.6  channel_width = 8
 * rocks = 120  bushes = 60  clearance = 1.0
 *
 * [Element_<name>]         ; any world: extra elements
 * type = box               ; plane | box | moving_box
 * min = 1 0 5              ; x y z [m]
 * max = 2 1 6
 * texture = noise   texel_size = 0.01   stretch = false
 * velocity = 0.8 0 0       ; moving_box [m/s]
 * t0 = 0                   ; moving_box: time at which it is at [min, max]
 * \endcode
 * \ingroup emslam_sim_grp \sa StereoRenderer, StereoSimulator */
class World
{
public:
    World() = default;

    /** Builds the world from `cfg` (sections above). `keep_out` (scene X, Z
     * pairs) are the trajectory way-points: scattered objects keep
     * `clearance` away from the segments joining them. Throws
     * std::invalid_argument naming the section and key on bad values. */
    void load(
        const mrpt::config::CConfigFileBase& cfg,
        const std::vector<std::array<double, 2>>& keep_out = {});

    /** Adds an element; returns its index. */
    std::size_t addElement(const Element& e);
    /** Adds a texture; returns its index. */
    int addTexture(const ProceduralTexture& t);
    /** Sets the height field and adds its Element. */
    void setHeightField(const HeightField& h, int texture, double texel_size);

    /** Every element (planes, boxes, the height field), in the order added. */
    const std::vector<Element>& elements() const { return m_elements; }
    /** The procedural textures the elements index. */
    const std::vector<ProceduralTexture>& textures() const { return m_textures; }
    /** True once setHeightField() gave a ground relief. */
    bool hasHeightField() const { return !m_height.heights.empty(); }
    /** The ground relief (empty heights without one). */
    const HeightField& heightField() const { return m_height; }
    /** Ground height under scene (x, z): the height field, or 0. */
    double groundHeight(double x, double z) const;
    /** The world type read by load(). */
    const std::string& type() const { return m_type; }

    /** [Building] parameters (type = building). */
    struct TBuildingParams : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        double cell_size{2.0};     //!< [m] edge of a map cell (Default: 2.0)
        double wall_height{2.8};   //!< [m] (Default: 2.8)
        double level_height{3.2};  //!< [m] floor-to-floor height (Default: 3.2)
        int levels{1};             //!< 1 or 2 (Default: 1)
        std::string map_0;         //!< level 0 plan, rows separated by '/'
        std::string map_1;         //!< level 1 plan (levels = 2)
        /** +x, -x, +z, -z: one for every staircase, or a space-separated list
         * with one per staircase in row-major order of their first cell. (Default: +x) */
        std::string stairs_dir{"+x"};
        double door_probability{0.15};         //!< per wall cell face (Default: 0.15)
        double poster_probability{0.25};       //!< per wall cell face (Default: 0.25)
        std::string wall_texture{"noise"};     //!< (Default: noise)
        std::string floor_texture{"tiles"};    //!< (Default: tiles)
        std::string ceiling_texture{"noise"};  //!< (Default: noise)
        double texel_size{0.01};               //!< [m] (Default: 0.01)

        /** stairs_dir split at spaces. */
        std::vector<std::string> stairsDirections() const;
    };

    /** [Ground] parameters (type = ground). */
    struct TGroundParams : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        double extent{40.0};    //!< [m] side of the square floor (Default: 40)
        int objects{60};        //!< scattered boxes (Default: 60)
        double min_size{0.3};   //!< [m] (Default: 0.3)
        double max_size{1.5};   //!< [m] (Default: 1.5)
        double clearance{1.0};  //!< [m] free band around the way-point path (Default: 1.0)
        std::string ground_texture{"gravel"};  //!< (Default: gravel)
        std::string object_texture{"noise"};   //!< (Default: noise)
        double texel_size{0.01};               //!< [m] (Default: 0.01)
    };

    /** [Terrain] parameters (type = terrain). */
    struct TTerrainParams : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        double extent{40.0};        //!< [m] side of the square terrain (Default: 40)
        double cell{0.1};           //!< [m] height sample spacing (Default: 0.1)
        double amplitude{0.25};     //!< [m] std of the multi-scale relief (Default: 0.25)
        double channel_depth{0.6};  //!< [m] depth of the dry river bed along Z (Default: 0.6)
        double channel_width{8.0};  //!< [m] (Default: 8)
        int rocks{120};             //!< rock bumps (Default: 120)
        int bushes{60};             //!< bush boxes (Default: 60)
        double clearance{1.0};      //!< [m] free band around the way-point path (Default: 1.0)
        std::string ground_texture{"gravel"};  //!< (Default: gravel)
        double texel_size{0.01};               //!< [m] (Default: 0.01)
    };

    /** Generator parameters as loaded. */
    TBuildingParams building;
    TGroundParams ground;    //!< `[Ground]`, as loaded
    TTerrainParams terrain;  //!< `[Terrain]`, as loaded

private:
    void buildBuilding(const mrpt::config::CConfigFileBase& cfg, std::uint64_t seed);
    /** Steps of one staircase over the level-0 cells rows r0..r1, columns c0..c1. */
    void addStaircase(int r0, int r1, int c0, int c1, const std::string& dir, int texture);
    void buildGround(
        const mrpt::config::CConfigFileBase& cfg,
        std::uint64_t seed,
        const std::vector<std::array<double, 2>>& keep_out);
    void buildTerrain(
        const mrpt::config::CConfigFileBase& cfg,
        std::uint64_t seed,
        const std::vector<std::array<double, 2>>& keep_out);
    void loadElements(const mrpt::config::CConfigFileBase& cfg, std::uint64_t seed);

    std::string m_type;
    std::vector<Element> m_elements;
    std::vector<ProceduralTexture> m_textures;
    HeightField m_height;
};

}  // namespace emslam::sim
