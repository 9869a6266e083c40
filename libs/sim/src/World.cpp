// SPDX-License-Identifier: BSD-3-Clause
// World: the element and texture store, the height field's skip maxima, and
// load(), which runs a generator and then adds the [Element_*] sections.
#include "WorldDetail.h"

#include <emslam/sim/World.h>

#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace emslam::sim
{
using detail::badKey;
using detail::makeBox;
using detail::makePlane;
using detail::mix;
using detail::requireRange;
using detail::requireTexture;

namespace
{
/** A number key of an `[Element*]` section (no parameter struct checks
 * these): the whole text must be a number, unlike read_double()'s atof(). */
double readNumber(
    const mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& k, double def)
{
    if (!c.keyExists(s, k))
    {
        return def;
    }
    const std::string txt = c.read_string(s, k, "");
    char* end = nullptr;
    const double v = std::strtod(txt.c_str(), &end);
    if (txt.empty() || *end != '\0')
    {
        badKey(s, k, "expected a number, got '" + txt + "'");
    }
    return v;
}

Vec3 readVec3(const mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& k)
{
    const std::string txt = c.read_string(s, k, "");
    std::istringstream in(txt);
    Vec3 v{};
    if (!(in >> v[0] >> v[1] >> v[2]))
    {
        badKey(s, k, "expected three numbers 'x y z', got '" + txt + "'");
    }
    std::string extra;
    if (in >> extra)
    {
        badKey(s, k, "expected three numbers 'x y z', got '" + txt + "'");
    }
    return v;
}
}  // namespace

// ---------------------------------------------------------------- World
std::size_t World::addElement(const Element& e)
{
    m_elements.push_back(e);
    return m_elements.size() - 1;
}

int World::addTexture(const ProceduralTexture& t)
{
    m_textures.push_back(t);
    return static_cast<int>(m_textures.size() - 1);
}

void World::setHeightField(const HeightField& h, int texture, double texel_size)
{
    m_height = h;
    const int B = HeightField::BLOCK;
    const int nbx = (h.heights.cols - 1 + B - 1) / B;
    const int nbz = (h.heights.rows - 1 + B - 1) / B;
    m_height.block_max.create(nbz, nbx, CV_32F);
    for (int bz = 0; bz < nbz; ++bz)
    {
        for (int bx = 0; bx < nbx; ++bx)
        {
            // The block's cells span samples [b*B, b*B + B] (inclusive) on each axis.
            const cv::Rect r(
                bx * B, bz * B, std::min(B + 1, h.heights.cols - bx * B),
                std::min(B + 1, h.heights.rows - bz * B));
            double mx = 0;
            cv::minMaxLoc(h.heights(r), nullptr, &mx);
            m_height.block_max.at<float>(bz, bx) = static_cast<float>(mx);
        }
    }
    const int C = HeightField::COARSE;
    const int ncx = (nbx + C - 1) / C;
    const int ncz = (nbz + C - 1) / C;
    m_height.coarse_max.create(ncz, ncx, CV_32F);
    for (int cz = 0; cz < ncz; ++cz)
    {
        for (int cx = 0; cx < ncx; ++cx)
        {
            const cv::Rect r(cx * C, cz * C, std::min(C, nbx - cx * C), std::min(C, nbz - cz * C));
            double mx = 0;
            cv::minMaxLoc(m_height.block_max(r), nullptr, &mx);
            m_height.coarse_max.at<float>(cz, cx) = static_cast<float>(mx);
        }
    }
    Element e;
    e.kind = Element::Kind::HeightField;
    e.lo = {h.x0, h.min_height, h.z0};
    e.hi = {
        h.x0 + h.cell * (h.heights.cols - 1), h.max_height, h.z0 + h.cell * (h.heights.rows - 1)};
    e.texture = texture;
    e.texel_size = texel_size;
    addElement(e);
}

double World::groundHeight(double x, double z) const
{
    return hasHeightField() ? m_height.at(x, z) : 0.0;
}

void World::load(
    const mrpt::config::CConfigFileBase& cfg, const std::vector<std::array<double, 2>>& keep_out)
{
    m_elements.clear();
    m_textures.clear();
    m_height = HeightField();
    if (!cfg.sectionExists("World"))
    {
        throw std::invalid_argument("[World]: section missing (it holds the world 'type')");
    }
    m_type = cfg.read_string("World", "type", "");
    const int seed = cfg.read_int("World", "seed", 1);
    const auto useed = static_cast<std::uint64_t>(seed);
    if (m_type == "building")
    {
        building.loadFromConfigFile(cfg, "Building");
        buildBuilding(cfg, useed);
    }
    else if (m_type == "ground")
    {
        ground.loadFromConfigFile(cfg, "Ground");
        buildGround(cfg, useed, keep_out);
    }
    else if (m_type == "terrain")
    {
        terrain.loadFromConfigFile(cfg, "Terrain");
        buildTerrain(cfg, useed, keep_out);
    }
    else if (m_type != "empty")
    {
        badKey(
            "World", "type",
            "unknown world type '" + m_type + "' (expected building, ground, terrain or empty)");
    }
    loadElements(cfg, useed);
    if (m_elements.empty())
    {
        throw std::invalid_argument("[World] type: the world '" + m_type + "' has no elements");
    }
}

void World::loadElements(const mrpt::config::CConfigFileBase& cfg, std::uint64_t seed)
{
    std::vector<std::string> sections;
    cfg.getAllSections(sections);
    std::uint64_t k = 0;
    for (const auto& s : sections)
    {
        if (s.rfind("Element", 0) != 0)
        {
            continue;
        }
        ++k;
        const std::string type = cfg.read_string(s, "type", "");
        const std::string tex = cfg.read_string(s, "texture", "noise");
        requireTexture(tex, s, "texture");
        const double texel = readNumber(cfg, s, "texel_size", 0.01);
        requireRange(texel, 1e-6, 1e3, s, "texel_size");
        const Vec3 lo = readVec3(cfg, s, "min");
        const Vec3 hi = readVec3(cfg, s, "max");
        for (int a = 0; a < 3; ++a)
        {
            if (hi[static_cast<std::size_t>(a)] < lo[static_cast<std::size_t>(a)])
            {
                badKey(s, "max", "every coordinate must be >= the one of 'min'");
            }
        }
        const int tid = addTexture(ProceduralTexture::generate(tex, mix(seed, 5000 + k), 256));
        Element e;
        if (type == "plane")
        {
            int axis = -1;
            int flat = 0;
            for (int a = 0; a < 3; ++a)
            {
                if (lo[static_cast<std::size_t>(a)] == hi[static_cast<std::size_t>(a)])
                {
                    axis = a;
                    ++flat;
                }
            }
            if (flat != 1)
            {
                badKey(s, "min", "a plane needs exactly one coordinate with min == max");
            }
            e = makePlane(axis, lo, hi, tid, texel);
            e.stretch = cfg.read_bool(s, "stretch", false);
        }
        else if (type == "box" || type == "moving_box")
        {
            e = makeBox(lo, hi, tid, texel);
            if (type == "moving_box")
            {
                e.velocity = readVec3(cfg, s, "velocity");
                e.t0 = readNumber(cfg, s, "t0", 0.0);
                requireRange(e.t0, -1e10, 1e10, s, "t0");
            }
        }
        else
        {
            badKey(
                s, "type",
                "unknown element type '" + type + "' (expected plane, box or moving_box)");
        }
        addElement(e);
    }
}

}  // namespace emslam::sim
