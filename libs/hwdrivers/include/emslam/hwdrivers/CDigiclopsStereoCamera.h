// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <emslam/hwdrivers/PackedFrame.h>
#include <emslam/hwdrivers/SensorStatus.h>
#include <emslam/stereo/StereoFrontEnd.h>
#include <emslam/stereo/StereoMatcher.h>
#include <emslam/stereo/StereoRectifier.h>

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/Clock.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/img/TCamera.h>
#include <mrpt/img/TStereoCamera.h>
#include <mrpt/poses/CPose3D.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace emslam::hwdrivers
{
/** The Point Grey Digiclops trinocular stereo head of the paper (three
 * 640x480 cameras, 10 cm baseline, ~14 fps) as an MRPT sensor, through
 * libdc1394 (IEEE-1394 and USB IIDC cameras). Also works with other IIDC
 * multi-sensor heads that pack their images the same way (e.g. a 2-camera
 * Bumblebee-style head in a 16-bit mode).
 *
 * Per frame it de-interleaves the packed frame into the camera images
 * (PackedFrame.h), rectifies the horizontal pair with the INI calibration
 * (StereoRectifier; the third image is undistorted) and emits, all with the
 * frame's timestamp:
 * - a `CObservationStereoImages` labelled `sensorLabel`: the rectified
 *   left/right pair, `hasImageRight`, the rectified calibration, `cameraPose`
 *   = the configured left camera pose (the small rotation introduced by
 *   rectification is not applied to it);
 * - for 3-image layouts, a `CObservationImage` labelled `sensorLabel + "_THIRD"`:
 *   the third camera (undistorted intrinsics, `cameraPose` = left pose composed
 *   with LEFT2THIRD_POSE);
 * - if `compute_range_scan`, a `CObservation3DRangeScan` labelled
 *   `sensorLabel + "_3D"`, computed on-line by emslam::stereo::StereoFrontEnd
 *   with the [`stereo_section`] parameters.
 *
 * <b>Pixel layout assumptions.</b> The camera sends one packed frame per
 * trigger (`pixel_layout`):
 * - `rgb24`: the three 8-bit grey cameras travel as the R, G and B bytes of an
 *   RGB8 frame (pixel-interleaved, 3 bytes per pixel, no row padding). The
 *   default channel mapping (`channel_right = 0`, `channel_left = 1`,
 *   `channel_third = 2`: R = right, G = left, B = top) is Point Grey's usual
 *   packing; it is configurable because it differs between heads: check it
 *   once by covering one lens.
 * - `interleaved16`: two 8-bit cameras as the two bytes of each 16-bit pixel
 *   (byte 0 first in transfer order); no third image.
 * - `planar8`: 2 or 3 mono8 images stacked vertically in one tall frame.
 * Each camera image has the calibration's resolution; a frame whose size does
 * not match is rejected with a message giving both sizes. Colour heads that
 * send a Bayer mosaic per camera are not de-mosaiced: the images are used as
 * grey levels.
 *
 * initialize() opens the camera (by GUID, or the `camera_index`-th one found),
 * sets mode, frame rate, shutter / gain / exposure and starts DMA capture.
 * With no camera it throws a message naming the cause: no device found (and
 * whether the IEEE-1394 bus / USB is visible at all), no permission on the
 * device node, or a video mode / frame rate the camera does not support
 * (listing the supported ones). `emslam-grabber --list-devices` shows what
 * is connected.
 *
 * \code
 * [DIGICLOPS]
 * driver              = CDigiclopsStereoCamera
 * sensorLabel         = STEREO      // + STEREO_THIRD (third image), STEREO_3D (range scan)
 * process_rate        = 30          // [Hz] polling rate, above the camera's frame rate
 * camera_guid         = 0           // hexadecimal GUID (see --list-devices); 0: by index
 * camera_index        = 0           // the n-th camera found when camera_guid = 0
 * video_mode          = 640x480_RGB8  // WxH_CODING (MONO8, MONO16, RGB8, ...) or FORMAT7_0..7
 * framerate           = 15          // [fps] standard modes: the nearest IIDC rate >= this
 * iso_speed           = 400         // [Mb/s] 100 | 200 | 400 | 800
 * shutter             = -1          // raw register value, -1: automatic
 * gain                = -1          // raw register value, -1: automatic
 * exposure            = -1          // raw auto-exposure target, -1: automatic
 * dma_buffers         = 8           // frames in the DMA ring
 * pixel_layout        = rgb24       // rgb24 | interleaved16 | planar8 (see above)
 * planar_channels     = 3           // planar8 only: 2 or 3 images per frame
 * channel_left        = 1           // channel index of the left camera
 * channel_right       = 0           // channel index of the right camera
 * channel_third       = 2           // channel index of the third (top) camera (3-image layouts)
 * calibration_section = DIGICLOPS_CALIB  // prefix of the calibration sections below
 * rectify             = true        // rectify the pair and undistort the third image
 * rectify_alpha       = 0           // OpenCV free scaling (0: valid pixels only, 1: all pixels)
 * pose_x              = 0           // [m] left camera on the robot
 * pose_y              = 0           // [m]
 * pose_z              = 0           // [m]
 * pose_yaw_deg        = 0           // [deg]
 * pose_pitch_deg      = 0           // [deg]
 * pose_roll_deg       = 0           // [deg]
 * compute_range_scan  = false       // also emit a CObservation3DRangeScan (stereo front-end)
 * stereo_section      = StereoMatcher  // its parameters for the range scan
 *
 * ; Calibration (TStereoCamera INI form; raw, i.e. unrectified, cameras):
 * [DIGICLOPS_CALIB_LEFT]
 * rawlog-grabber-ignore = true      // for the stock rawlog-grabber: not a sensor
 * resolution = [640 480]
 * cx = 320
 * cy = 240
 * fx = 400
 * fy = 400
 * distortion_model = plumb_bob
 * dist = [0 0 0 0 0]
 * ; [DIGICLOPS_CALIB_RIGHT]: the same keys for the right camera
 * [DIGICLOPS_CALIB_LEFT2RIGHT_POSE]
 * rawlog-grabber-ignore = true
 * pose_quaternion = [0.10 0 0 1 0 0 0]   // x y z qr qx qy qz: right camera in the left frame
 * ; [DIGICLOPS_CALIB_THIRD]: the same keys for the third camera (3-image layouts only)
 * [DIGICLOPS_CALIB_LEFT2THIRD_POSE]
 * rawlog-grabber-ignore = true
 * pose_quaternion = [0 -0.10 0 1 0 0 0]  // third camera in the left frame
 * \endcode
 * \ingroup emslam_hwdrivers_grp \sa PackedFrameFormat, listDevices(), CSimulatedStereoCamera */
class CDigiclopsStereoCamera : public mrpt::hwdrivers::CGenericSensor, public SensorStatus
{
    DEFINE_GENERIC_SENSOR(CDigiclopsStereoCamera)

public:
    /** The sensor-specific INI keys and the calibration (see the class comment). */
    struct TParameters : public mrpt::config::CLoadableOptions
    {
        /** Reads the keys of section `s` and the calibration sections
         * `<calibration_section>_*`; throws naming the key or section. */
        void loadFromConfigFile(
            const mrpt::config::CConfigFileBase& c, const std::string& s) override;
        /** Writes the keys to `s` and the calibration to its sections. */
        void saveToConfigFile(
            mrpt::config::CConfigFileBase& c, const std::string& s) const override;
        /** Throws std::invalid_argument naming the key of an invalid value. */
        void validate() const;

        /** Camera GUID (hexadecimal; 0: choose by camera_index). (Default: 0) */
        std::uint64_t camera_guid{0};
        /** Index of the camera among those found, when camera_guid = 0. (Default: 0) */
        int camera_index{0};
        /** IIDC video mode, e.g. 640x480_RGB8, 640x480_MONO16, FORMAT7_0. (Default: 640x480_RGB8)
         */
        std::string video_mode{"640x480_RGB8"};
        /** Frame rate [fps]; standard modes use the nearest IIDC rate >= this. (Default: 15) */
        double framerate{15.0};
        /** ISO speed [Mb/s]: 100, 200, 400 or 800. (Default: 400) */
        int iso_speed{400};
        /** Shutter register value, -1: automatic. (Default: -1) */
        int shutter{-1};
        /** Gain register value, -1: automatic. (Default: -1) */
        int gain{-1};
        /** Auto-exposure target register value, -1: automatic. (Default: -1) */
        int exposure{-1};
        /** Frames in the DMA ring buffer. (Default: 8) */
        int dma_buffers{8};
        /** Packed layout: rgb24, interleaved16 or planar8. (Default: rgb24) */
        std::string pixel_layout{"rgb24"};
        /** planar8 only: images per frame, 2 or 3. (Default: 3) */
        int planar_channels{3};
        /** Channel of the left camera. (Default: 1) */
        int channel_left{1};
        /** Channel of the right camera. (Default: 0) */
        int channel_right{0};
        /** Channel of the third camera (3-image layouts). (Default: 2) */
        int channel_third{2};
        /** Prefix of the calibration sections. (Default: DIGICLOPS_CALIB) */
        std::string calibration_section{"DIGICLOPS_CALIB"};
        /** Rectify the pair and undistort the third image. (Default: true) */
        bool rectify{true};
        /** OpenCV free scaling of the rectification, [0, 1]. (Default: 0) */
        double rectify_alpha{0.0};
        /** Left camera pose on the robot: position [m]. (Default: 0) */
        ///@{
        double pose_x{0}, pose_y{0}, pose_z{0};
        ///@}
        /** Left camera pose on the robot: angles [deg]. (Default: 0) */
        ///@{
        double pose_yaw_deg{0}, pose_pitch_deg{0}, pose_roll_deg{0};
        ///@}
        /** Emit a CObservation3DRangeScan per frame. (Default: false) */
        bool compute_range_scan{false};
        /** Section of the StereoMatcher parameters. (Default: Stereo) */
        std::string stereo_section{"StereoMatcher"};

        /** Raw (unrectified) calibration of the pair, from the calibration sections. */
        mrpt::img::TStereoCamera stereo_camera;
        /** Raw calibration of the third camera (`[CALIBRATION_SECTION_THIRD]`, CALIBRATION_SECTION
         * = `calibration_section`). */
        mrpt::img::TCamera third_camera;
        /** Third camera in the raw left camera's frame (`[CALIBRATION_SECTION_LEFT2THIRD_POSE]`).
         */
        mrpt::poses::CPose3D T_left_third;
        /** Stereo matcher parameters (read only if compute_range_scan). */
        emslam::stereo::StereoMatcher::TParameters stereo;

        /** The packed-frame geometry these parameters describe. */
        PackedFrameFormat frameFormat() const;
    };

    CDigiclopsStereoCamera();
    ~CDigiclopsStereoCamera() override;

    /** Opens the camera and starts capture; throws naming the cause. */
    void initialize() override;
    /** Waits for the next frame, converts it and queues its observations. */
    void doProcess() override;

    /** Converts one packed frame into its observations (stereo pair, third
     * image, optional range scan), all stamped `t`: the hardware-free half of
     * doProcess(). Throws if the frame size does not match the format. */
    std::vector<mrpt::serialization::CSerializable::Ptr> convertFrame(
        const std::uint8_t* data, std::size_t size, mrpt::Clock::time_point t);

    /** The parameters loadConfig() read (or setParameters() set). */
    const TParameters& parameters() const { return m_params; }
    /** Sets the parameters directly (as loadConfig() would); for tests and tools. */
    void setParameters(const TParameters& p);

    std::size_t droppedFrames() const override { return m_dropped; }

protected:
    /** Reads TParameters from `section` of `cfg`; CGenericSensor::loadConfig() calls it. */
    void loadConfig_sensorSpecific(
        const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;

private:
    struct Device;  // libdc1394 handles (CDigiclopsStereoCamera_dc1394.cpp)
    void openDevice();
    void closeDevice();
    /** Grabs one frame (blocking); returns false if none arrived. */
    bool grabFrame();

    TParameters m_params;
    std::unique_ptr<Device> m_dev;
    emslam::stereo::StereoRectifier m_rectifier;
    cv::Mat m_third_map_x, m_third_map_y;
    std::unique_ptr<emslam::stereo::StereoFrontEnd> m_front_end;
    std::atomic<std::size_t> m_dropped{0};  // read by the grabber's status thread
};

}  // namespace emslam::hwdrivers
