// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/rectify/RectifierOptions.h>
#include <emslam/util/ConfigVisitor.h>

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>

#include <cmath>
#include <cstdlib>
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

namespace
{
/** The value named `name` among `choices` of `[Rectifier] key`; throws naming
 * the key and the valid names otherwise. */
template <class Enum>
Enum parseChoice(
    const std::string& key, const std::string& name, std::initializer_list<Enum> choices)
{
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

/** `key` as one of `choices`, saved by its name. */
template <class Enum>
void choice(
    emslam::util::ConfigVisitor& v,
    const std::string& key,
    Enum& value,
    std::initializer_list<Enum> choices,
    const std::string& doc)
{
    v.text(
        key, value, [](Enum e) { return toString(e); },
        [&](const std::string& name) { return parseChoice(key, name, choices); }, doc);
}

std::string seedText(std::uint64_t seed)
{
    return std::to_string(seed);
}

std::uint64_t parseSeed(const std::string& text)
{
    // As read_double() reads it: a seed may be written 1e6.
    const double value = std::atof(text.c_str());
    // 2^53: every whole number up to it is exact in a double.
    require(
        value >= 0 && value <= 9007199254740992.0 && std::floor(value) == value, "seed",
        "must be a whole number in [0, 2^53]");
    return static_cast<std::uint64_t>(value);
}

/** Every key of [Rectifier], once for load and save. */
void visit(TRectifierOptions& p, emslam::util::ConfigVisitor& v)
{
    v.field("eps_xyz", p.eps_xyz, "epsilon of each translation component [m]");
    v.field("eps_rot_deg", p.eps_rot_deg, "epsilon of each rotation component [deg]");
    v.field("select_fraction", p.select_fraction, "S_sel, fraction of the actions perturbed");
    v.field("nc_max", p.nc_max, "NC_max, consecutive failures that end a rectification");
    v.field("max_attempts", p.max_attempts, "cap of attempts per rectification (0: none)");
    v.field("min_improvement", p.min_improvement, "relative energy drop of a success");
    choice(
        v, "acceptance", p.acceptance, {Acceptance::Ratio, Acceptance::Greedy},
        "ratio (paper) | greedy");
    v.field("reuse_success", p.reuse_success, "try a successful change again");
    v.field("rectify_every", p.rectify_every, "S_rec, serial mode");
    choice(
        v, "mode", p.mode, {RectificationMode::Serial, RectificationMode::AnyTime},
        "serial | anytime");
    v.field("buffer_size", p.buffer_size, "S_buf, AnyTime mode");
    v.field("n_max", p.n_max, "N_max, trajectory compression (0: never)");
    v.text("seed", p.seed, seedText, parseSeed, "random seed");
    v.field("vertical_band", p.vertical_band, "keep only points in [band_min_y, band_max_y]");
    v.field("band_min_y", p.band_min_y, "camera-frame y, down [m]");
    v.field("band_max_y", p.band_max_y, "camera-frame y, down [m]");
    // %e: small weights must survive the round trip, and the value must read
    // as a number, not a whole one (see emslam::apps::findMalformedConfigValues()).
    v.text(
        "prior_weight", p.prior_weight, [](double w) { return mrpt::format("%.10e", w); },
        [](const std::string& t) { return std::atof(t.c_str()); },
        "odometry prior weight (0: off, the paper)");
    v.field("prior_sigma_xyz", p.prior_sigma_xyz, "odometry prior, one step [m]");
    v.field("prior_sigma_rot_deg", p.prior_sigma_rot_deg, "odometry prior, one step [deg]");
    v.field(
        "experimental_grid_phases", p.experimental_grid_phases,
        "entropy averaged over shifted voxel grids (1: the paper)");
    v.field(
        "coarse_levels", p.coarse_levels,
        "each rectification first runs on cells 2^L..2 l_d (0: the paper)");
    v.field(
        "validate_phases", p.validate_phases,
        "keep a rectification only if K shifted grids agree (0: the paper)");
    v.field(
        "confirm_phases", p.confirm_phases,
        "a success moving a point > a cell needs K shifted grids (0: off)");
    v.field(
        "confirm_min_move", p.confirm_min_move,
        "[cells] moves confirm_phases checks beyond (0: every success)");
    v.field(
        "confirm_all_before_revisit", p.confirm_all_before_revisit,
        "confirm_phases checks every success until a revisit");
    v.field(
        "hold_before_revisit", p.hold_before_revisit,
        "no change at all until a revisit (energies blind to a_0)");
    choice(
        v, "prior_covariance", p.prior_covariance,
        {PriorCovariance::Fixed, PriorCovariance::Egomotion},
        "fixed (prior_sigma_*) | egomotion (Dpp curvature)");
    choice(
        v, "proposal", p.proposal,
        {ProposalShape::Box, ProposalShape::Covariance, ProposalShape::Coherent},
        "box (the paper's eps) | covariance | coherent");
    v.field("proposal_scale", p.proposal_scale, "sigma multiplier of the covariance proposal");
    v.field("threads", p.threads, "threads of one attempt's map update: 1 | 2 (same result)");
    v.field(
        "chains", p.chains, "serial mode, K independent searches, poses averaged (1 = the paper)");
}
}  // namespace

void TRectifierOptions::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
    emslam::util::loadByVisit(*this, c, s, visit);
    validate();
}

void TRectifierOptions::saveToConfigFile(
    mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    emslam::util::saveByVisit(*this, c, s, visit);
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
