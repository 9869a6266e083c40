// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/egomotion/DescriptorProducts.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <tuple>
#include <vector>

using emslam::egomotion::DescriptorProducts;

namespace
{
/** n random unit rows of `dim` floats (seeded), row-major. */
std::vector<float> unitRows(int n, int dim, unsigned seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<float> N(0.0f, 1.0f);
    std::vector<float> v(static_cast<std::size_t>(n * dim));
    for (int i = 0; i < n; ++i)
    {
        double norm2 = 0;
        for (int k = 0; k < dim; ++k)
        {
            const float x = N(rng);
            v[static_cast<std::size_t>(i * dim + k)] = x;
            norm2 += static_cast<double>(x) * x;
        }
        for (int k = 0; k < dim; ++k)
        {
            v[static_cast<std::size_t>(i * dim + k)] /= static_cast<float>(std::sqrt(norm2));
        }
    }
    return v;
}

/** Largest |S(i, j) - p_i . c_j| over every pair, the dot products in double. */
double largestError(
    const std::vector<float>& p,
    int np,
    const std::vector<float>& c,
    int nc,
    int dim,
    DescriptorProducts::Kernel kernel)
{
    const DescriptorProducts products(c.data(), nc, dim, kernel);
    DescriptorProducts::RowMajorMatrix s;
    products.multiply(p.data(), np, s);
    EXPECT_EQ(s.rows(), np);
    EXPECT_EQ(s.cols(), nc);
    double worst = 0;
    for (int i = 0; i < np; ++i)
    {
        for (int j = 0; j < nc; ++j)
        {
            double truth = 0;
            for (int k = 0; k < dim; ++k)
            {
                truth += static_cast<double>(p[static_cast<std::size_t>(i * dim + k)]) *
                         c[static_cast<std::size_t>(j * dim + k)];
            }
            worst = std::max(worst, std::abs(s(i, j) - truth));
        }
    }
    return worst;
}
}  // namespace

// Sizes off the kernel's blocks (6 rows, 16 columns) on both sides, the
// log-polar descriptor's 128 values and an odd short one: every product is
// the dot product to float rounding, by this CPU's fastest kernel and by the
// portable one.
TEST(DescriptorProducts, equalTheDotProductsAtEverySize)
{
    for (const auto& [np, nc, dim] : std::vector<std::tuple<int, int, int>>{
             {1, 1, 128}, {6, 16, 128}, {37, 23, 128}, {50, 97, 7}})
    {
        const auto p = unitRows(np, dim, 1), c = unitRows(nc, dim, 2);
        EXPECT_LT(largestError(p, np, c, nc, dim, DescriptorProducts::Kernel::Fastest), 2e-6)
            << np << " x " << nc << " x " << dim
            << (DescriptorProducts::vectorized() ? " (AVX2 kernel)" : " (Eigen)");
        EXPECT_LT(largestError(p, np, c, nc, dim, DescriptorProducts::Kernel::Portable), 2e-6)
            << np << " x " << nc << " x " << dim << " (Eigen)";
    }
}

// A row times itself is 1 (unit rows), and rows of P that are rows of C find
// themselves: the layout of S is row i of P, column j of C.
TEST(DescriptorProducts, placeEachProductAtItsRowAndColumn)
{
    const int n = 41, dim = 128;
    const auto c = unitRows(n, dim, 3);
    const DescriptorProducts products(c.data(), n, dim);
    DescriptorProducts::RowMajorMatrix s;
    products.multiply(c.data() + 5 * dim, n - 5, s);  // P = rows 5.. of C
    for (int i = 0; i < n - 5; ++i)
    {
        EXPECT_NEAR(s(i, i + 5), 1.0f, 1e-5f) << i;
        for (int j = 0; j < n; ++j)
        {
            if (j != i + 5)
            {
                EXPECT_LT(std::abs(s(i, j)), 0.6f) << i << ", " << j;  // random 128-d: |rho| ~ 0.09
            }
        }
    }
}

TEST(DescriptorProducts, emptySidesGiveAnEmptyMatrix)
{
    const auto c = unitRows(3, 8, 4);
    DescriptorProducts::RowMajorMatrix s;
    DescriptorProducts(c.data(), 3, 8).multiply(c.data(), 0, s);
    EXPECT_EQ(s.rows(), 0);
    EXPECT_EQ(s.cols(), 3);
    DescriptorProducts(c.data(), 0, 8).multiply(c.data(), 3, s);
    EXPECT_EQ(s.rows(), 3);
    EXPECT_EQ(s.cols(), 0);
}
