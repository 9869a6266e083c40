// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/sim/StereoSimulator.h>
#include <emslam/sim/World.h>

#include <mrpt/config/CLoadableOptions.h>

#include <cstddef>
#include <string>
#include <vector>

namespace emslam::sim
{
/** One sample of a true surface. \ingroup emslam_sim_grp \sa SurfaceSampler */
struct SurfaceSample
{
    Vec3 position{0, 0, 0};  //!< [m]
    Vec3 normal{0, 0, 0};    //!< unit normal (its sign is arbitrary: faces are two-sided)
    /** Nearest camera depth the sample was seen at [m] (0: not tested). */
    float seen_range{0.0F};
};

/** The true surfaces of a World as a dense cloud: the reference a map is
 * measured against (`emslam-sim --map-gt-out`, eval::MapAccuracy).
 *
 * Every static face (planes, the six faces of each box, the height field)
 * is sampled at the centres of a regular grid of about `spacing` (moving
 * boxes are left out: they are no part of a static map). visibleSurfaces()
 * keeps the samples a camera of the trajectory saw: in the image, at a depth
 * in [min_range, max_range], and not hidden: the exact depth the renderer
 * gives the four pixels around the sample's projection, interpolated in
 * inverse depth (exact on a plane), agrees with the sample's depth. The
 * frames tested are those where the camera moved `pose_step` or turned
 * `pose_step_deg` since the last one tested.
 *
 * \code
 * ; emslam-sim --map-gt-out: --map-gt-spacing, --map-gt-range set these
 * spacing = 0.02        ; [m] distance between samples
 * max_range = 12        ; [m] farthest depth a sample is seen at (the mapper's [StereoMatcher]
 * max_range) min_range = 0.3       ; [m] pose_step = 0.25      ; [m] pose_step_deg = 10    ; [deg]
 * \endcode
 * \ingroup emslam_sim_grp */
class SurfaceSampler
{
public:
    /** Sample spacing, depth window and the pose steps of the visibility test (INI keys of the
     * class comment). */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws std::invalid_argument naming the key of a bad value. */
        void validate() const;

        double spacing{0.02};      //!< [m] (Default: 0.02)
        double max_range{12.0};    //!< [m] (Default: 12)
        double min_range{0.3};     //!< [m] (Default: 0.3)
        double pose_step{0.25};    //!< [m] (Default: 0.25)
        double pose_step_deg{10};  //!< [deg] (Default: 10)
    };

    /** A sampler with the parameters `p` (validated). */
    explicit SurfaceSampler(const TParameters& p);

    /** Every static surface of `world`, scene frame, seen_range 0. */
    std::vector<SurfaceSample> allSurfaces(const World& world) const;

    /** The samples seen from frames [0, frames) of `sim`, in the first left
     * camera's frame (the frame of the ground truth and of the maps), each
     * with the nearest depth it was seen at. */
    std::vector<SurfaceSample> visibleSurfaces(
        const StereoSimulator& sim, std::size_t frames) const;

    /** The frames visibleSurfaces() tests among [0, frames). */
    std::vector<std::size_t> testedFrames(const StereoSimulator& sim, std::size_t frames) const;

private:
    TParameters m_p;
};

}  // namespace emslam::sim
