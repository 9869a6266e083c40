// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace emslam::sim
{
/** A seeded, procedurally generated grey-level texture (albedo in [0,255]),
 * square, power-of-two sized, sampled bilinearly with wrap-around (tiling) or
 * clamping (posters, doors stretched once over a surface).
 *
 * Kinds (the INI names): `noise` (multi-scale value noise), `bricks`, `tiles`,
 * `repetitive` (perfectly periodic tiles: the repetitive-texture case of the
 * paper's Fig. 14), `poster` (random rectangles and discs over noise), `wood`
 * (door panels: streaks), `gravel` (fine noise, ground), `bush` (high-contrast
 * blobs). Every kind carries multi-scale noise so that stereo finds gradient.
 * \ingroup emslam_sim_grp \sa World */
class ProceduralTexture
{
public:
    ProceduralTexture() = default;

    /** Generates a texture of `kind` with `size`x`size` texels (size: a power
     * of two >= 16). Throws std::invalid_argument naming the kind if unknown.
     * The same arguments give the same texture, so the last few are kept and
     * shared (their pixels are never written after generation): loading a
     * world again, as a configuration check does, costs no new textures. */
    static ProceduralTexture generate(const std::string& kind, std::uint64_t seed, int size = 256);

    /** True if `kind` names a known texture kind. */
    static bool isKnownKind(const std::string& kind);
    /** The known kinds, comma-separated (for error messages). */
    static std::string knownKinds();

    /** Bilinear sample at texel coordinates (s, t) (texel centres at integer
     * + 0.5), wrapping around the texture borders. */
    float sampleWrap(double s, double t) const;
    /** Bilinear sample at normalized coordinates (u, v) in [0,1], clamped. */
    float sampleClamp(double u, double v) const;
    /** Trilinear (mip-mapped) sample at texel coordinates (s, t), wrapping;
     * `footprint` is the pixel size in level-0 texels (<= 1: sampleWrap()). */
    float sampleWrapLod(double s, double t, double footprint) const;
    /** Trilinear (mip-mapped) sample at normalized (u, v), clamped;
     * `footprint` in level-0 texels. */
    float sampleClampLod(double u, double v, double footprint) const;

    /** Side length [texels]. */
    int size() const { return m_img.cols; }
    /** The texels, CV_32FC1. */
    const cv::Mat& image() const { return m_img; }

private:
    static ProceduralTexture generateNew(const std::string& kind, std::uint64_t seed, int size);
    static float bilinearWrap(const cv::Mat& m, int mask, double s, double t);
    static float bilinearClamp(const cv::Mat& m, double u, double v);
    void buildMipmaps();

    cv::Mat m_img;
    int m_mask{0};
    /** Mip levels 1.. (2x2 box averages), level k is size >> k. */
    std::vector<cv::Mat> m_mips;
};

}  // namespace emslam::sim
