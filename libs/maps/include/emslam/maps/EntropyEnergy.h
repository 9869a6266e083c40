// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace emslam::maps
{
/** The consistency energies of the paper (§2.2.1), by expression number.
 * World axes are the first camera's optical frame: Y is vertical and XZ is
 * the horizontal plane.
 * \ingroup emslam_maps_grp \sa CEntropyVoxelMap */
enum class EnergyType : std::uint8_t
{
    /** Exp. 8, 6DOF: E = H(A). INI name `unstructured`. */
    Unstructured = 0,
    /** Exp. 9, 6DOF: E = H(A) + H(A_Y). INI name `low_structured`. */
    LowStructured,
    /** Exp. 10, 6DOF: E = H(A) + H(A_XY) + H(A_XZ) + H(A_YZ). INI name `structured`. */
    Structured,
    /** Exp. 11, 3DOF: E = H(A_XZ). INI name `planar_low_structured`. */
    PlanarLowStructured,
    /** Exp. 12, 3DOF: E = H(A_XZ) + H(A_X) + H(A_Z). INI name `planar_structured`. */
    PlanarStructured
};

/** One entropy term: the full 3D histogram, a 2D marginal on a principal
 * plane, or a 1D marginal on a principal axis. \ingroup emslam_maps_grp */
enum class EntropyTerm : std::uint8_t
{
    H3D = 0,  //!< H(A)
    XY,       //!< H(A_XY)
    XZ,       //!< H(A_XZ)
    YZ,       //!< H(A_YZ)
    X,        //!< H(A_X)
    Y,        //!< H(A_Y)
    Z         //!< H(A_Z)
};

/** Number of EntropyTerm values. \ingroup emslam_maps_grp */
constexpr std::size_t NUM_ENTROPY_TERMS = 7;

/** The seven entropies of a map, indexed by EntropyTerm. \ingroup emslam_maps_grp */
using EntropyTerms = std::array<double, NUM_ENTROPY_TERMS>;

/** Bit mask of EntropyTerm values (bit i = term i). \ingroup emslam_maps_grp */
using TermMask = std::uint8_t;

/** Bit of one term in a TermMask. \ingroup emslam_maps_grp */
constexpr TermMask termBit(EntropyTerm t)
{
    return static_cast<TermMask>(1u << static_cast<unsigned>(t));
}

/** The terms an energy sums. \ingroup emslam_maps_grp */
TermMask energyTerms(EnergyType e);

/** 6 for Exp. 8-10, 3 for Exp. 11-12. \ingroup emslam_maps_grp */
int energyDof(EnergyType e);

/** Expression number of the energy in the paper (8..12). \ingroup emslam_maps_grp */
int energyExpression(EnergyType e);

/** INI name of an energy (`unstructured`, `low_structured`, ...). \ingroup emslam_maps_grp */
std::string toString(EnergyType e);

/** Short name of a term: `H3D`, `XY`, `XZ`, `YZ`, `X`, `Y`, `Z`. \ingroup emslam_maps_grp */
std::string toString(EntropyTerm t);

/** Parses an INI energy name (case-sensitive, as toString() writes it).
 * Throws std::exception naming `key` and listing the valid names.
 * \ingroup emslam_maps_grp */
EnergyType energyTypeFromString(const std::string& name, const std::string& key = "energy");

/** Sum of the terms of `e` taken from `h`. \ingroup emslam_maps_grp */
double energyFromTerms(EnergyType e, const EntropyTerms& h);

}  // namespace emslam::maps
