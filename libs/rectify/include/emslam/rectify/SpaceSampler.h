// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose3D.h>

#include <string>

namespace emslam::rectify
{
/** Observation space sampling (§2.2.4): a frame joins the trajectory only if
 * the motion since the last accepted frame is large enough, so a robot that
 * stands still or crawls does not flood the trajectory with useless
 * elements. The motion is the composition of the egomotion actions of the
 * frames in between (rejected frames still move the camera).
 *
 * "Large enough" is: translation norm > t_min, or rotation angle > θ_min.
 * (The paper says "some translation ... some rotation"; norms make the test
 * independent of the direction of motion.)
 *
 * \code
 * [SpaceSampler]
 * enabled       = true
 * t_min         = 0.15   ; [m]
 * theta_min_deg = 5      ; [deg]
 * \endcode
 * \ingroup emslam_rectify_grp */
class SpaceSampler
{
public:
    /** `[SpaceSampler]` parameters. */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the `[SpaceSampler]` keys of section `s` of `c`; absent keys keep their value. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes every key to section `s` of `c`. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws std::invalid_argument naming the key of a bad value. */
        void validate() const;

        bool enabled{true};         //!< false: every frame is accepted (Default: true)
        double t_min{0.15};         //!< [m] (Default: 0.15)
        double theta_min_deg{5.0};  //!< [deg] (Default: 5)
    };

    SpaceSampler() = default;
    /** A sampler with the thresholds `p` (validated). */
    explicit SpaceSampler(const TParameters& p);

    /** Feeds the action T_prev_cur of a new frame; returns true if the frame
     * is accepted. The first frame ever fed is always accepted (its action
     * is ignored). */
    bool feed(const mrpt::poses::CPose3D& T_prev_cur);
    /** Motion since the last accepted frame: after an accepted feed(), the
     * action of the accepted frame (T_lastaccepted_cur). */
    const mrpt::poses::CPose3D& actionSinceAccepted() const { return m_since_accepted; }
    /** Frames accepted / rejected so far. */
    std::size_t accepted() const { return m_accepted; }
    std::size_t rejected() const { return m_rejected; }  //!< (see accepted())
    /** Forgets the last accepted frame (the next feed() is accepted); the
     * counters stay. */
    void reset();
    /** The thresholds it uses. */
    const TParameters& params() const { return m_p; }

private:
    TParameters m_p;
    mrpt::poses::CPose3D m_since_accepted;
    mrpt::poses::CPose3D m_pending;  //!< motion since the last accepted frame
    bool m_has_reference{false};     //!< a frame has been accepted since reset()
    std::size_t m_accepted{0};
    std::size_t m_rejected{0};
};

}  // namespace emslam::rectify
