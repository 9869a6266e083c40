// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace emslam::egomotion
{
/** The products S = P C^T of every row of P with every row of a fixed C
 * (descriptors, row-major, `dim` floats each): the similarity matrix of the
 * exhaustive matching, computed block of rows by block of rows.
 *
 * Why: that product is most of a loop closer's registration (thousands of
 * features on each side at full KITTI resolution), and the portable build
 * gives Eigen only SSE. On a CPU with AVX2 and FMA (asked at run time, the
 * build stays portable) an 8-wide kernel over C^T packed once in panels
 * computes it about 2.5x faster (doc/performance.md); elsewhere it is Eigen's
 * product, as before. The two differ by rounding only (a few 1e-7 on unit
 * vectors): each S(i, j) is the same dot product summed in another order.
 * \ingroup emslam_egomotion_grp \sa matchMutual */
class DescriptorProducts
{
public:
    /** Row-major float matrix: one descriptor per row. */
    using RowMajorMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

    /** Which product multiply() runs: the fastest this CPU has, or Eigen's
     * (what a CPU without AVX2 runs; for tests of that path). */
    enum class Kernel
    {
        Fastest,
        Portable
    };

    /** C: `rows` x `dim`, row-major; it must outlive this object. */
    DescriptorProducts(
        const float* c, Eigen::Index rows, Eigen::Index dim, Kernel kernel = Kernel::Fastest);

    /** S = P C^T for P (`rows` x dim, row-major); S is resized to rows x |C|. */
    void multiply(const float* p, Eigen::Index rows, RowMajorMatrix& s) const;

    /** Whether multiply() runs the AVX2 + FMA kernel on this CPU. */
    static bool vectorized();

    /** out[k] = p . c[rows[k]] for k < n: one descriptor `p` against chosen
     * rows of C (`dim` floats each, row-major), as the guided matching
     * compares a feature with the features near its prediction. Each dot
     * product is summed in eight lanes then in a fixed tree, four rows at a
     * time; compiled for the x86-64 baseline and for AVX2 (picked at run time,
     * util/CpuDispatch.h), which give the same bits. */
    static void dotRows(
        const float* p,
        const float* c,
        const std::uint32_t* rows,
        std::size_t n,
        Eigen::Index dim,
        float* out);

private:
    const float* m_c;
    Eigen::Index m_rows, m_dim;
    std::vector<float> m_panels;  //!< C^T in panels of columns (AVX2 kernel only)
};

}  // namespace emslam::egomotion
