// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/RectifierOptions.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include <cmath>
#include <initializer_list>
#include <stdexcept>

namespace emslam::rectify
{
namespace
{
void require(bool ok, const std::string& key, const std::string& msg)
{
    if (!ok)
    {
        throw std::invalid_argument("[Rectifier] " + key + ": " + msg);
    }
}

/** The value named `name` among `choices` of `[Rectifier] key`; throws naming
 * the key and the valid names otherwise. */
template <class Enum>
Enum readChoice(
    const mrpt::config::CConfigFileBase& c,
    const std::string& section,
    const std::string& key,
    Enum current,
    std::initializer_list<Enum> choices)
{
    const std::string name = c.read_string(section, key, toString(current));
    std::string valid;
    for (Enum e : choices)
    {
        if (name == toString(e))
        {
            return e;
        }
        valid += (valid.empty() ? "" : ", ") + toString(e);
    }
    throw std::invalid_argument(
        "[Rectifier] " + key + ": unknown value '" + name + "' (valid: " + valid + ")");
}
}  // namespace

std::string toString(ProposalShape p)
{
    switch (p)
    {
        case ProposalShape::Covariance:
            return "covariance";
        case ProposalShape::Coherent:
            return "coherent";
        default:
            return "box";
    }
}

std::string toString(Acceptance a)
{
    return a == Acceptance::Ratio ? "ratio" : "greedy";
}

std::string toString(RectificationMode m)
{
    return m == RectificationMode::Serial ? "serial" : "anytime";
}

void TRectifierOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    MRPT_LOAD_CONFIG_VAR(eps_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(eps_rot_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(select_fraction, double, c, s);
    MRPT_LOAD_CONFIG_VAR(nc_max, int, c, s);
    MRPT_LOAD_CONFIG_VAR(max_attempts, int, c, s);
    MRPT_LOAD_CONFIG_VAR(min_improvement, double, c, s);
    acceptance =
        readChoice(c, s, "acceptance", acceptance, {Acceptance::Ratio, Acceptance::Greedy});
    MRPT_LOAD_CONFIG_VAR(reuse_success, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(rectify_every, int, c, s);
    mode = readChoice(c, s, "mode", mode, {RectificationMode::Serial, RectificationMode::AnyTime});
    MRPT_LOAD_CONFIG_VAR(buffer_size, int, c, s);
    MRPT_LOAD_CONFIG_VAR(n_max, int, c, s);
    const double seed_value = c.read_double(s, "seed", static_cast<double>(seed));
    // 2^53: every whole number up to it is exact in a double.
    require(
        seed_value >= 0 && seed_value <= 9007199254740992.0 && std::floor(seed_value) == seed_value,
        "seed", "must be a whole number in [0, 2^53]");
    seed = static_cast<std::uint64_t>(seed_value);
    MRPT_LOAD_CONFIG_VAR(vertical_band, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(band_min_y, double, c, s);
    MRPT_LOAD_CONFIG_VAR(band_max_y, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prior_weight, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prior_sigma_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prior_sigma_rot_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(experimental_grid_phases, int, c, s);
    MRPT_LOAD_CONFIG_VAR(coarse_levels, int, c, s);
    MRPT_LOAD_CONFIG_VAR(validate_phases, int, c, s);
    MRPT_LOAD_CONFIG_VAR(confirm_phases, int, c, s);
    MRPT_LOAD_CONFIG_VAR(confirm_min_move, double, c, s);
    MRPT_LOAD_CONFIG_VAR(confirm_all_before_revisit, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(hold_before_revisit, bool, c, s);
    prior_covariance = readChoice(
        c, s, "prior_covariance", prior_covariance,
        {PriorCovariance::Fixed, PriorCovariance::Egomotion});
    proposal = readChoice(
        c, s, "proposal", proposal,
        {ProposalShape::Box, ProposalShape::Covariance, ProposalShape::Coherent});
    MRPT_LOAD_CONFIG_VAR(proposal_scale, double, c, s);
    MRPT_LOAD_CONFIG_VAR(threads, int, c, s);
    MRPT_LOAD_CONFIG_VAR(chains, int, c, s);
    validate();
}

void TRectifierOptions::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    MRPT_SAVE_CONFIG_VAR_COMMENT(eps_xyz, "epsilon of each translation component [m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(eps_rot_deg, "epsilon of each rotation component [deg]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(select_fraction, "S_sel, fraction of the actions perturbed");
    MRPT_SAVE_CONFIG_VAR_COMMENT(nc_max, "NC_max, consecutive failures that end a rectification");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_attempts, "cap of attempts per rectification (0: none)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(min_improvement, "relative energy drop of a success");
    c.write(s, "acceptance", toString(acceptance), -1, -1, "ratio (paper) | greedy");
    MRPT_SAVE_CONFIG_VAR_COMMENT(reuse_success, "try a successful change again");
    MRPT_SAVE_CONFIG_VAR_COMMENT(rectify_every, "S_rec, serial mode");
    c.write(s, "mode", toString(mode), -1, -1, "serial | anytime");
    MRPT_SAVE_CONFIG_VAR_COMMENT(buffer_size, "S_buf, AnyTime mode");
    MRPT_SAVE_CONFIG_VAR_COMMENT(n_max, "N_max, trajectory compression (0: never)");
    c.write(s, "seed", std::to_string(seed), -1, -1, "random seed");
    MRPT_SAVE_CONFIG_VAR_COMMENT(vertical_band, "keep only points in [band_min_y, band_max_y]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(band_min_y, "camera-frame y, down [m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(band_max_y, "camera-frame y, down [m]");
    // %e: small weights must survive the round trip, and the value must read
    // as a number, not a whole one (see emslam::apps::findMalformedConfigValues()).
    c.write(
        s, "prior_weight", mrpt::format("%.10e", prior_weight), -1, -1,
        "odometry prior weight (0: off, the paper)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prior_sigma_xyz, "odometry prior, one step [m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prior_sigma_rot_deg, "odometry prior, one step [deg]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        experimental_grid_phases, "entropy averaged over shifted voxel grids (1: the paper)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        coarse_levels, "each rectification first runs on cells 2^L..2 l_d (0: the paper)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        validate_phases, "keep a rectification only if K shifted grids agree (0: the paper)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        confirm_phases, "a success moving a point > a cell needs K shifted grids (0: off)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        confirm_min_move, "[cells] moves confirm_phases checks beyond (0: every success)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        confirm_all_before_revisit, "confirm_phases checks every success until a revisit");
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        hold_before_revisit, "no change at all until a revisit (energies blind to a_0)");
    c.write(
        s, "prior_covariance", toString(prior_covariance), -1, -1,
        "fixed (prior_sigma_*) | egomotion (Dpp curvature)");
    c.write(
        s, "proposal", toString(proposal), -1, -1, "box (the paper's eps) | covariance | coherent");
    MRPT_SAVE_CONFIG_VAR_COMMENT(proposal_scale, "sigma multiplier of the covariance proposal");
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        threads, "threads of one attempt's map update: 1 | 2 (same result)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        chains, "serial mode, K independent searches, poses averaged (1 = the paper)");
}

void TRectifierOptions::validate() const
{
    // A step of more than 10 m per action is no perturbation; poses must stay
    // where map cell indices (coordinate / cell size) fit an int.
    require(
        std::isfinite(eps_xyz) && eps_xyz >= 0 && eps_xyz <= 10, "eps_xyz",
        "= " + std::to_string(eps_xyz) + ": must be in [0, 10] m");
    require(
        std::isfinite(eps_rot_deg) && eps_rot_deg >= 0 && eps_rot_deg < 90, "eps_rot_deg",
        "must be in [0, 90)");
    require(eps_xyz > 0 || eps_rot_deg > 0, "eps_xyz", "eps_xyz and eps_rot_deg are both 0");
    require(select_fraction > 0 && select_fraction <= 1, "select_fraction", "must be in (0, 1]");
    require(
        nc_max >= 1 && nc_max <= 1000000, "nc_max",
        "= " + std::to_string(nc_max) + ": must be in [1, 1000000]");
    require(
        max_attempts >= 0, "max_attempts",
        "= " + std::to_string(max_attempts) + ": must be >= 0 (0: no cap)");
    require(
        std::isfinite(min_improvement) && min_improvement >= 0 && min_improvement < 1,
        "min_improvement", "must be in [0, 1)");
    require(rectify_every >= 0, "rectify_every", "must be >= 0 (0: never, egomotion only)");
    require(
        rectify_every >= 1 || mode == RectificationMode::Serial, "rectify_every",
        "must be >= 1 in anytime mode");
    require(
        buffer_size >= 1 && buffer_size <= 1000000, "buffer_size",
        "= " + std::to_string(buffer_size) + ": must be in [1, 1000000]");
    require(
        n_max == 0 || (n_max >= 4 && n_max <= 1000000), "n_max",
        "= " + std::to_string(n_max) + ": must be 0 (no compression) or in [4, 1000000]");
    // Checked even with the band off: effective.ini must load back.
    require(
        std::isfinite(band_min_y) && std::abs(band_min_y) <= 1e6, "band_min_y",
        "= " + std::to_string(band_min_y) + ": must be a number of metres in [-1e6, 1e6]");
    require(
        std::isfinite(band_max_y) && std::abs(band_max_y) <= 1e6, "band_max_y",
        "= " + std::to_string(band_max_y) + ": must be a number of metres in [-1e6, 1e6]");
    require(
        !vertical_band || band_min_y < band_max_y, "band_min_y",
        "must be < band_max_y when vertical_band = true");
    // The prior's cost is weight * (step / sigma)^2: keep it finite.
    require(
        std::isfinite(prior_weight) && prior_weight >= 0 && prior_weight <= 1e6, "prior_weight",
        "= " + std::to_string(prior_weight) + ": must be in [0, 1e6]");
    require(
        std::isfinite(prior_sigma_xyz) && prior_sigma_xyz >= 1e-6 && prior_sigma_xyz <= 1000,
        "prior_sigma_xyz", "= " + std::to_string(prior_sigma_xyz) + ": must be in [1e-6, 1000] m");
    require(
        std::isfinite(prior_sigma_rot_deg) && prior_sigma_rot_deg >= 1e-6 &&
            prior_sigma_rot_deg <= 180,
        "prior_sigma_rot_deg",
        "= " + std::to_string(prior_sigma_rot_deg) + ": must be in [1e-6, 180] deg");
    require(
        experimental_grid_phases >= 1 && experimental_grid_phases <= 8, "experimental_grid_phases",
        "must be in 1..8");
    require(coarse_levels >= 0 && coarse_levels <= 4, "coarse_levels", "must be in 0..4");
    require(
        validate_phases == 0 || (validate_phases >= 2 && validate_phases <= 8), "validate_phases",
        "must be 0 (off) or in 2..8");
    require(
        confirm_phases == 0 || (confirm_phases >= 2 && confirm_phases <= 8), "confirm_phases",
        "must be 0 (off) or in 2..8");
    require(
        std::isfinite(confirm_min_move) && confirm_min_move >= 0 && confirm_min_move <= 1000,
        "confirm_min_move", "must be in [0, 1000] cells");
    require(
        std::isfinite(proposal_scale) && proposal_scale > 0 && proposal_scale <= 100,
        "proposal_scale", "must be in (0, 100]");
    require(threads == 1 || threads == 2, "threads", "must be 1 or 2");
    require(chains >= 1 && chains <= 16, "chains", "must be in 1..16");
    require(
        chains == 1 || mode == RectificationMode::Serial, "chains",
        "must be 1 in anytime mode (the chains run in the caller's thread)");
}

}  // namespace emslam::rectify
