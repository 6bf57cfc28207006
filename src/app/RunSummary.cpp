#include "app/RunSummary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "diagnostics/ConvergenceIndex.hpp"

namespace poresph {
namespace {

// A component smaller than this fraction of the largest is taken as zero
// (the off-diagonal of a symmetric cell): no relative uncertainty for it.
constexpr double kNegligibleComponent = 1e-6;
// Above this relative change at half the force, the flow is not in Darcy's regime.
constexpr double kDarcyLinearityLimit = 0.01;
// Above this Reynolds number (mean grain diameter) inertia lowers k below
// the creeping-flow value by more than the method's error: 0.85 % at 2.2 in
// a square array of solid fraction 0.16, 17 % at 34 in problem III
// (docs/validation.md, "Navier-Stokes reference"; docs/steady_solver.md).
constexpr double kDarcyReynolds = 1.0;
// Above this particle-scale Reynolds number (mean pore speed dx / nu)
// convection outweighs viscosity from one particle to the next, where the
// steady solver's preconditioner, built on the viscous and pressure terms,
// falls short: problem III at 0.01 L converged at 1.3 and not at 2.8
// (docs/steady_solver.md, "Inertia").
constexpr double kConvectiveParticleReynolds = 2.0;

double speed_of(const StageRecord& r) { return std::sqrt(r.u[0] * r.u[0] + r.u[1] * r.u[1] + r.u[2] * r.u[2]); }

// Which stage a warning is about.
std::string stage_name(const StageRecord& r, int levels, bool tensor) {
  std::string which = levels > 1 ? "level " + std::to_string(r.level + 1) + " of " + std::to_string(levels) : "the run";
  if (tensor && r.axis >= 0) which += std::string(" driven along ") + "xyz"[r.axis];
  if (r.half_force) which += " at half the body force";
  return which;
}

bool tensor_records(const std::vector<StageRecord>& records) {
  return std::any_of(records.begin(), records.end(),
                     [&](const StageRecord& r) { return r.axis != records.front().axis; });
}

// A steady solve that stopped short of Solver/Tolerance: its k is not the answer.
// A linear iteration runs two DG solves and one of the velocity block, each
// of at most the inner cap (max_inner_iterations, which a stalled linear
// solve raises as far as raised_inner_iterations): with 1.5 times the first
// or more a linear iteration, the DG solves were near their cap. On the
// narrow passages of an image their result is then too rough for the outer
// solve to use (docs/steady_solver.md, "What fails on a blobs image"), and
// a higher cap is what helped there. 0: the cap is not known. A solve
// whose residual met Solver/Tolerance (0: not known) stopped because k had
// not settled: its last Newton step moved k by r.relative_change, more than
// Solver/Permeability Tolerance. A fast flow is named as the likely cause
// where convection outweighs viscosity at the particle scale.
std::string unconverged_warning(const StageRecord& r, int levels, bool tensor, const SummaryScales& scales,
                                bool last_stage) {
  const int max_inner_iterations = scales.max_inner_iterations;
  const double tolerance = scales.solver_tolerance;
  char text[1600];
  // The checkpoint holds the last stage's state only: an earlier stage's
  // solve is taken up again by running the scene anew.
  int n = std::snprintf(text, sizeof text,
                        "the steady solve of %s did not converge: relative residual %.3g after %lld Newton and %lld "
                        "linear iterations; k is that of its last state%s (raise Solver/Max Linear Iterations or "
                        "Solver/Max Nonlinear Iterations, and %s)",
                        stage_name(r, levels, tensor).c_str(), r.solver_residual, r.nonlinear_iterations,
                        r.linear_iterations, last_stage ? ", which the checkpoint keeps" : "",
                        last_stage ? "continue with --restart" : "run the scene again: a restart continues its last "
                                                                 "stage only");
  if (tolerance > 0 && r.solver_residual <= tolerance && n > 0 && n < static_cast<int>(sizeof text))
    n += std::snprintf(text + n, sizeof text - n,
                       "; the residual is below Solver/Tolerance, but the last Newton step still moved k by %.2g %%, "
                       "more than Solver/Permeability Tolerance: where the pore space narrows to a particle or two, "
                       "pressure modes that the SPH gradient hardly sees carry k and hardly show in the residual "
                       "(docs/steady_solver.md, \"k settled\")",
                       100 * r.relative_change);
  const double inner_per_linear =
      r.linear_iterations > 0 ? static_cast<double>(r.inner_iterations) / static_cast<double>(r.linear_iterations) : 0;
  if (max_inner_iterations > 0 && inner_per_linear >= 1.5 * max_inner_iterations && n > 0 &&
      n < static_cast<int>(sizeof text))
    std::snprintf(text + n, sizeof text - n,
                  "; its inner solves took %.0f iterations a linear iteration, near the cap of its two DG solves, "
                  "Solver/Max Inner Iterations = %d (raised when the solve stalls, at most to Solver/Raised Inner "
                  "Iterations = %d): raising them may help (docs/steady_solver.md, \"What fails on a blobs image\")",
                  inner_per_linear, max_inner_iterations,
                  std::max(scales.raised_inner_iterations, max_inner_iterations));
  n = static_cast<int>(std::strlen(text));
  const double particle_reynolds = speed_of(r) * r.spacing * scales.particle_reynolds_scale;
  if (scales.inertia && particle_reynolds > kConvectiveParticleReynolds && n < static_cast<int>(sizeof text))
    std::snprintf(text + n, sizeof text - n,
                  "; the mean pore speed times the particle spacing over nu is %.2g: where convection outweighs "
                  "viscosity from one particle to the next (above about %.0f) the solver's preconditioner falls "
                  "short, and Solver/Method = explicit marches instead (docs/steady_solver.md, \"Inertia\")",
                  particle_reynolds, kConvectiveParticleReynolds);
  return text;
}

// A stage that ended without a steady k: its k is not the answer yet, and
// says so. It is warned of where a steady k was sought (Permeability/Steady
// Tolerance), and in a ladder either way, since the extrapolation over the
// levels takes each level's k as steady. stopped_by: what ended the run, for
// the stage that ended it (else empty); more time is the remedy only where
// time ran out.
std::string unsteady_warning(const StageRecord& r, int levels, bool tensor, bool steady_sought,
                             const std::string& stopped_by) {
  const std::string which = stage_name(r, levels, tensor);
  const char* remedy = stopped_by == "failure" ? "the run failed first (its failure says why)"
                       : stopped_by == "signal" ? "--restart from its checkpoint continues it"
                                                : "raise Run/End Time or Run/Max Steps";
  char text[300];
  if (std::isfinite(r.relative_change) && std::isfinite(r.remaining_change))
    std::snprintf(text, sizeof text,
                  "k was not steady when %s ended (step %lld): it moved by %.2g %% over its last span and may "
                  "move by %.2g %% more; %s",
                  which.c_str(), r.steps, 100 * r.relative_change, 100 * r.remaining_change, remedy);
  else
    std::snprintf(text, sizeof text,
                  "k was not steady when %s ended (step %lld), too early to say how far it still has to go; %s",
                  which.c_str(), r.steps, remedy);
  if (!steady_sought)
    return text + std::string(": the extrapolation over the levels takes each level's k as steady, and "
                              "Permeability/Steady Tolerance ends each level when it is");
  return text;
}

}  // namespace

// What the stages measured, into the report: the finest level's tensor (set
// by the stages), the ladder's levels and their grid convergence index, the
// Darcy check, whether every stage was steady (a warning for each that
// sought a steady k and did not reach it).
void summarise_stages(const std::vector<StageRecord>& records, int dim, int levels, bool steady_sought,
                      RunReport& report, const SummaryScales& scales) {
  report.steps = 0, report.simulated_time = 0, report.neighbour_rebuilds = 0;
  for (const auto& r : records) {
    report.steps += r.steps;
    report.simulated_time += r.simulated_time;
    report.neighbour_rebuilds += r.neighbour_rebuilds;
  }
  for (const auto& r : records) {
    if (!r.steady_solve) continue;
    auto& solver = report.solver;
    solver.method = "steady";
    solver.converged = solver.converged && r.solver_converged;
    solver.nonlinear_iterations += r.nonlinear_iterations;
    solver.linear_iterations += r.linear_iterations;
    solver.inner_iterations += r.inner_iterations;
    solver.rate_evaluations += r.rate_evaluations;
    solver.partial_rate_evaluations += r.partial_rate_evaluations;
    solver.residual = std::max(solver.residual, r.solver_residual);
    solver.setup_seconds += r.solver_setup_seconds;
    solver.solve_seconds += r.solver_solve_seconds;
    solver.bytes_per_particle = std::max(solver.bytes_per_particle, r.solver_bytes_per_particle);
    if (!r.solver_converged)
      report.warnings.push_back(unconverged_warning(r, levels, tensor_records(records), scales, &r == &records.back()));
  }
  // The march stops where a fluid particle's density leaves the limit (exit
  // status 3); a solve has no steps to stop, and its state is judged here.
  if (report.solver.method == "steady" && scales.density_variation_limit > 0 &&
      report.max_density_variation > scales.density_variation_limit) {
    char text[400];
    std::snprintf(text, sizeof text,
                  "the solved state's density varies by %.3g of rho0, beyond Checks/Density Variation Limit = "
                  "%.3g, at which a march stops: its fields compress the fluid more than the run is checked "
                  "for (k, of a flow the density hardly changes, may hold still); a larger Fluid/Sound Speed, "
                  "or the run's own, keeps them within",
                  report.max_density_variation, scales.density_variation_limit);
    report.warnings.push_back(text);
  }
  // The run's verdict, not only its last stage's: a restart that solved the
  // last stage leaves an earlier stage's unconverged solve as it was.
  if (report.solver.method == "steady" && !report.solver.converged && report.stopped_by == "steady_state")
    report.stopped_by = "not_converged";
  bool any = false, steady = true;
  const bool tensor = tensor_records(records);
  for (const auto& r : records) {
    if (!r.has_permeability) continue;
    any = true;
    steady = steady && r.steady;
    if ((steady_sought || levels > 1) && !r.steady && !r.steady_solve)
      report.warnings.push_back(
          unsteady_warning(r, levels, tensor, steady_sought, &r == &records.back() ? report.stopped_by : ""));
    report.steady_relative_change = std::max(report.steady_relative_change, r.relative_change);
    report.steady_remaining_change = std::max(report.steady_remaining_change, r.remaining_change);
  }
  report.steady = any && steady;
  // The finest tensor, and the superficial velocity of its first column.
  // The Reynolds number is the fastest finest stage's: a tensor's axes
  // drive the same force through the medium each way, and the flow that
  // inertia bends most is the fastest of them.
  double fastest = 0;
  for (const auto& r : records) {
    if (!r.has_permeability || r.half_force || r.level != levels - 1 || r.axis < 0) continue;
    if (!report.has_permeability)
      for (int i = 0; i < dim; ++i) report.superficial_velocity[i] = r.u[i];
    report.has_permeability = report.driven[r.axis] = true;
    for (int i = 0; i < dim; ++i) report.permeability[i][r.axis] = r.k[i];
    double speed = 0;
    for (int i = 0; i < dim; ++i) speed += r.u[i] * r.u[i];
    fastest = std::max(fastest, std::sqrt(speed));
  }
  if (report.has_permeability && scales.reynolds_scale > 0) report.reynolds_number = fastest * scales.reynolds_scale;
  // Darcy's k is the creeping-flow limit; a run with the Darcy check
  // measures how far inertia moved k and warns by that measure instead.
  const bool linearity_checked =
      std::any_of(records.begin(), records.end(), [](const StageRecord& r) { return r.half_force; });
  if (scales.inertia && !linearity_checked && report.reynolds_number > kDarcyReynolds) {
    char text[400];
    std::snprintf(text, sizeof text,
                  "the Reynolds number (mean pore speed times the mean grain diameter over nu) is %.3g: above "
                  "about %.0f inertia lowers k below the creeping-flow (Darcy) permeability (docs/validation.md, "
                  "\"Navier-Stokes reference\"); Permeability/Linearity Check measures by how much, and "
                  "Fluid/Convection = false gives the creeping-flow k",
                  report.reynolds_number, kDarcyReynolds);
    report.warnings.push_back(text);
  }

  if (levels > 1) {
    report.levels.assign(levels, RunReport::Level{});
    for (const auto& r : records) {
      if (r.half_force) continue;
      auto& level = report.levels[r.level];
      level.spacing = r.spacing;
      level.steps += r.steps;
      level.wall_seconds += r.wall_seconds;
      level.warm_started = level.warm_started && r.warm_started;
      level.steady = level.steady && (!r.has_permeability || r.steady);
      if (r.has_permeability && r.axis >= 0)
        for (int i = 0; i < dim; ++i) level.permeability[i][r.axis] = r.k[i];
      if (r.has_phases) {
        level.has_phases = true, level.has_relative_permeability = r.has_relative_permeability;
        for (int p = 0; p < 2; ++p)
          level.saturation[p] = r.saturation[p], level.relative_permeability[p] = r.relative_permeability[p];
      }
    }
    // Each phase's k_r from the levels, as k's components are.
    const bool phases_measured = std::all_of(report.levels.begin(), report.levels.end(), [](const auto& level) {
      return level.has_relative_permeability;
    });
    if (phases_measured && report.phases.size() == 2)
      for (int p = 0; p < 2; ++p) {
        std::vector<double> spacings, values;
        for (const auto& level : report.levels)
          spacings.push_back(level.spacing), values.push_back(level.relative_permeability[p]);
        const auto e = convergence_estimate(spacings, values);
        auto& phase = report.phases[p];
        phase.has_extrapolation = true;
        phase.relative_permeability_extrapolated = e.extrapolated;
        phase.relative_permeability_uncertainty = e.uncertainty;
        if (!e.asymptotic)
          report.warnings.push_back("the levels of phase " + std::to_string(p) + "'s k_r (" + phase.name +
                                    ") are not in the asymptotic range: " + e.problem);
      }
    double largest = 0;
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j) largest = std::max(largest, std::abs(report.permeability[i][j]));
    report.observed_order = NAN;
    double order_component = -1;
    for (int j = 0; j < dim; ++j) {
      if (!report.driven[j]) continue;
      for (int i = 0; i < dim; ++i) {
        std::vector<double> spacings, values;
        for (const auto& level : report.levels) spacings.push_back(level.spacing), values.push_back(level.permeability[i][j]);
        const auto e = convergence_estimate(spacings, values);
        report.permeability_extrapolated[i][j] = e.extrapolated;
        const bool negligible = std::abs(values.back()) <= kNegligibleComponent * largest;
        report.permeability_uncertainty[i][j] = negligible ? NAN : e.uncertainty;
        if (negligible) continue;
        if (std::abs(values.back()) > order_component) order_component = std::abs(values.back()), report.observed_order = e.order;
        if (!e.asymptotic) {
          const std::string name = std::string("k") + "xyz"[i] + "xyz"[j];
          report.warnings.push_back("the levels of " + name + " are not in the asymptotic range: " + e.problem);
        }
      }
    }
  }

  for (const auto& half : records) {
    if (!half.half_force || !half.has_permeability) continue;
    for (const auto& full : records) {
      if (full.half_force || full.level != half.level || full.axis != half.axis || !full.has_permeability) continue;
      report.has_linearity = true;
      const int j = std::max(half.axis, 0);
      double length = 0;
      for (int i = 0; i < dim; ++i) length += full.k[i] * full.k[i];
      length = std::sqrt(length);
      for (int i = 0; i < dim; ++i) {
        const bool negligible = std::abs(full.k[i]) <= kNegligibleComponent * length;
        const double change = negligible ? NAN : (half.k[i] - full.k[i]) / full.k[i];
        report.darcy_linearity[i][j] = change;
        if (std::isfinite(change) && std::abs(change) > kDarcyLinearityLimit) {
          char text[400];
          std::snprintf(text, sizeof text, "k%c%c changes by %+.2f %% at half the body force", "xyz"[i], "xyz"[j],
                        100 * change);
          std::string warning = text;
          if (full.steady && half.steady) {
            warning += ": the flow is not in the Darcy regime";
            if (report.reynolds_number > 0) {  // grains give it a length; an image does not
              std::snprintf(text, sizeof text, " (Reynolds number %.3g)", report.reynolds_number);
              warning += text;
            }
          } else {
            // Two unsteady k differ by how far each march got, whatever the flow's regime.
            const char* which = !full.steady && !half.steady ? "at either force" : !full.steady ? "at the full force"
                                                                                                 : "at half the force";
            std::snprintf(text, sizeof text,
                          ", but k was not steady %s: the change may be the march's, not inertia's; a steady k at "
                          "both forces (Permeability/Steady Tolerance, Run/End Time) tells them apart",
                          which);
            warning += text;
          }
          report.warnings.push_back(warning);
        }
      }
    }
  }
}

}  // namespace poresph
