// SPDX-License-Identifier: BSD-3-Clause
// CEntropyVoxelMap: observation likelihood (MRPT's computeObservationLikelihood()).
#include "TermKeys.h"

#include <emslam/maps/CEntropyVoxelMap.h>

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>

#include <cmath>
#include <vector>

using emslam::CEntropyVoxelMap;
using emslam::maps::CellIndex;
using emslam::maps::EntropyTerm;
using emslam::maps::WeightedHistogram;
using emslam::maps::WeightedPointCloud;
using emslam::maps::detail::termKey;

bool CEntropyVoxelMap::internal_canComputeObservationLikelihood(
    const mrpt::obs::CObservation& obs) const
{
    return dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs) != nullptr ||
           dynamic_cast<const mrpt::obs::CObservationPointCloud*>(&obs) != nullptr;
}

double CEntropyVoxelMap::internal_computeObservationLikelihood(
    const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const
{
    WeightedPointCloud raw;
    if (!observationToCloud(obs, raw) || raw.empty())
    {
        return 0.0;
    }
    const WeightedPointCloud cloud = emslam::maps::simplifyCloud(raw, m_creation.cell_size);
    std::vector<CellIndex> cells;
    m_engine.computeCells(cloud, takenFrom, cells);

    // General term: the 3D histogram for 6DOF energies, XZ for 3DOF ones.
    const EntropyTerm gt = m_creation.dof == 6 ? EntropyTerm::H3D : EntropyTerm::XZ;
    const auto t = static_cast<std::size_t>(gt);
    WeightedHistogram built;
    const WeightedHistogram* map_h = trackedHistogram(gt);
    if (!map_h)
    {
        built = buildHistogram(gt);
        map_h = &built;
    }
    WeightedHistogram obs_h(cloud.size());
    for (std::size_t j = 0; j < cloud.size(); j++)
    {
        obs_h.add(termKey(t, cells[j]), cloud.weights[j]);
    }
    // Code length C(X) = W_X·H(X) = W_X log W_X − S_X [nats].
    const auto code = [](double W, double S) { return W > 0 ? W * std::log(W) - S : 0.0; };
    const double Wa = map_h->totalWeight(), Sa = map_h->sumWLogW();
    const double Wo = obs_h.totalWeight(), So = obs_h.sumWLogW();
    double Su = Sa;
    obs_h.forEachCell(
        [&](std::uint64_t key, double wo)
        {
            const double wa = map_h->weight(key);
            Su += WeightedHistogram::wLogW(wa + wo) - WeightedHistogram::wLogW(wa);
        });
    // logL = C(A) + C(O) − C(A ∪ O) ≤ 0: minus the weighted Jensen-Shannon
    // divergence between map and observation, times W_A + W_O.
    return code(Wa, Sa) + code(Wo, So) - code(Wa + Wo, Su);
}
