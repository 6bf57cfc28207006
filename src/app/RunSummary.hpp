#pragma once
// The run's summary from its stages' records: the finest level's tensor,
// the ladder's levels and their grid convergence index, the Darcy check,
// and the warnings these call for (an unsteady k, levels outside the
// asymptotic range, inertia). Apart from the time loop so that tests can
// give it records directly.
#include <vector>

#include "app/Run.hpp"
#include "app/StageRecord.hpp"

namespace poresph {

// Into `report` (which holds the rest of the run's measures): dim, the
// space's dimension; levels, Convergence/Levels; steady_sought, whether the
// stages had a steady test (Permeability/Steady Tolerance > 0).
void summarise_stages(const std::vector<StageRecord>& records, int dim, int levels, bool steady_sought,
                      RunReport& report);

}  // namespace poresph
