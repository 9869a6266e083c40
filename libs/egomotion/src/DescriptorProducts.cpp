// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/egomotion/DescriptorProducts.h>
#include <emslam/util/CpuDispatch.h>

#include <algorithm>
#include <cstddef>
#include <cstring>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define EMSLAM_DESCRIPTOR_PRODUCTS_AVX2 1
#include <immintrin.h>
#endif

namespace emslam::egomotion
{
namespace
{
/** Columns of C^T per panel: two 8-float registers. */
constexpr Eigen::Index PANEL = 16;

#ifdef EMSLAM_DESCRIPTOR_PRODUCTS_AVX2
/** Rows of P per step: 6 x 2 accumulators + 2 panel loads + 1 broadcast
 * fill the 16 AVX registers. */
constexpr Eigen::Index ROWS = 6;

/** S(i, j0 .. j0+15) for every row i of P, from one panel (dim x 16, k-major)
 * of C^T: each step of k adds P(i, k) times the panel's row k. */
__attribute__((target("avx2,fma"))) void panelTimesRows(
    const float* panel,
    Eigen::Index width,  // columns of the panel that are real (<= PANEL)
    const float* p,
    Eigen::Index rows,
    Eigen::Index dim,
    float* s,
    Eigen::Index s_stride)
{
    for (Eigen::Index i = 0; i < rows; i += ROWS)
    {
        const Eigen::Index n = std::min(ROWS, rows - i);
        // Missing rows of the last step repeat the last real row (not stored).
        const float* r[ROWS];
        for (Eigen::Index k = 0; k < ROWS; ++k)
        {
            r[k] = p + (i + std::min(k, n - 1)) * dim;
        }
        const float *r0 = r[0], *r1 = r[1], *r2 = r[2], *r3 = r[3], *r4 = r[4], *r5 = r[5];
        __m256 a00 = _mm256_setzero_ps(), a01 = a00, a10 = a00, a11 = a00, a20 = a00, a21 = a00,
               a30 = a00, a31 = a00, a40 = a00, a41 = a00, a50 = a00, a51 = a00;
        const float* c = panel;
        for (Eigen::Index k = 0; k < dim; ++k, c += PANEL)
        {
            const __m256 c0 = _mm256_loadu_ps(c), c1 = _mm256_loadu_ps(c + 8);
            __m256 b = _mm256_broadcast_ss(r0 + k);
            a00 = _mm256_fmadd_ps(b, c0, a00);
            a01 = _mm256_fmadd_ps(b, c1, a01);
            b = _mm256_broadcast_ss(r1 + k);
            a10 = _mm256_fmadd_ps(b, c0, a10);
            a11 = _mm256_fmadd_ps(b, c1, a11);
            b = _mm256_broadcast_ss(r2 + k);
            a20 = _mm256_fmadd_ps(b, c0, a20);
            a21 = _mm256_fmadd_ps(b, c1, a21);
            b = _mm256_broadcast_ss(r3 + k);
            a30 = _mm256_fmadd_ps(b, c0, a30);
            a31 = _mm256_fmadd_ps(b, c1, a31);
            b = _mm256_broadcast_ss(r4 + k);
            a40 = _mm256_fmadd_ps(b, c0, a40);
            a41 = _mm256_fmadd_ps(b, c1, a41);
            b = _mm256_broadcast_ss(r5 + k);
            a50 = _mm256_fmadd_ps(b, c0, a50);
            a51 = _mm256_fmadd_ps(b, c1, a51);
        }
        alignas(32) float out[ROWS][PANEL];
        _mm256_store_ps(out[0], a00);
        _mm256_store_ps(out[0] + 8, a01);
        _mm256_store_ps(out[1], a10);
        _mm256_store_ps(out[1] + 8, a11);
        _mm256_store_ps(out[2], a20);
        _mm256_store_ps(out[2] + 8, a21);
        _mm256_store_ps(out[3], a30);
        _mm256_store_ps(out[3] + 8, a31);
        _mm256_store_ps(out[4], a40);
        _mm256_store_ps(out[4] + 8, a41);
        _mm256_store_ps(out[5], a50);
        _mm256_store_ps(out[5] + 8, a51);
        for (Eigen::Index k = 0; k < n; ++k)
        {
            std::copy(out[k], out[k] + width, s + (i + k) * s_stride);
        }
    }
}

bool cpuHasAvx2Fma()
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}
#endif
/** Lanes of one dot product: element k goes to lane k % 8. A GCC vector:
 * one AVX register in the AVX2 compilation, two SSE registers in the
 * baseline's, the same arithmetic lane by lane. */
constexpr int LANES = 8;
typedef float Lanes __attribute__((vector_size(LANES * sizeof(float))));

/** Σ of the eight lanes and the tail, in a fixed tree. */
inline float laneSum(const float* s, float tail)
{
    return (((s[0] + s[4]) + (s[1] + s[5])) + ((s[2] + s[6]) + (s[3] + s[7]))) + tail;
}

/** out[k] = p . c[rows[k]], four rows at a time so that four independent
 * sums are in flight. Inlined into a baseline and an AVX2 function: both do
 * the same multiplications and additions in the same order. */
[[gnu::always_inline]] inline void dotRowsBody(
    const float* p,
    const float* c,
    const std::uint32_t* rows,
    std::size_t n,
    Eigen::Index dim,
    float* out)
{
    const Eigen::Index full = dim - dim % LANES;
    float lanes[4][LANES];
    std::size_t k = 0;
    while (k < n)
    {
        const std::size_t m = std::min<std::size_t>(4, n - k);
        // Rows past the last real one repeat it (not stored).
        const float* r[4];
        for (std::size_t q = 0; q < 4; ++q)
        {
            r[q] = c + rows[k + std::min(q, m - 1)] * dim;
        }
        Lanes s0 = {}, s1 = {}, s2 = {}, s3 = {};
        for (Eigen::Index d = 0; d < full; d += LANES)
        {
            Lanes a, b0, b1, b2, b3;
            std::memcpy(&a, p + d, sizeof a);
            std::memcpy(&b0, r[0] + d, sizeof b0);
            std::memcpy(&b1, r[1] + d, sizeof b1);
            std::memcpy(&b2, r[2] + d, sizeof b2);
            std::memcpy(&b3, r[3] + d, sizeof b3);
            s0 += a * b0;
            s1 += a * b1;
            s2 += a * b2;
            s3 += a * b3;
        }
        std::memcpy(lanes[0], &s0, sizeof s0);
        std::memcpy(lanes[1], &s1, sizeof s1);
        std::memcpy(lanes[2], &s2, sizeof s2);
        std::memcpy(lanes[3], &s3, sizeof s3);
        for (std::size_t q = 0; q < m; ++q)
        {
            float tail = 0;
            for (Eigen::Index d = full; d < dim; ++d)
            {
                tail += p[d] * r[q][d];
            }
            out[k + q] = laneSum(lanes[q], tail);
        }
        k += m;
    }
}

// dotRowsBody() compiled for the baseline and for AVX2 (util/CpuDispatch.h).
#define EMSLAM_DOT_ROWS(SUFFIX, TARGET)                                           \
    TARGET void dotRows##SUFFIX(                                                  \
        const float* p, const float* c, const std::uint32_t* rows, std::size_t n, \
        Eigen::Index dim, float* out)                                             \
    {                                                                             \
        dotRowsBody(p, c, rows, n, dim, out);                                     \
    }
EMSLAM_DOT_ROWS(Baseline, )
EMSLAM_DOT_ROWS(Avx2, EMSLAM_TARGET_AVX2)
#undef EMSLAM_DOT_ROWS
}  // namespace

bool DescriptorProducts::vectorized()
{
#ifdef EMSLAM_DESCRIPTOR_PRODUCTS_AVX2
    static const bool has = cpuHasAvx2Fma();
    return has;
#else
    return false;
#endif
}

DescriptorProducts::DescriptorProducts(
    const float* c, Eigen::Index rows, Eigen::Index dim, Kernel kernel)
    : m_c(c), m_rows(rows), m_dim(dim)
{
    if (kernel == Kernel::Portable || !vectorized() || rows <= 0 || dim <= 0)
    {
        return;
    }
    // Panel q holds rows q*16 .. q*16+15 of C as columns, k-major, zero padded.
    const Eigen::Index panels = (rows + PANEL - 1) / PANEL;
    m_panels.assign(static_cast<std::size_t>(panels * dim * PANEL), 0.0f);
    for (Eigen::Index j = 0; j < rows; ++j)
    {
        float* dst = m_panels.data() + (j / PANEL) * dim * PANEL + (j % PANEL);
        const float* src = c + j * dim;
        for (Eigen::Index k = 0; k < dim; ++k)
        {
            dst[k * PANEL] = src[k];
        }
    }
}

void DescriptorProducts::multiply(const float* p, Eigen::Index rows, RowMajorMatrix& s) const
{
    s.resize(rows, m_rows);
    if (rows == 0 || m_rows == 0)
    {
        return;
    }
#ifdef EMSLAM_DESCRIPTOR_PRODUCTS_AVX2
    if (!m_panels.empty())
    {
        // Panel by panel: one panel (dim x 16 floats) stays in L1 while the
        // rows of P stream past it.
        for (Eigen::Index j0 = 0; j0 < m_rows; j0 += PANEL)
        {
            panelTimesRows(
                m_panels.data() + (j0 / PANEL) * m_dim * PANEL, std::min(PANEL, m_rows - j0), p,
                rows, m_dim, s.data() + j0, m_rows);
        }
        return;
    }
#endif
    using ConstMap = Eigen::Map<const RowMajorMatrix>;
    s.noalias() = ConstMap(p, rows, m_dim) * ConstMap(m_c, m_rows, m_dim).transpose();
}

void DescriptorProducts::dotRows(
    const float* p,
    const float* c,
    const std::uint32_t* rows,
    std::size_t n,
    Eigen::Index dim,
    float* out)
{
    if (util::avx2Enabled())
    {
        dotRowsAvx2(p, c, rows, n, dim, out);
    }
    else
    {
        dotRowsBaseline(p, c, rows, n, dim, out);
    }
}

}  // namespace emslam::egomotion
