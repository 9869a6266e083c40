// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/maps/EntropyEnergy.h>

#include <mrpt/core/exceptions.h>

namespace emslam::maps
{
TermMask energyTerms(EnergyType e)
{
    switch (e)
    {
        case EnergyType::Unstructured:
            return termBit(EntropyTerm::H3D);
        case EnergyType::LowStructured:
            return termBit(EntropyTerm::H3D) | termBit(EntropyTerm::Y);
        case EnergyType::Structured:
            return termBit(EntropyTerm::H3D) | termBit(EntropyTerm::XY) | termBit(EntropyTerm::XZ) |
                   termBit(EntropyTerm::YZ);
        case EnergyType::PlanarLowStructured:
            return termBit(EntropyTerm::XZ);
        case EnergyType::PlanarStructured:
            return termBit(EntropyTerm::XZ) | termBit(EntropyTerm::X) | termBit(EntropyTerm::Z);
    }
    THROW_EXCEPTION("energyTerms(): invalid EnergyType value");
}

int energyDof(EnergyType e)
{
    return (e == EnergyType::PlanarLowStructured || e == EnergyType::PlanarStructured) ? 3 : 6;
}

int energyExpression(EnergyType e)
{
    return 8 + static_cast<int>(e);
}

std::string toString(EnergyType e)
{
    switch (e)
    {
        case EnergyType::Unstructured:
            return "unstructured";
        case EnergyType::LowStructured:
            return "low_structured";
        case EnergyType::Structured:
            return "structured";
        case EnergyType::PlanarLowStructured:
            return "planar_low_structured";
        case EnergyType::PlanarStructured:
            return "planar_structured";
    }
    THROW_EXCEPTION("toString(): invalid EnergyType value");
}

std::string toString(EntropyTerm t)
{
    static const char* names[NUM_ENTROPY_TERMS] = {"H3D", "XY", "XZ", "YZ", "X", "Y", "Z"};
    return names[static_cast<std::size_t>(t)];
}

EnergyType energyTypeFromString(const std::string& name, const std::string& key)
{
    for (int i = 0; i <= static_cast<int>(EnergyType::PlanarStructured); i++)
    {
        const auto e = static_cast<EnergyType>(i);
        if (toString(e) == name)
        {
            return e;
        }
    }
    THROW_EXCEPTION_FMT(
        "CEntropyVoxelMap: unknown '%s' = '%s' (expected one of: unstructured, "
        "low_structured, structured [6DOF]; planar_low_structured, planar_structured "
        "[3DOF])",
        key.c_str(), name.c_str());
}

double energyFromTerms(EnergyType e, const EntropyTerms& h)
{
    const TermMask mask = energyTerms(e);
    double sum = 0;
    for (std::size_t i = 0; i < NUM_ENTROPY_TERMS; i++)
    {
        if (mask & (1u << i))
        {
            sum += h[i];
        }
    }
    return sum;
}

}  // namespace emslam::maps
