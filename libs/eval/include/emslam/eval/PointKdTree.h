// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/math/KDTreeCapable.h>
#include <mrpt/math/TPoint3D.h>

#include <cstddef>
#include <vector>

namespace emslam::eval
{
/** A 3D point set with nearest-neighbour queries through MRPT's nanoflann
 * k-d tree (mrpt::math::KDTreeCapable), built on the first query.
 * \ingroup emslam_eval_grp */
class PointKdTree : public mrpt::math::KDTreeCapable<PointKdTree>
{
public:
    explicit PointKdTree(std::vector<mrpt::math::TPoint3Df> points) : m_points(std::move(points)) {}

    /** Index of the point nearest to `q` and its squared distance [m^2].
     * Throws if the set is empty. */
    std::size_t nearest(const mrpt::math::TPoint3Df& q, float& dist_sq) const
    {
        return kdTreeClosestPoint3D(q.x, q.y, q.z, dist_sq);
    }

    const std::vector<mrpt::math::TPoint3Df>& points() const { return m_points; }

    /** \name KDTreeCapable's interface
     * @{ */
    std::size_t kdtree_get_point_count() const { return m_points.size(); }
    float kdtree_get_pt(std::size_t i, int dim) const
    {
        const auto& p = m_points[i];
        return dim == 0 ? p.x : (dim == 1 ? p.y : p.z);
    }
    float kdtree_distance(const float* a, std::size_t i, std::size_t) const
    {
        const auto& p = m_points[i];
        const float dx = a[0] - p.x, dy = a[1] - p.y, dz = a[2] - p.z;
        return dx * dx + dy * dy + dz * dz;
    }
    template <class BBOX>
    bool kdtree_get_bbox(BBOX&) const
    {
        return false;
    }
    /** @} */

private:
    std::vector<mrpt::math::TPoint3Df> m_points;
};

}  // namespace emslam::eval
