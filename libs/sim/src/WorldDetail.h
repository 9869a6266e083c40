// SPDX-License-Identifier: BSD-3-Clause
// Private to emslam_sim (not installed): the key checks, seed mixing and
// element constructors shared by World's loader and its generators
// (World.cpp, World_params.cpp, World_building.cpp, World_outdoor.cpp).
#pragma once

#include <emslam/sim/World.h>

#include <cstdint>
#include <string>

namespace emslam::sim::detail
{
/** Throws std::invalid_argument "[section] key: msg". */
[[noreturn]] void badKey(
    const std::string& section, const std::string& key, const std::string& msg);

/** `v` finite and > 0. */
void requirePositive(double v, const std::string& section, const std::string& key);

/** `v` finite and within [lo, hi]. */
void requireRange(
    double v, double lo, double hi, const std::string& section, const std::string& key);

/** `kind` is a ProceduralTexture kind. */
void requireTexture(const std::string& kind, const std::string& section, const std::string& key);

/** Seed of stream `k` of a world's `seed` (the splitmix64 finalizer): each
 * texture and random placement gets its own, uncorrelated seed. */
inline std::uint64_t mix(std::uint64_t seed, std::uint64_t k)
{
    std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (k + 1);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

/** A Plane element normal to `axis`. */
inline Element makePlane(int axis, const Vec3& lo, const Vec3& hi, int texture, double texel)
{
    Element e;
    e.kind = Element::Kind::Plane;
    e.axis = axis;
    e.lo = lo;
    e.hi = hi;
    e.texture = texture;
    e.texel_size = texel;
    return e;
}

/** A static Box element. */
inline Element makeBox(const Vec3& lo, const Vec3& hi, int texture, double texel)
{
    Element e;
    e.kind = Element::Kind::Box;
    e.lo = lo;
    e.hi = hi;
    e.texture = texture;
    e.texel_size = texel;
    return e;
}

}  // namespace emslam::sim::detail
