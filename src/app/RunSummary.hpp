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

// What the summary needs of the scene beyond the stages' records.
struct SummaryScales {
  // The Reynolds number per unit of superficial speed: mean grain diameter /
  // (porosity nu); 0 where the solid gives no length.
  double reynolds_scale = 0;
  // 1 / (porosity nu): times a stage's superficial speed and spacing, the
  // particle-scale Reynolds number (mean pore speed dx / nu); 0: not known.
  double particle_reynolds_scale = 0;
  // Whether the equations carry inertia (Fluid/Convection, or particles that
  // move with the flow): only then does a Reynolds number move k.
  bool inertia = false;
  // Solver/Max Inner Iterations (0: not known), which an unconverged steady
  // solve's warning names when its inner solves came near it, with Solver/
  // Raised Inner Iterations; Solver/Tolerance (0: not known), below which it
  // says that k had not settled.
  int max_inner_iterations = 0, raised_inner_iterations = 0;
  double solver_tolerance = 0;
  // Checks/Density Variation Limit (0: not known), at which the march stops
  // and beyond which a steady solve's state is warned of.
  double density_variation_limit = 0;
};

// Into `report` (which holds the rest of the run's measures): dim, the
// space's dimension; levels, Convergence/Levels; steady_sought, whether the
// stages had a steady test (Permeability/Steady Tolerance > 0). What
// the whole run counts (steps, time, list builds) is summed from the
// records alone, so that a run continued from a checkpoint, which carries
// the records of the stages before it, reports what a run in one go does.
void summarise_stages(const std::vector<StageRecord>& records, int dim, int levels, bool steady_sought,
                      RunReport& report, const SummaryScales& scales = {});

}  // namespace poresph
