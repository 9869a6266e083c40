// SPDX-License-Identifier: BSD-3-Clause
#include "PoseEigen.h"

#include <emslam/egomotion/DppPoseEstimator.h>
#include <emslam/util/CpuDispatch.h>

#include <mrpt/core/exceptions.h>
#include <mrpt/math/CMatrixFixed.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace emslam::egomotion
{
namespace
{
using detail::expSO3;
using detail::fromPose;
using detail::Mat3;
using detail::Mat6;
using detail::toPose;
using detail::Vec3;
using detail::Vec6;

/** A point closer than this to its camera centre [m] defines no ray: Eq. 7
 * divides by its norm. Such pairs are left out of E (their term would not
 * depend on the pose anyway, since |R b| = |b|). */
constexpr double MIN_RAY_NORM = 1e-6;
/** Keeps the derivative of a norm finite where the norm vanishes (the term
 * itself is then 0, so this only decides which subgradient is used). */
constexpr double TINY = 1e-300;

Vec3 toVec(const mrpt::math::TPoint3D& p)
{
    return {p.x, p.y, p.z};
}

bool usable(const mrpt::math::TPoint3Df& p)
{
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
           double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z >= MIN_RAY_NORM * MIN_RAY_NORM;
}

/** The pairs of the problem, degenerate ones dropped, stored by
 * coordinate so that the loops over them vectorise: `columns` holds the n
 * values of ax, ay, az, bx, by, bz, 1/|a|, 1/|b| one after the other
 * (|R b| = |b|). With room for the terms of one evaluation. */
struct Pairs
{
    enum Column
    {
        AX,
        AY,
        AZ,
        BX,
        BY,
        BZ,
        INV_NA,
        INV_NB,
        COLUMNS
    };
    std::size_t n{0};
    std::vector<double> columns;
    /** Per pair: Dpp, then its gradient [t; w] (six arrays), of the last
     * evaluation. */
    mutable std::vector<double> term, grad[6];

    std::size_t size() const { return n; }
    double at(Column c, std::size_t i) const { return columns[c * n + i]; }
    Vec3 a(std::size_t i) const { return {at(AX, i), at(AY, i), at(AZ, i)}; }
    Vec3 b(std::size_t i) const { return {at(BX, i), at(BY, i), at(BZ, i)}; }
};

Pairs makePairs(
    const std::vector<mrpt::math::TPoint3Df>& a, const std::vector<mrpt::math::TPoint3Df>& b)
{
    ASSERT_EQUAL_(a.size(), b.size());
    std::vector<std::size_t> kept;
    for (std::size_t i = 0; i < a.size(); ++i)
    {
        if (usable(a[i]) && usable(b[i]))
        {
            kept.push_back(i);
        }
    }
    Pairs p;
    p.n = kept.size();
    p.columns.resize(Pairs::COLUMNS * p.n);
    for (std::size_t k = 0; k < p.n; ++k)
    {
        const auto& pa = a[kept[k]];
        const auto& pb = b[kept[k]];
        const double values[Pairs::COLUMNS] = {
            pa.x,
            pa.y,
            pa.z,
            pb.x,
            pb.y,
            pb.z,
            1.0 / Vec3(pa.x, pa.y, pa.z).norm(),
            1.0 / Vec3(pb.x, pb.y, pb.z).norm()};
        for (int c = 0; c < Pairs::COLUMNS; ++c)
        {
            p.columns[c * p.n + k] = values[c];
        }
    }
    p.term.resize(p.n);
    for (auto& g : p.grad)
    {
        g.resize(p.n);
    }
    return p;
}

/** (R, t) as the loops read it: R row by row, then t. */
std::array<double, 12> motionOf(const Mat3& R, const Vec3& t)
{
    return {R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2),
            R(2, 0), R(2, 1), R(2, 2), t.x(),   t.y(),   t.z()};
}

// The two loops below are written element by element with no sum, over
// arrays passed as restrict parameters, so that the compiler vectorises them
// (4 pairs per AVX2 instruction; GCC needs the restrict parameters to prove
// the arrays apart). The sums are the caller's, in a fixed order. With
// c = R b, q = a - t, u = q x c, v = (c + t) x a:
//   d1 = |u| / |c|,  d2 = |v| / |a|,  Dpp = d1 d2,
//   dd1/dt = (u x c) / (|u||c|),           dd2/dt = (a x v) / (|v||a|),
//   dd1/dw = -c x (q x u) / (|u||c|),      dd2/dw = c x (a x v) / (|v||a|),
// where w perturbs the rotation on the left (dc = w x c).

/** Dpp of each of the n pairs (`pairs`: Pairs::columns) at `motion`
 * (motionOf()) into e and, with GRADIENTS, its gradient with respect to t
 * (gt*) and to w (gw*); the gradient pointers are not read without. */
template <bool GRADIENTS>
[[gnu::always_inline]] inline void pairTerms(
    std::size_t n,
    const double* __restrict pairs,
    const double* __restrict motion,
    double* __restrict e,
    double* __restrict gtx,
    double* __restrict gty,
    double* __restrict gtz,
    double* __restrict gwx,
    double* __restrict gwy,
    double* __restrict gwz)
{
    const double *ax = pairs, *ay = ax + n, *az = ay + n, *bx = az + n, *by = bx + n, *bz = by + n,
                 *ina = bz + n, *inb = ina + n;
    const double r00 = motion[0], r01 = motion[1], r02 = motion[2], r10 = motion[3],
                 r11 = motion[4], r12 = motion[5], r20 = motion[6], r21 = motion[7],
                 r22 = motion[8], tx = motion[9], ty = motion[10], tz = motion[11];
    for (std::size_t i = 0; i < n; ++i)
    {
        const double cx = r00 * bx[i] + r01 * by[i] + r02 * bz[i];
        const double cy = r10 * bx[i] + r11 * by[i] + r12 * bz[i];
        const double cz = r20 * bx[i] + r21 * by[i] + r22 * bz[i];
        const double qx = ax[i] - tx, qy = ay[i] - ty, qz = az[i] - tz;
        const double ux = qy * cz - qz * cy, uy = qz * cx - qx * cz, uz = qx * cy - qy * cx;
        const double wx = cx + tx, wy = cy + ty, wz = cz + tz;
        const double vx = wy * az[i] - wz * ay[i], vy = wz * ax[i] - wx * az[i],
                     vz = wx * ay[i] - wy * ax[i];
        const double nu = std::sqrt(ux * ux + uy * uy + uz * uz);
        const double nv = std::sqrt(vx * vx + vy * vy + vz * vz);
        const double d1 = nu * inb[i], d2 = nv * ina[i];
        e[i] = d1 * d2;
        if constexpr (!GRADIENTS)
        {
            continue;
        }
        const double s1 = d2 * (inb[i] / std::max(nu, TINY));
        const double s2 = d1 * (ina[i] / std::max(nv, TINY));
        // u x c, a x v, q x u
        const double ucx = uy * cz - uz * cy, ucy = uz * cx - ux * cz, ucz = ux * cy - uy * cx;
        const double avx = ay[i] * vz - az[i] * vy, avy = az[i] * vx - ax[i] * vz,
                     avz = ax[i] * vy - ay[i] * vx;
        const double qux = qy * uz - qz * uy, quy = qz * ux - qx * uz, quz = qx * uy - qy * ux;
        gtx[i] = s1 * ucx + s2 * avx;
        gty[i] = s1 * ucy + s2 * avy;
        gtz[i] = s1 * ucz + s2 * avz;
        // -s1 c x (q x u) + s2 c x (a x v)
        gwx[i] = -s1 * (cy * quz - cz * quy) + s2 * (cy * avz - cz * avy);
        gwy[i] = -s1 * (cz * qux - cx * quz) + s2 * (cz * avx - cx * avz);
        gwz[i] = -s1 * (cx * quy - cy * qux) + s2 * (cx * avy - cy * avx);
    }
}

// Each loop compiled for the baseline and for AVX2 (util/CpuDispatch.h).
#define EMSLAM_DPP_KERNELS(SUFFIX, TARGET)                                                        \
    TARGET void pairEnergies##SUFFIX(const Pairs& p, const double* m)                             \
    {                                                                                             \
        pairTerms<false>(                                                                         \
            p.n, p.columns.data(), m, p.term.data(), nullptr, nullptr, nullptr, nullptr, nullptr, \
            nullptr);                                                                             \
    }                                                                                             \
    TARGET void pairGradients##SUFFIX(const Pairs& p, const double* m)                            \
    {                                                                                             \
        pairTerms<true>(                                                                          \
            p.n, p.columns.data(), m, p.term.data(), p.grad[0].data(), p.grad[1].data(),          \
            p.grad[2].data(), p.grad[3].data(), p.grad[4].data(), p.grad[5].data());              \
    }
EMSLAM_DPP_KERNELS(Baseline, )
EMSLAM_DPP_KERNELS(Avx2, EMSLAM_TARGET_AVX2)
#undef EMSLAM_DPP_KERNELS

/** The terms (and gradients, if asked) of every pair at (R, t) into
 * p.term (and p.grad). */
void evaluatePairs(const Pairs& p, const Mat3& R, const Vec3& t, bool gradients)
{
    const auto m = motionOf(R, t);
    const bool avx2 = util::avx2Enabled();
    if (gradients)
    {
        avx2 ? pairGradientsAvx2(p, m.data()) : pairGradientsBaseline(p, m.data());
    }
    else
    {
        avx2 ? pairEnergiesAvx2(p, m.data()) : pairEnergiesBaseline(p, m.data());
    }
}

/** Σ x[i] in four interleaved partial sums: a fixed order, whatever the
 * CPU, and four independent additions in flight. */
double sumOf(const std::vector<double>& x)
{
    double s[4] = {0, 0, 0, 0};
    const std::size_t n = x.size(), n4 = n - n % 4;
    for (std::size_t i = 0; i < n4; i += 4)
    {
        s[0] += x[i];
        s[1] += x[i + 1];
        s[2] += x[i + 2];
        s[3] += x[i + 3];
    }
    for (std::size_t i = n4; i < n; ++i)
    {
        s[i - n4] += x[i];
    }
    return (s[0] + s[1]) + (s[2] + s[3]);
}

/** E(R, t) of Eq. 4 with Dpp of Eq. 7; gradients as documented in the header. */
double energyGrad(const Pairs& p, const Mat3& R, const Vec3& t, Vec3* gt, Vec3* gw)
{
    evaluatePairs(p, R, t, gt != nullptr || gw != nullptr);
    for (int k = 0; k < 3; ++k)
    {
        if (gt)
        {
            (*gt)[k] = sumOf(p.grad[k]);
        }
        if (gw)
        {
            (*gw)[k] = sumOf(p.grad[3 + k]);
        }
    }
    return sumOf(p.term);
}

/** One conjugate-gradient run (Polak-Ribiere+, restarted when the direction
 * stops descending) over one block: the translation or the left rotation
 * vector. The line search is adaptive: it starts from the step length that
 * worked last time (`step`, kept across runs), doubles while the energy keeps
 * dropping and halves until it drops. Returns the new energy. */
double cgBlock(
    const Pairs& p,
    Mat3& R,
    Vec3& t,
    bool rotation,
    double e,
    int max_iters,
    double tolerance,
    double& step,
    int& evals)
{
    auto gradient = [&](Vec3& g)
    {
        ++evals;
        return rotation ? energyGrad(p, R, t, nullptr, &g) : energyGrad(p, R, t, &g, nullptr);
    };
    auto energyAt = [&](const Vec3& x)
    {
        ++evals;
        return rotation ? energyGrad(p, expSO3(x) * R, t, nullptr, nullptr)
                        : energyGrad(p, R, t + x, nullptr, nullptr);
    };
    auto apply = [&](const Vec3& x)
    {
        if (rotation)
        {
            R = expSO3(x) * R;
        }
        else
        {
            t += x;
        }
    };
    // Steps below this change nothing measurable (metres or radians).
    constexpr double MIN_STEP = 1e-12;

    Vec3 g;
    gradient(g);
    Vec3 d = -g;
    for (int it = 0; it < max_iters; ++it)
    {
        const double gn = g.norm();
        if (gn <= 0 || !std::isfinite(gn))
        {
            break;
        }
        if (d.dot(g) >= 0)
        {
            d = -g;  // restart on a non-descent direction
        }
        const Vec3 dir = d.normalized();
        double alpha = std::max(step, 1e3 * MIN_STEP);
        double e_new = energyAt(alpha * dir);
        if (e_new < e)
        {
            for (int k = 0; k < 40; ++k)
            {
                const double e2 = energyAt(2 * alpha * dir);
                if (!(e2 < e_new))
                {
                    break;
                }
                alpha *= 2;
                e_new = e2;
            }
        }
        else
        {
            while (!(e_new < e) && alpha > MIN_STEP)
            {
                alpha *= 0.5;
                e_new = energyAt(alpha * dir);
            }
            if (!(e_new < e))
            {
                break;  // no descent along d: a minimum for this block
            }
        }
        apply(alpha * dir);
        step = alpha;
        const double de = e - e_new;
        e = e_new;
        Vec3 g_new;
        gradient(g_new);
        const double beta = std::max(0.0, g_new.dot(g_new - g) / std::max(g.squaredNorm(), TINY));
        d = -g_new + beta * d;
        g = g_new;
        if (de <= tolerance * std::max(e, TINY))
        {
            break;
        }
    }
    return e;
}

/** The Gauss-Newton system of E at (R, t), each Dpp read as a squared
 * residual r² (it is a product of two distances): JᵀJ = Σ ∇r ∇rᵀ with
 * ∇r = ∇Dpp / (2 r), and ∇E = Σ ∇Dpp, over [t, w] (w the left rotation
 * vector). The exact Hessian of a product of distances is indefinite near
 * zero residuals. Returns E. */
double gaussNewtonSystem(const Pairs& p, const Mat3& R, const Vec3& t, Mat6& JtJ, Vec6& grad)
{
    JtJ.setZero();
    grad.setZero();
    evaluatePairs(p, R, t, true);
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        const double dpp = p.term[i];
        if (!(dpp > 1e-30))
        {
            continue;  // an exact fit: no gradient direction to learn from
        }
        Vec6 g;
        for (int k = 0; k < 6; ++k)
        {
            g[k] = p.grad[k][i];
        }
        grad += g;
        g /= 2.0 * std::sqrt(dpp);
        JtJ += g * g.transpose();
    }
    return sumOf(p.term);
}

/** Levenberg-Marquardt on the six parameters at once, on the system of
 * gaussNewtonSystem(): δ = −(H + λ diag H)⁻¹ ∇E with
 * H = 2 Σ ∇r ∇rᵀ, kept only when E drops. The alternating blocks above
 * move the translation and the rotation in turn; where the two trade off
 * (a turn in front of a wall: a small rotation about the vertical looks like
 * a sideways step) they zig-zag down the valley and stop short of its
 * minimum. Returns the new energy. */
double jointRefine(
    const Pairs& p, Mat3& R, Vec3& t, double e, int max_iters, double tolerance, int& evals)
{
    return detail::levenbergMarquardt(
        [&p](const Mat3& Rc, const Vec3& tc, Mat6& H, Vec6& g)
        {
            gaussNewtonSystem(p, Rc, tc, H, g);
            H *= 2.0;
        },
        [&p](const Mat3& Rc, const Vec3& tc) { return energyGrad(p, Rc, tc, nullptr, nullptr); }, R,
        t, e, max_iters, tolerance, evals);
}
}  // namespace

double DppPoseEstimator::dpp(
    const mrpt::math::TPoint3D& a, const mrpt::math::TPoint3D& b_hat, const mrpt::math::TPoint3D& t)
{
    const Vec3 va = toVec(a), vb = toVec(b_hat), vt = toVec(t);
    const Vec3 c = vb - vt;  // R b: the current point seen from its own centre
    const double na = va.norm(), nc = c.norm();
    if (na < MIN_RAY_NORM || nc < MIN_RAY_NORM)
    {
        return 0;  // no ray through a point at its camera centre
    }
    return (va - vt).cross(c).norm() / nc * vb.cross(va).norm() / na;
}

double DppPoseEstimator::energy(
    const std::vector<mrpt::math::TPoint3Df>& a,
    const std::vector<mrpt::math::TPoint3Df>& b,
    const mrpt::poses::CPose3D& T_prev_cur,
    std::array<double, 3>* grad_t,
    std::array<double, 3>* grad_w)
{
    const Pairs p = makePairs(a, b);
    Mat3 R;
    Vec3 t, gt, gw;
    fromPose(T_prev_cur, R, t);
    const double e = energyGrad(p, R, t, grad_t ? &gt : nullptr, grad_w ? &gw : nullptr);
    for (int k = 0; k < 3; ++k)
    {
        if (grad_t)
        {
            (*grad_t)[k] = gt[k];
        }
        if (grad_w)
        {
            (*grad_w)[k] = gw[k];
        }
    }
    return e;
}

bool DppPoseEstimator::covarianceAt(
    const std::vector<mrpt::math::TPoint3Df>& a,
    const std::vector<mrpt::math::TPoint3Df>& b,
    const mrpt::poses::CPose3D& T_prev_cur,
    mrpt::math::CMatrixDouble66& covariance)
{
    const Pairs p = makePairs(a, b);
    constexpr std::size_t DOF = 6;
    if (p.size() <= DOF)
    {
        return false;
    }
    Mat3 R;
    Vec3 t;
    fromPose(T_prev_cur, R, t);
    Mat6 JtJ;
    Vec6 grad;
    const double e = gaussNewtonSystem(p, R, t, JtJ, grad);
    const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(JtJ);
    if (llt.info() != Eigen::Success || !(e > 0))
    {
        return false;
    }
    // cov = σ² (JᵀJ)⁻¹ with σ² = E / (n − 6).
    const double sigma2 = e / static_cast<double>(p.size() - DOF);
    Eigen::Matrix<double, 6, 6> C = sigma2 * llt.solve(Eigen::Matrix<double, 6, 6>::Identity());
    // The rotation above perturbs on the left, exp(w) R; the rectifier's
    // actions on the right, R exp(θ): θ = Rᵀ w.
    Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Identity();
    J.block<3, 3>(3, 3) = R.transpose();
    C = J * C * J.transpose();
    if (!C.allFinite())
    {
        return false;
    }
    for (int r = 0; r < 6; ++r)
    {
        for (int c = 0; c < 6; ++c)
        {
            covariance(r, c) = 0.5 * (C(r, c) + C(c, r));
        }
    }
    return true;
}

mrpt::poses::CPose3D DppPoseEstimator::euclideanFit(
    const std::vector<mrpt::math::TPoint3Df>& a, const std::vector<mrpt::math::TPoint3Df>& b)
{
    const Pairs p = makePairs(a, b);
    ASSERTMSG_(p.size() >= 3, "euclideanFit needs at least 3 valid pairs");
    Vec3 ca = Vec3::Zero(), cb = Vec3::Zero();
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        ca += p.a(i);
        cb += p.b(i);
    }
    ca /= double(p.size());
    cb /= double(p.size());
    Mat3 H = Mat3::Zero();
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        H += (p.b(i) - cb) * (p.a(i) - ca).transpose();
    }
    const Eigen::JacobiSVD<Mat3> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 D = Mat3::Identity();
    // A reflection would fit mirrored data better; force a proper rotation.
    D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
    const Mat3 R = svd.matrixV() * D * svd.matrixU().transpose();
    return toPose(R, ca - R * cb);
}

DppPoseEstimator::Result DppPoseEstimator::estimate(
    const std::vector<mrpt::math::TPoint3Df>& a,
    const std::vector<mrpt::math::TPoint3Df>& b,
    const mrpt::poses::CPose3D& initial_guess) const
{
    const Pairs p = makePairs(a, b);
    ASSERTMSG_(p.size() >= 3, "DppPoseEstimator::estimate needs at least 3 valid pairs");
    Result res;
    Mat3 R;
    Vec3 t;
    fromPose(initial_guess, R, t);
    double e = energyGrad(p, R, t, nullptr, nullptr);
    res.evaluations = 1;
    if (m_params.euclidean_init)
    {
        // Keep whichever start is better: a good guess from the caller beats
        // a Euclidean fit spoiled by depth noise.
        Mat3 R0;
        Vec3 t0;
        fromPose(euclideanFit(a, b), R0, t0);
        const double e0 = energyGrad(p, R0, t0, nullptr, nullptr);
        ++res.evaluations;
        if (e0 < e)
        {
            R = R0;
            t = t0;
            e = e0;
        }
    }
    res.initial_energy = e;

    double step_t = 1e-2, step_w = 1e-3;  // first trial steps [m], [rad]
    for (int k = 0; k < m_params.max_alternations; ++k)
    {
        ++res.alternations;
        const double e_start = e;
        const double e_t = cgBlock(
            p, R, t, false, e, m_params.max_cg_iterations, m_params.tolerance, step_t,
            res.evaluations);
        const double e_w = cgBlock(
            p, R, t, true, e_t, m_params.max_cg_iterations, m_params.tolerance, step_w,
            res.evaluations);
        e = e_w;
        // Converged when neither block moved the energy.
        if (e_start - e <= m_params.tolerance * std::max(e_start, TINY))
        {
            break;
        }
    }
    if (m_params.joint_refinement)
    {
        e = jointRefine(p, R, t, e, m_params.max_alternations, m_params.tolerance, res.evaluations);
    }
    res.energy = e;
    res.T_prev_cur = toPose(R, t);
    res.has_covariance = covarianceAt(a, b, res.T_prev_cur, res.covariance);
    return res;
}

}  // namespace emslam::egomotion
