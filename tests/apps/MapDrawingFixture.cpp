// SPDX-License-Identifier: BSD-3-Clause
#include "MapDrawingFixture.h"

namespace emslam::test
{
namespace
{
/** A rectangular loop in the horizontal plane at camera height (y = 0):
 * x in [x0, x1], z in [z0, z1], one pose every 0.25 m. */
emslam::io::TumTrajectory loop(double x0, double x1, double z0, double z1)
{
    emslam::io::TumTrajectory t;
    const double corners[5][2] = {{x0, z0}, {x1, z0}, {x1, z1}, {x0, z1}, {x0, z0}};
    double time = 0;
    for (int k = 0; k < 4; ++k)
    {
        for (double s = 0; s < 1.0; s += 0.05)
        {
            const double x = corners[k][0] + s * (corners[k + 1][0] - corners[k][0]);
            const double z = corners[k][1] + s * (corners[k + 1][1] - corners[k][1]);
            t.add(time, mrpt::poses::CPose3D(x, 0, z, 0, 0, 0));
            time += 0.1;
        }
    }
    return t;
}

void addPoint(emslam::slam::IntensityCloud& c, double x, double y, double z)
{
    c.points.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
    c.intensity.push_back(128);
}
}  // namespace

MapDrawingFixture::MapDrawingFixture()
{
    // Room: x in [-3, 3], z in [0, 10]; floor y = 1, ceiling y = -2.
    for (double x = -3; x <= 3.001; x += 0.1)
    {
        for (double z = 0; z <= 10.001; z += 0.1)
        {
            addPoint(cloud, x, 1.0, z);   // floor
            addPoint(cloud, x, -2.0, z);  // ceiling
        }
    }
    for (double y = -2; y <= 1.001; y += 0.1)
    {
        for (double z = 0; z <= 10.001; z += 0.1)
        {
            addPoint(cloud, -3, y, z);
            addPoint(cloud, 3, y, z);
        }
        for (double x = -3; x <= 3.001; x += 0.1)
        {
            addPoint(cloud, x, y, 0);
            addPoint(cloud, x, y, 10);
        }
    }
    egomotion = loop(-1.5, 1.5, 2, 8);
    slam = loop(-1.0, 1.0, 2.5, 7.5);
    ground_truth = loop(-2.0, 2.0, 1.5, 8.5);

    emslam::maps::WeightedPointCloud w;
    w.points = cloud.points;
    w.weights.assign(w.points.size(), 1.0f);
    entropy_map.insertWeightedCloud(w, mrpt::poses::CPose3D());
}

emslam::apps::MapDrawingContent MapDrawingFixture::content() const
{
    emslam::apps::MapDrawingContent c;
    c.cloud = &cloud;
    c.egomotion = &egomotion;
    c.slam = &slam;
    c.ground_truth = &ground_truth;
    c.entropy_map = &entropy_map;
    c.loops = &loops;
    return c;
}
}  // namespace emslam::test
