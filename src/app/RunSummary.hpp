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
// stages had a steady test (Permeability/Steady Tolerance > 0);
// reynolds_scale, the Reynolds number per unit of superficial speed (mean
// grain diameter / (porosity nu); 0 where the solid gives no length);
// max_inner_iterations, Solver/Max Inner Iterations (0: not known), which an
// unconverged steady solve's warning names when its inner solves came near it,
// with raised_inner_iterations, Solver/Raised Inner Iterations, and
// solver_tolerance, Solver/Tolerance (0: not known), below which it says
// that k had not settled. What
// the whole run counts (steps, time, list builds) is summed from the
// records alone, so that a run continued from a checkpoint, which carries
// the records of the stages before it, reports what a run in one go does.
void summarise_stages(const std::vector<StageRecord>& records, int dim, int levels, bool steady_sought,
                      RunReport& report, double reynolds_scale = 0, int max_inner_iterations = 0,
                      int raised_inner_iterations = 0, double solver_tolerance = 0);

}  // namespace poresph
