// SPDX-License-Identifier: BSD-3-Clause
#include "StereoKeyCheck.h"

#include <emslam/stereo/SparseStereoMatcher.h>
#include <emslam/stereo/StereoCalibration.h>
#include <emslam/util/CpuDispatch.h>

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#if EMSLAM_HAVE_AVX2_PATHS
#include <immintrin.h>
#endif

namespace emslam::stereo
{
namespace
{
constexpr int PREFILTER_CAP = 31;

/** SAD costs of the disparities d = d_hi - j (j = 0 .. n-1) between the
 * block of `a` centred at column `ua` and the blocks of `b` centred at
 * ua + sign * d, rows v-h .. v+h, of two prefiltered images (values in
 * [0, 2 PREFILTER_CAP]), `first_col_b` the centre column in `b` of j = 0.
 * Written so that the inner loops run over contiguous pixels of `b` in 8-bit
 * lanes (the compiler vectorises them): a difference is at most 62, so four
 * of them add up in 8 bits before being widened into the 16-bit costs. The
 * portable path; blockCosts() runs register-blocked kernels where it can. */
void blockCostsPortable(
    const cv::Mat& a,
    const cv::Mat& b,
    int ua,
    int v,
    int h,
    int first_col_b,
    int n,
    std::uint16_t* cost)
{
    constexpr int GROUP = 4;  // 4 * 62 < 256
    static_assert(GROUP * 2 * PREFILTER_CAP < 256, "8-bit partial sums overflow");
    thread_local std::vector<std::uint8_t> partial;
    partial.resize(static_cast<std::size_t>(n));
    std::uint8_t* part = partial.data();
    std::fill(cost, cost + n, std::uint16_t{0});
    for (int r = v - h; r <= v + h; ++r)
    {
        const std::uint8_t* ra = a.ptr<std::uint8_t>(r);
        const std::uint8_t* rb = b.ptr<std::uint8_t>(r);
        for (int c0 = -h; c0 <= h; c0 += GROUP)
        {
            std::fill(part, part + n, std::uint8_t{0});
            for (int c = c0; c < std::min(c0 + GROUP, h + 1); ++c)
            {
                const std::uint8_t va = ra[ua + c];
                const std::uint8_t* pb = rb + first_col_b + c;
                for (int j = 0; j < n; ++j)
                {
                    part[j] = static_cast<std::uint8_t>(
                        part[j] + (std::max(va, pb[j]) - std::min(va, pb[j])));
                }
            }
            for (int j = 0; j < n; ++j)
            {
                cost[j] = static_cast<std::uint16_t>(cost[j] + part[j]);
            }
        }
    }
}

#if EMSLAM_HAVE_AVX2_PATHS
/** blockCosts() of the 32 disparities j0 .. j0+31 on AVX2, their 16-bit
 * costs in two registers over the whole block (the portable loop reads and
 * writes them once per group of columns). Integer arithmetic: the same
 * costs. */
EMSLAM_TARGET_AVX2 void blockCosts32(
    const cv::Mat& a,
    const cv::Mat& b,
    int ua,
    int v,
    int h,
    int first_col_b,
    int j0,
    std::uint16_t* cost)
{
    constexpr int GROUP = 4;  // 4 * 62 < 256, as the baseline
    __m256i lo = _mm256_setzero_si256(), hi = _mm256_setzero_si256();
    for (int r = v - h; r <= v + h; ++r)
    {
        const std::uint8_t* ra = a.ptr<std::uint8_t>(r) + ua;
        const std::uint8_t* rb = b.ptr<std::uint8_t>(r) + first_col_b + j0;
        for (int c0 = -h; c0 <= h; c0 += GROUP)
        {
            __m256i part = _mm256_setzero_si256();
            for (int c = c0; c < std::min(c0 + GROUP, h + 1); ++c)
            {
                const __m256i va = _mm256_set1_epi8(static_cast<char>(ra[c]));
                const __m256i vb = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(rb + c));
                const __m256i diff =
                    _mm256_or_si256(_mm256_subs_epu8(va, vb), _mm256_subs_epu8(vb, va));
                part = _mm256_add_epi8(part, diff);
            }
            lo = _mm256_add_epi16(lo, _mm256_cvtepu8_epi16(_mm256_castsi256_si128(part)));
            hi = _mm256_add_epi16(hi, _mm256_cvtepu8_epi16(_mm256_extracti128_si256(part, 1)));
        }
    }
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(cost + j0), lo);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(cost + j0 + 16), hi);
}

/** blockCosts32() for 16 disparities, in 128-bit registers: SSE2, the
 * x86-64 baseline's own register-blocked kernel (and AVX2's for 16 to 31
 * disparities). */
void blockCosts16(
    const cv::Mat& a,
    const cv::Mat& b,
    int ua,
    int v,
    int h,
    int first_col_b,
    int j0,
    std::uint16_t* cost)
{
    constexpr int GROUP = 4;  // 4 * 62 < 256, as the baseline
    const __m128i zero = _mm_setzero_si128();
    __m128i lo = zero, hi = zero;
    for (int r = v - h; r <= v + h; ++r)
    {
        const std::uint8_t* ra = a.ptr<std::uint8_t>(r) + ua;
        const std::uint8_t* rb = b.ptr<std::uint8_t>(r) + first_col_b + j0;
        for (int c0 = -h; c0 <= h; c0 += GROUP)
        {
            __m128i part = zero;
            for (int c = c0; c < std::min(c0 + GROUP, h + 1); ++c)
            {
                const __m128i va = _mm_set1_epi8(static_cast<char>(ra[c]));
                const __m128i vb = _mm_loadu_si128(reinterpret_cast<const __m128i*>(rb + c));
                part =
                    _mm_add_epi8(part, _mm_or_si128(_mm_subs_epu8(va, vb), _mm_subs_epu8(vb, va)));
            }
            lo = _mm_add_epi16(lo, _mm_unpacklo_epi8(part, zero));
            hi = _mm_add_epi16(hi, _mm_unpackhi_epi8(part, zero));
        }
    }
    _mm_storeu_si128(reinterpret_cast<__m128i*>(cost + j0), lo);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(cost + j0 + 8), hi);
}

/** Calls kernel(j0) on blocks of `width` disparities that cover 0 .. n-1,
 * the last one ending at n (overlapping the one before: the same costs
 * computed twice), if n >= width and every load of `width` bytes from
 * column first_col_b + c + j0 (|c| <= h) stays in the row of `cols`
 * pixels. Returns whether it did. */
template <typename Kernel>
bool coverByBlocks(int n, int width, int first_col_b, int h, int cols, const Kernel& kernel)
{
    if (n < width || first_col_b + h + n > cols)
    {
        return false;
    }
    for (int j0 = 0; j0 < n - width; j0 += width)
    {
        kernel(j0);
    }
    kernel(n - width);
    return true;
}
#endif

/** The SAD costs of blockCostsPortable(), by the widest register-blocked
 * kernel the CPU runs (util/CpuDispatch.h): 32 disparities per block on
 * AVX2, 16 on SSE2; what no block covers, by the portable loop. Integer
 * arithmetic: every path gives the same costs. */
void blockCosts(
    const cv::Mat& a,
    const cv::Mat& b,
    int ua,
    int v,
    int h,
    int first_col_b,
    int n,
    std::uint16_t* cost)
{
#if EMSLAM_HAVE_AVX2_PATHS
    const auto block = [&](auto kernel)
    { return [&, kernel](int j0) { kernel(a, b, ua, v, h, first_col_b, j0, cost); }; };
    if ((util::avx2Enabled() &&
         coverByBlocks(n, 32, first_col_b, h, b.cols, block(blockCosts32))) ||
        coverByBlocks(n, 16, first_col_b, h, b.cols, block(blockCosts16)))
    {
        return;
    }
#endif
    blockCostsPortable(a, b, ua, v, h, first_col_b, n, cost);
}

/** Sums over a block of the intensities that refineByGradient() needs at
 * one whole-pixel shift x0, exact in integers. With the right image sampled
 * between columns k - 1 and k (k = u + c - x0, weight a on k - 1):
 *   R(a) = R0 + a R1,          R0 = R[k],  R1 = R[k-1] - R[k],
 *   g(a) = -(D0 + a D1) / 2,   D0 = R[k+1] - R[k-1],
 *                              D1 = (R[k] - R[k-2]) - D0,
 * so every sum of refineByGradient() is a polynomial in a of these. */
struct ShiftSums
{
    int l = 0, r0 = 0, r1 = 0, d0 = 0, d1 = 0;
    int l_d0 = 0, l_d1 = 0, r0_d0 = 0, r0_d1 = 0, r1_d0 = 0, r1_d1 = 0;
    int d0_d0 = 0, d0_d1 = 0, d1_d1 = 0;
};

/** ShiftSums of the block at (u, v), half size h, right image shifted by x0.
 * Values below 2^8 and differences below 2^10: every sum of at most 15 x 15
 * products fits in 32 bits. */
ShiftSums shiftSums(const cv::Mat& left, const cv::Mat& right, int u, int v, int h, int x0)
{
    ShiftSums s;
    for (int r = v - h; r <= v + h; ++r)
    {
        const std::uint8_t* pl = left.ptr<std::uint8_t>(r) + u;
        const std::uint8_t* pr = right.ptr<std::uint8_t>(r) + u - x0;
        for (int c = -h; c <= h; ++c)
        {
            const int l = pl[c], rk = pr[c];
            const int r1 = pr[c - 1] - rk;
            const int d0 = pr[c + 1] - pr[c - 1];
            const int d1 = (rk - pr[c - 2]) - d0;
            s.l += l;
            s.r0 += rk;
            s.r1 += r1;
            s.d0 += d0;
            s.d1 += d1;
            s.l_d0 += l * d0;
            s.l_d1 += l * d1;
            s.r0_d0 += rk * d0;
            s.r0_d1 += rk * d1;
            s.r1_d0 += r1 * d0;
            s.r1_d1 += r1 * d1;
            s.d0_d0 += d0 * d0;
            s.d0_d1 += d0 * d1;
            s.d1_d1 += d1 * d1;
        }
    }
    return s;
}

/** Gauss-Newton on the zero-mean sum of squared differences of the raw
 * intensities, R linearly interpolated: the disparity near `d` that aligns
 * the two blocks best, free of the pixel-locking of a fit to integer costs.
 * Returns `d` unchanged if the block has no horizontal texture or the
 * iteration leaves [d - 1, d + 1]. The block's sums are exact integers
 * (ShiftSums), computed again only when the whole-pixel shift changes. */
double refineByGradient(const cv::Mat& left, const cv::Mat& right, int u, int v, int h, double d)
{
    const double n = (2 * h + 1) * (2 * h + 1);
    double x = d;
    int x0_sums = std::numeric_limits<int>::min();
    ShiftSums s;
    for (int it = 0; it < 4; ++it)
    {
        const double x0 = std::floor(x), a = x - x0;
        const int ix0 = static_cast<int>(x0);
        if (ix0 != x0_sums)
        {
            // Right columns k - 2 .. k + 1 for k = u + c - x0, c in [-h, h].
            if (u - h - ix0 - 2 < 0 || u + h - ix0 + 1 >= right.cols)
            {
                return d;
            }
            s = shiftSums(left, right, u, v, h, ix0);
            x0_sums = ix0;
        }
        const double sl = s.l, sr = s.r0 + a * s.r1;
        const double sg = -0.5 * (s.d0 + a * s.d1);
        const double slg = -0.5 * (s.l_d0 + a * s.l_d1);
        const double srg = -0.5 * (s.r0_d0 + a * (s.r0_d1 + s.r1_d0) + a * a * s.r1_d1);
        const double sgg = 0.25 * (s.d0_d0 + 2 * a * s.d0_d1 + a * a * s.d1_d1);
        // Residual e = (L - mean L) - (R - mean R); de/dx = -(g - mean g).
        const double gg = sgg - sg * sg / n;
        if (gg < 1e-6)
        {
            return d;
        }
        const double eg = (slg - sl * sg / n) - (srg - sr * sg / n);
        x += eg / gg;
        if (std::abs(x - d) > 1.0)
        {
            return d;
        }
    }
    return x;
}

int argMin(const std::uint16_t* cost, int n)
{
    return static_cast<int>(std::min_element(cost, cost + n) - cost);
}

/** The smallest of cost[0 .. n-1] (65535 if n <= 0): a loop without an early
 * exit, which the compiler vectorises. */
int minCost(const std::uint16_t* cost, int n)
{
    std::uint16_t m = std::numeric_limits<std::uint16_t>::max();
    for (int j = 0; j < n; ++j)
    {
        m = std::min(m, cost[j]);
    }
    return m;
}
}  // namespace

void SparseStereoMatcher::TParameters::validate() const
{
    requireStereo(
        num_disparities >= 3 && num_disparities <= 4096, "num_disparities / image_scale",
        num_disparities, "in [3, 4096] at full resolution");
    requireStereo(
        min_disparity >= -1000 && min_disparity <= 1000, "min_disparity", min_disparity,
        "in [-1000, 1000]");
    // 15 x 15 x 62 (the largest prefiltered difference) fits in 16 bits.
    requireStereo(
        block_size >= 3 && block_size <= 15 && block_size % 2 == 1, "sparse_block_size", block_size,
        "odd, in [3, 15]");
    requireStereo(
        uniqueness_ratio >= 0 && uniqueness_ratio < 100, "uniqueness_ratio", uniqueness_ratio,
        "in [0, 100) for the sparse matcher");
    requireStereo(lr_max_diff <= 1024, "lr_max_diff", lr_max_diff, "<= 1024 (< 0: off)");
    requireStereo(min_range >= 0 && min_range < 10000, "min_range", min_range, "in [0, 10000) m");
    requireStereo(
        max_range > min_range && max_range <= 10000, "max_range", max_range,
        "in (min_range, 10000] m");
}

SparseStereoMatcher::TParameters SparseStereoMatcher::fromStereo(
    const StereoMatcher::TParameters& p)
{
    TParameters s;
    const double scale = p.image_scale > 0 ? p.image_scale : 1.0;
    const int nd = ((p.num_disparities + 15) / 16) * 16;  // what SGBM searches
    s.num_disparities = static_cast<int>(std::ceil(nd / scale));
    s.min_disparity = static_cast<int>(std::floor(p.min_disparity / scale));
    s.block_size = p.sparse_block_size;
    s.uniqueness_ratio = std::min(p.uniqueness_ratio, 99);
    s.lr_max_diff = p.lr_max_diff;
    s.min_range = p.min_range;
    s.max_range = p.max_range;
    s.subpixel = p.subpixel;
    return s;
}

SparseStereoMatcher::SparseStereoMatcher(const TParameters& p) : m_params(p)
{
    m_params.validate();
}

cv::Mat SparseStereoMatcher::prefilter(const cv::Mat& gray)
{
    ASSERTMSG_(gray.type() == CV_8UC1, "Stereo: the sparse matcher needs 8-bit gray images");
    cv::Mat dx;
    cv::Sobel(gray, dx, CV_16S, 1, 0, 3, 1, 0, cv::BORDER_REPLICATE);
    cv::Mat out(gray.size(), CV_8UC1);
    for (int r = 0; r < gray.rows; ++r)
    {
        const short* s = dx.ptr<short>(r);
        std::uint8_t* o = out.ptr<std::uint8_t>(r);
        for (int c = 0; c < gray.cols; ++c)
        {
            o[c] = static_cast<std::uint8_t>(
                std::clamp(static_cast<int>(s[c]), -PREFILTER_CAP, PREFILTER_CAP) + PREFILTER_CAP);
        }
    }
    return out;
}

double SparseStereoMatcher::disparityAt(const cv::Mat& lf, const cv::Mat& rf, int u, int v) const
{
    const int h = m_params.block_size / 2;
    if (v - h < 0 || v + h >= lf.rows || u - h < 0 || u + h >= lf.cols)
    {
        return -1;
    }
    // Right block centre u - d must keep the block inside the image.
    const int d_lo = std::max(m_params.min_disparity, u + h - (rf.cols - 1));
    const int d_hi = std::min(m_params.min_disparity + m_params.num_disparities - 1, u - h);
    const int n = d_hi - d_lo + 1;
    if (n < 3)
    {
        return -1;
    }
    thread_local std::vector<std::uint16_t> cost;
    cost.resize(static_cast<std::size_t>(n));
    // j = 0 is d_hi: the right block at u - d_hi, the leftmost.
    blockCosts(lf, rf, u, v, h, u - d_hi, n, cost.data());
    const int j_best = argMin(cost.data(), n);
    if (j_best == 0 || j_best == n - 1)
    {
        return -1;  // at an end of the range: the minimum may lie beyond it
    }
    const int c1 = cost[static_cast<std::size_t>(j_best)];
    // Uniqueness, as SGBM: any disparity more than 1 px away must cost more
    // than c1 * 100 / (100 - ratio), so the cheapest of them must.
    const int runner_up = std::min(
        minCost(cost.data(), j_best - 1), minCost(cost.data() + j_best + 2, n - j_best - 2));
    if (runner_up * (100 - m_params.uniqueness_ratio) <= c1 * 100)
    {
        return -1;
    }
    const int d_best = d_hi - j_best;
    // Costs at d - 1 and d + 1 (j grows as d shrinks).
    const double c_minus = cost[static_cast<std::size_t>(j_best + 1)];
    const double c_plus = cost[static_cast<std::size_t>(j_best - 1)];
    const double curv = c_minus + c_plus - 2.0 * c1;
    const double delta = curv > 0 ? (c_minus - c_plus) / (2.0 * curv) : 0.0;

    if (m_params.lr_max_diff >= 0)
    {
        // The right pixel's best match among left pixels ur + d'.
        const int ur = u - d_best;
        const int e_lo = std::max(m_params.min_disparity, h - ur);
        const int e_hi =
            std::min(m_params.min_disparity + m_params.num_disparities - 1, lf.cols - 1 - h - ur);
        const int m = e_hi - e_lo + 1;
        if (m < 1)
        {
            return -1;
        }
        thread_local std::vector<std::uint16_t> back;
        back.resize(static_cast<std::size_t>(m));
        // Here index k is d' = e_lo + k: the left block at ur + e_lo + k.
        blockCosts(rf, lf, ur, v, h, ur + e_lo, m, back.data());
        const int d_back = e_lo + argMin(back.data(), m);
        if (std::abs(d_back - d_best) > m_params.lr_max_diff)
        {
            return -1;
        }
    }
    return m_params.subpixel ? d_best + delta : d_best;
}

StereoFrame SparseStereoMatcher::compute(
    const cv::Mat& left_gray,
    const cv::Mat& right_gray,
    const mrpt::img::TStereoCamera& camera,
    const std::vector<PixelCoord>& pixels) const
{
    ASSERTMSG_(!left_gray.empty() && !right_gray.empty(), "Stereo: empty image");
    ASSERTMSG_(left_gray.size() == right_gray.size(), "Stereo: left/right image sizes differ");
    ASSERTMSG_(
        left_gray.type() == CV_8UC1 && right_gray.type() == CV_8UC1,
        "Stereo: the sparse matcher needs 8-bit gray images");
    ASSERTMSG_(
        left_gray.cols == static_cast<int>(camera.leftCamera.ncols) &&
            left_gray.rows == static_cast<int>(camera.leftCamera.nrows),
        mrpt::format(
            "Stereo: image size %dx%d differs from the calibration's %ux%u", left_gray.cols,
            left_gray.rows, camera.leftCamera.ncols, camera.leftCamera.nrows));
    validateStereoCamera(camera, "stereo calibration");

    StereoFrame f;
    f.camera = camera;
    f.intensity = left_gray.clone();  // the caller may reuse its image buffer
    f.valid = cv::Mat::zeros(left_gray.size(), CV_8UC1);
    const cv::Mat lf = prefilter(left_gray), rf = prefilter(right_gray);

    const auto& lc = camera.leftCamera;
    const double fx = lc.fx(), fy = lc.fy(), cx = lc.cx(), cy = lc.cy();
    const double doffs = camera.rightCamera.cx() - cx;  // as StereoMatcher::compute
    const double fb = fx * baselineOf(camera);
    f.points.reserve(pixels.size());
    f.pixels.reserve(pixels.size());
    for (const PixelCoord& p : pixels)
    {
        const int u = p.u, v = p.v;
        if (u >= left_gray.cols || v >= left_gray.rows)
        {
            continue;
        }
        double disp = disparityAt(lf, rf, u, v);
        if (disp <= 0)
        {
            continue;
        }
        if (m_params.subpixel)
        {
            disp = refineByGradient(left_gray, right_gray, u, v, m_params.block_size / 2, disp);
        }
        const double d = disp + doffs;
        const double z = d > 0.0 ? fb / d : -1.0;
        if (z < m_params.min_range || z > m_params.max_range)
        {
            continue;
        }
        f.valid.at<std::uint8_t>(v, u) = 255;
        f.points.emplace_back(
            static_cast<float>((u - cx) * z / fx), static_cast<float>((v - cy) * z / fy),
            static_cast<float>(z));
        f.pixels.push_back(p);
    }
    return f;
}

}  // namespace emslam::stereo
