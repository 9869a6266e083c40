// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/hwdrivers/VideoSource.h>
#include <emslam/stereo/StereoRectifier.h>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/Clock.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/img/TStereoCamera.h>
#include <mrpt/obs/CObservationStereoImages.h>

#include <cstddef>
#include <memory>
#include <opencv2/core.hpp>
#include <string>

namespace emslam::hwdrivers
{
/** A stereo camera over OpenCV's cv::VideoCapture: a side-by-side stereo
 * camera (one UVC device whose frames hold left | right, e.g. a ZED in UVC
 * mode), two cameras, a stereo video file or a GStreamer pipeline. Each
 * doProcess() reads one frame (two with `source_right`), splits it, converts
 * it to grey, rectifies the pair with the calibration (StereoRectifier) and
 * emits a `CObservationStereoImages` labelled `sensorLabel`: both images,
 * `hasImageRight`, the rectified calibration, `cameraPose` = the `pose_*`
 * keys: the observation the other stereo sources emit.
 *
 * <b>Sources.</b> `source` (and `source_right`) is read as: digits only: a
 * device index (V4L2); `/dev/...`: a V4L2 device node (e.g.
 * `/dev/v4l/by-id/...`, stable across reboots); containing `!`: a GStreamer
 * pipeline ending in `appsink`; anything else: a video file (or an image
 * sequence such as `left_%04d.png`), relative to the working folder.
 *
 * <b>Timestamps.</b> A file has no capture clock: with `timestamps = video`
 * (the default for files) frame k is stamped `start_time + k / fps`, fps
 * being `video_fps` or else the rate the file declares (an image sequence
 * declares none; a variable-rate file is stamped as if constant). With
 * `now` (the default for devices and pipelines) a frame gets the wall clock
 * when OpenCV returned it (for two devices: once both were grabbed, before
 * decoding).
 *
 * <b>End.</b> A file or pipeline that ends throws EndOfStream from
 * doProcess() (emslam-grabber: a normal end, every frame kept); a device
 * that stops delivering (unplugged) throws std::runtime_error (the grabber
 * keeps the frames and reports the sensor as failed). initialize() opens the
 * sources and reads the first frame: a missing device or file, a frame whose
 * size does not match the calibration or a calibration OpenCV cannot
 * rectify throws there, naming the key, before anything is recorded.
 *
 * \code
 * [VIDEO_STEREO]
 * driver              = CVideoStereoCamera
 * sensorLabel         = STEREO
 * process_rate        = 30          // [Hz] (default: a file's frame rate; devices: 100, read()
 * waits) source              = hall.avi    // device index | /dev/videoN | video file | GStreamer
 * pipeline source_right        =             // empty: side-by-side frames; else the right camera's
 * source backend             = auto        // auto | v4l2 | ffmpeg | gstreamer | any capture_width
 * = 0           // [px] devices: frame width to request (side by side: both), 0: default
 * capture_height      = 0           // [px] devices: frame height to request, 0: default
 * capture_fps         = 0           // [Hz] devices: frame rate to request, 0: default
 * fourcc              =             // devices: pixel format to request (MJPG, YUYV), empty:
 * default timestamps          = auto        // auto (files: video, else now) | video | now
 * start_time          = 0           // [s] video stamps: UNIX time of frame 0
 * video_fps           = 0           // [Hz] video stamps: frame rate, 0: the file's
 * grayscale           = true        // emit grey images (false: the source's colour)
 * calibration_file    =             // empty: the sections below; .yml/.yaml/.xml/.json: OpenCV;
 * .ini: MRPT calibration_extrinsics_file =     // OpenCV only: a second file (R, T), e.g.
 * extrinsics.yml calibration_section = VIDEO_CALIB // MRPT INI form: prefix of the
 * _LEFT/_RIGHT/_LEFT2RIGHT_POSE sections translation_scale   = 1           // OpenCV only: T times
 * this is in metres (0.001: T in mm) rectify             = true        // rectify the pair with the
 * calibration rectify_alpha       = 0           // OpenCV free scaling, 0 (valid pixels) .. 1 (all
 * pixels) pose_x = 0, pose_y = 0, pose_z = 0                    // [m] left camera on the robot
 * pose_yaw_deg = 0, pose_pitch_deg = 0, pose_roll_deg = 0  // [deg]
 * \endcode
 * The calibration (raw cameras) is in MRPT's TStereoCamera INI form
 * (`[VIDEO_CALIB_LEFT]`, `_RIGHT`, `_LEFT2RIGHT_POSE`, as for
 * CDigiclopsStereoCamera), or in an OpenCV file (io::loadOpenCvStereoCalibration():
 * M1/K1, D1, M2/K2, D2, R, T, optional image_width / image_height; without a
 * size the calibration is taken to have the size of each camera's image).
 * \ingroup emslam_hwdrivers_grp \sa CDigiclopsStereoCamera, VideoSource */
class CVideoStereoCamera : public mrpt::hwdrivers::CGenericSensor
{
    DEFINE_GENERIC_SENSOR(CVideoStereoCamera)

public:
    /** The sensor-specific INI keys and the calibration (see the class comment). */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` and the calibration; throws naming the key. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes the keys (and, without calibration_file, the calibration sections). */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws std::invalid_argument naming the key of an invalid value. */
        void validate() const;

        /** Left (or side-by-side) source. Mandatory. */
        std::string source;
        /** Right camera's source; empty: `source` delivers side-by-side frames. */
        std::string source_right;
        /** auto, v4l2, ffmpeg, gstreamer or any. (Default: auto) */
        std::string backend{"auto"};
        /** [px] Frame size requested from devices; 0: the device's. (Default: 0) */
        int capture_width{0}, capture_height{0};
        /** [Hz] Frame rate requested from devices; 0: the device's. (Default: 0) */
        double capture_fps{0.0};
        /** Pixel format requested from devices (4 characters); empty: the device's. */
        std::string fourcc;
        /** auto, video or now. (Default: auto: video for files, now otherwise) */
        std::string timestamps{"auto"};
        /** [s] UNIX time of frame 0 with video timestamps. (Default: 0) */
        double start_time{0.0};
        /** [Hz] Frame rate of video timestamps; 0: the rate the file declares. (Default: 0) */
        double video_fps{0.0};
        /** Emit grey images. (Default: true) */
        bool grayscale{true};
        /** Calibration file (OpenCV .yml/.yaml/.xml/.json or MRPT .ini); empty:
         * the calibration sections of the sensor's own INI. */
        std::string calibration_file;
        /** OpenCV calibration: a second file read after calibration_file. */
        std::string calibration_extrinsics_file;
        /** Prefix of the TStereoCamera INI sections. (Default: VIDEO_CALIB) */
        std::string calibration_section{"VIDEO_CALIB"};
        /** OpenCV calibration: factor from T's unit to metres. (Default: 1) */
        double translation_scale{1.0};
        /** Rectify the pair. (Default: true) */
        bool rectify{true};
        /** OpenCV free scaling of the rectification, [0, 1]. (Default: 0) */
        double rectify_alpha{0.0};
        /** Left camera pose on the robot: position [m]. (Default: 0) */
        double pose_x{0}, pose_y{0}, pose_z{0};
        /** Left camera pose on the robot: angles [deg]. (Default: 0) */
        double pose_yaw_deg{0}, pose_pitch_deg{0}, pose_roll_deg{0};

        /** Raw calibration; a 0x0 resolution (an OpenCV file without a size)
         * takes the images' size at initialize(). */
        mrpt::img::TStereoCamera stereo_camera;

    private:
        /** The ranges of the number keys (part of validate()). */
        void validateNumbers() const;
        /** Reads stereo_camera from the file or sections the keys name. */
        void loadCalibration(const mrpt::config::CConfigFileBase& c, const std::string& s);
    };

    CVideoStereoCamera() = default;
    ~CVideoStereoCamera() override;

    /** Opens the sources and reads the first frame; throws naming the cause. */
    void initialize() override;
    /** Emits the next frame; throws EndOfStream at the end of a file or
     * pipeline, std::runtime_error when a device stops. */
    void doProcess() override;

    const TParameters& parameters() const { return m_params; }
    /** Frames emitted so far. */
    std::size_t framesDelivered() const { return m_delivered; }
    /** The calibration of the emitted observations (after initialize()). */
    const mrpt::img::TStereoCamera& outputCamera() const { return m_output_camera; }
    /** True if frames are stamped start_time + k / fps (after initialize()). */
    bool stampsFromVideo() const { return m_video_stamps; }
    /** The frame rate of video stamps [Hz] (after initialize()). */
    double stampFps() const { return m_stamp_fps; }

protected:
    void loadConfig_sensorSpecific(
        const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;

private:
    /** Opens source (and source_right) and settles the timestamps' clock. */
    void openSources();
    /** Checks the calibration against the images' `size` (filling in a
     * missing size) and prepares the rectification. */
    void prepareCalibration(cv::Size size);
    /** Reads the next raw frame(s) into m_left / m_right; false at the end. */
    bool readFrame();
    /** The observation of the frame in m_left / m_right, stamped `t`. */
    mrpt::obs::CObservationStereoImages::Ptr convertFrame(mrpt::Clock::time_point t);
    /** Where a source's end or failure is reported from. */
    std::string endMessage() const;

    TParameters m_params;
    std::string m_section;
    bool m_rate_from_source{false};
    std::unique_ptr<VideoSource> m_source, m_source_right;
    cv::Mat m_left, m_right;
    bool m_have_first{false};
    mrpt::Clock::time_point m_first_t{};
    bool m_video_stamps{false};
    double m_stamp_fps{0.0};
    std::size_t m_read{0};
    std::size_t m_delivered{0};
    emslam::stereo::StereoRectifier m_rectifier;
    mrpt::img::TStereoCamera m_output_camera;
};

}  // namespace emslam::hwdrivers
