// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/obs/CObservation.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace emslam::io
{
/** Decides which frames of a rawlog an app may use, so that every program
 * that reads frames (emslam-mapper, emslam-odometry, emslam-stereo) skips the
 * same ones, says so the same way and writes trajectories strictly
 * increasing in time. A frame is a stereo (`CObservationStereoImages`) or
 * RGB-D (`CObservation3DRangeScan`) observation; other observations are no
 * frames and pass untouched.
 *
 * A frame is skipped, and counted by its cause, when
 * - its **camera** (image size, intrinsics, baseline; see Camera) differs
 *   from the session's, the camera of the first frame used;
 * - its **timestamp** is invalid (INVALID_TIMESTAMP, not finite, not after
 *   1970-01-01 or not before 2100: what a NaN or 1e300 written by a tool
 *   through mrpt::Clock::fromDouble() becomes), or not
 *   strictly after the timestamp of the last frame used (duplicated, going
 *   back), compared in seconds as the trajectories write them;
 * - the app could not use it (skipUnusable(): what the stereo front-end
 *   refuses, e.g. left and right images of different sizes).
 * The first NAMED_PER_CAUSE skips of each cause get a warning naming their
 * record, the others are only counted. A camera change is only compared
 * between frames whose calibration fits their images: an inconsistent frame
 * is the front-end's to refuse, with its exact reason.
 * \code
 * FrameStreamGuard guard;
 * const auto d = guard.check(obs, record);
 * if (d.verdict == FrameStreamGuard::Verdict::Skip) { warn(d.warning); }
 * else if (d.verdict == FrameStreamGuard::Verdict::Use)
 * {
 *     try { use(obs); guard.accept(); }
 *     catch (const std::exception& e) { warn(guard.skipUnusable(record, e.what())); }
 * }
 * // at the end: warn(guard.cameraChangeWarning()) if not empty
 * \endcode
 * \ingroup emslam_io_grp \sa RawlogInput */
class FrameStreamGuard
{
public:
    /** Warnings per cause before the others are only counted. */
    static constexpr std::size_t NAMED_PER_CAUSE = 5;

    /** What a frame's camera is compared by. */
    struct Camera
    {
        /** Size of the (left / intensity) image [px]. */
        ///@{
        std::uint32_t width{0}, height{0};
        ///@}
        /** Left (RGB-D: intensity) camera's intrinsics [px]. */
        ///@{
        double fx{0}, fy{0}, cx{0}, cy{0};
        ///@}
        /** Right (RGB-D: depth) camera's intrinsics [px]. */
        ///@{
        double right_fx{0}, right_fy{0}, right_cx{0}, right_cy{0};
        ///@}
        double baseline{0};  //!< [m]; 0 for RGB-D
        bool rgbd{false};    //!< an RGB-D camera (intensity + depth), not a stereo pair

        /** Same size and, within a relative 1e-6, same numbers. */
        bool sameAs(const Camera& o) const;
        /** "320x240 (fx 200, fy 200, cx 160, cy 120, baseline 0.1 m)"; the
         * right camera's intrinsics are added when they differ from the left's. */
        std::string toString() const;
    };

    /** What check() says about a frame. */
    enum class Verdict
    {
        Use,        //!< a frame the app may use: process it, then accept() or skipUnusable()
        NotAFrame,  //!< neither stereo nor RGB-D: not the guard's business
        Skip        //!< skipped and counted (see Decision::warning)
    };
    /** Why a frame was skipped. */
    enum class Cause
    {
        BadStamp,
        CameraChanged,
        Unusable
    };

    /** What check() decided. */
    struct Decision
    {
        Verdict verdict{Verdict::NotAFrame};  //!< use it, not a frame, or skipped
        /** For a skip: the warning line (without the program's prefix), or ""
         * once NAMED_PER_CAUSE of its cause were named. */
        std::string warning;
    };

    /** Frames skipped per cause. */
    struct Counts
    {
        /** Skipped for a bad timestamp, another camera, or unusable by the app. */
        ///@{
        std::size_t bad_stamps{0}, camera_changes{0}, unusable{0};
        ///@}
        /** Skipped frames in all. */
        std::size_t total() const { return bad_stamps + camera_changes + unusable; }
    };

    /** The first camera change: where, from what to what, and whether the
     * session's camera ever came back (interleaved) or not (for good). */
    struct CameraChange
    {
        std::size_t record{0};  //!< the first frame whose camera differed
        /** The session's camera and the one that differed. */
        ///@{
        Camera from, to;
        ///@}
        bool for_good{true};  //!< no frame with the session's camera was used after it
        /** Runs of consecutive frames with another camera (1 when for good). */
        std::size_t runs{0};
        std::size_t used_before{0};  //!< frames used before it
    };

    /** The camera of a stereo or RGB-D observation whose calibration fits its
     * images; empty for other classes and for an observation the front-end
     * would refuse (no image, invalid calibration, calibration of another
     * size than the image). */
    static std::optional<Camera> cameraOf(const mrpt::obs::CObservation& obs);
    /** Why `t` (seconds since 1970, as mrpt::Clock::toDouble() gives it) is
     * no frame timestamp ("its timestamp nan is not finite", "its timestamp
     * 0 s is not after 1970-01-01", "its timestamp 1e+300 s is after 2100"),
     * or "" if it is one. */
    static std::string invalidStampReason(double t);

    /** Checks one observation of record `record` (it changes nothing but the
     * counts): Use, NotAFrame, or Skip with its warning. After Use, call
     * accept() once the app has used the frame, or skipUnusable(). */
    Decision check(const mrpt::obs::CObservation& obs, std::size_t record);
    /** check() on a frame's stamp (seconds; mrpt::Clock::toDouble()) and
     * camera (empty: let the app decide if it can use the frame). */
    Decision check(double stamp, const std::optional<Camera>& camera, std::size_t record);
    /** The frame of the last check() that returned Use was used: its stamp
     * becomes the one to pass, its camera (if none yet) the session's. */
    void accept();
    /** The frame of the last check() that returned Use could not be used
     * (`reason`, e.g. what the front-end threw): counted; returns its warning
     * ("skipping unusable observation at record N: reason") or "". */
    std::string skipUnusable(std::size_t record, const std::string& reason);

    /** Frames skipped so far, per cause. */
    const Counts& counts() const { return m_counts; }
    /** Frames used (accept()). */
    std::size_t accepted() const { return m_accepted; }
    /** "record N: cause" of every skip a warning named, in order. */
    const std::vector<std::string>& namedSkips() const { return m_named; }
    /** The session's camera, once a frame was used. */
    const std::optional<Camera>& sessionCamera() const { return m_session; }
    /** The first camera change, if any. */
    const std::optional<CameraChange>& cameraChange() const { return m_change; }

    /** The line to end a run with when frames were skipped for their camera,
     * else "". For good: "N frames skipped: camera changed from A to B at
     * record K; only the M frames before it were used". Interleaved: "N
     * frames skipped: their camera differed from the session's A in R runs
     * (the first at record K: B); the frames with the session's camera were
     * used". */
    std::string cameraChangeWarning() const;
    /** "3 frames skipped (1 with a bad timestamp, 1 with another camera, 1
     * unusable)", naming only the causes that occurred; "" when none was. */
    std::string skippedText() const;

private:
    /** check(), `stamp_problem` (if not "") standing for invalidStampReason(). */
    Decision checkFrame(
        double stamp,
        const std::string& stamp_problem,
        const std::optional<Camera>& camera,
        std::size_t record);
    Decision skip(Cause cause, std::size_t record, const std::string& what);

    Counts m_counts;
    std::size_t m_accepted{0};
    std::vector<std::string> m_named;
    std::optional<Camera> m_session;
    std::optional<CameraChange> m_change;
    bool m_in_change_run{false};
    /** The last frame used: its stamp and record. */
    std::optional<double> m_last_stamp;
    std::size_t m_last_record{0};
    /** The frame check() passed, waiting for accept(). */
    struct Pending
    {
        double stamp{0};
        std::optional<Camera> camera;
        std::size_t record{0};
    };
    std::optional<Pending> m_pending;
};

}  // namespace emslam::io
