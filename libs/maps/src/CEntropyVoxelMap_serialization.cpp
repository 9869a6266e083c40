// SPDX-License-Identifier: BSD-3-Clause
// CEntropyVoxelMap: binary serialization.
#include <emslam/maps/CEntropyVoxelMap.h>

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/serialization/CArchive.h>

#include <utility>
#include <vector>

using emslam::CEntropyVoxelMap;

IMPLEMENTS_SERIALIZABLE(CEntropyVoxelMap, mrpt::maps::CMetricMap, emslam)

// Version 0 layout: genericMapParams; creation (cell_size f64, energy u8,
// dof i32); insertion (max_range f64, min_range f64, decimation i32); draw
// (max_cubes i32, min_cube_size f64); u32 observation count; per observation:
// the 12 upper entries of the 4x4 pose matrix (f64, row major, so the cells
// are recomputed bit-exactly), u32 point count, then x y z w (f32) per point.
// Histograms are rebuilt on load (IncrementalEntropyGrid::assignObservations()).
uint8_t CEntropyVoxelMap::serializeGetVersion() const
{
    return 0;
}

void CEntropyVoxelMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    out << genericMapParams;
    out << m_creation.cell_size << static_cast<uint8_t>(m_creation.energy)
        << static_cast<int32_t>(m_creation.dof);
    out << insertionOptions.max_range << insertionOptions.min_range
        << static_cast<int32_t>(insertionOptions.decimation);
    out << static_cast<int32_t>(drawOptions.max_cubes) << drawOptions.min_cube_size;
    out.WriteAs<uint32_t>(m_engine.observationCount());
    for (std::size_t i = 0; i < m_engine.observationCount(); i++)
    {
        const auto& cloud = m_engine.observationCloud(i);
        const auto T =
            m_engine.observationPose(i).getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
        for (int r = 0; r < 3; r++)
        {
            for (int c = 0; c < 4; c++)
            {
                out << T(r, c);
            }
        }
        out.WriteAs<uint32_t>(cloud.size());
        for (std::size_t j = 0; j < cloud.size(); j++)
        {
            const auto& p = cloud.points[j];
            out << p.x << p.y << p.z << cloud.weights[j];
        }
    }
}

void CEntropyVoxelMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    switch (version)
    {
        case 0:
        {
            in >> genericMapParams;
            TCreationOptions creation;
            in >> creation.cell_size;
            creation.energy = static_cast<emslam::maps::EnergyType>(in.ReadAs<uint8_t>());
            creation.dof = in.ReadAs<int32_t>();
            in >> insertionOptions.max_range >> insertionOptions.min_range;
            insertionOptions.decimation = in.ReadAs<int32_t>();
            drawOptions.max_cubes = in.ReadAs<int32_t>();
            in >> drawOptions.min_cube_size;
            creation.validate();
            insertionOptions.validate();
            drawOptions.validate();

            std::vector<emslam::maps::IncrementalEntropyGrid::PosedCloud> obs(
                in.ReadAs<uint32_t>());
            for (auto& o : obs)
            {
                mrpt::math::CMatrixDouble44 T = mrpt::math::CMatrixDouble44::Identity();
                for (int r = 0; r < 3; r++)
                {
                    for (int c = 0; c < 4; c++)
                    {
                        in >> T(r, c);
                    }
                }
                o.pose = mrpt::poses::CPose3D(T);
                const auto n = in.ReadAs<uint32_t>();
                o.cloud.points.resize(n);
                o.cloud.weights.resize(n);
                for (std::size_t j = 0; j < n; j++)
                {
                    auto& p = o.cloud.points[j];
                    in >> p.x >> p.y >> p.z >> o.cloud.weights[j];
                }
            }
            m_creation = creation;
            m_engine.assignObservations(
                creation.cell_size, emslam::maps::energyTerms(creation.energy), std::move(obs));
        }
        break;
        default:
            MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    }
}
