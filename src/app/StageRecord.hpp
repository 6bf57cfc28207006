#pragma once
// What a finished stage of a run measured (app/RunPlan.hpp's stages), as
// the checkpoints keep it and the run's summary reads it.
#include <vector>

namespace poresph {

// What a finished stage measured, kept in every later checkpoint
// (RunState::completed_stages) so that a restarted run reports all of them.
struct StageRecord {
  static constexpr int kSize = 36;
  int level = 0, axis = -1;
  bool half_force = false;
  double spacing = 0;
  long long steps = 0;
  double simulated_time = 0, wall_seconds = 0;
  bool warm_started = false, steady = false, has_permeability = false;
  double relative_change = 0, remaining_change = 0;
  double k[3] = {0, 0, 0};  // the driven column, k_i = nu <u_i> / F (driving_force)
  double u[3] = {0, 0, 0};  // the superficial velocity it was measured from
  long long neighbour_rebuilds = 0;
  // Solver/Method = steady: what the stage's solve did (solver/SteadySolver.hpp).
  bool steady_solve = false, solver_converged = false;
  long long nonlinear_iterations = 0, linear_iterations = 0, inner_iterations = 0, rate_evaluations = 0,
            partial_rate_evaluations = 0;
  double solver_residual = 0, solver_setup_seconds = 0, solver_solve_seconds = 0, solver_bytes_per_particle = 0;
  // Two fluids (Phases): each phase's saturation and, with Phases/Single
  // Phase Permeability, its relative permeability at the stage's end.
  bool has_phases = false, has_relative_permeability = false;
  double saturation[2] = {0, 0}, relative_permeability[2] = {0, 0};

  void append_to(std::vector<double>& values) const {
    const double v[kSize] = {double(level), double(axis), double(half_force), spacing, double(steps),
                             simulated_time, wall_seconds, double(warm_started), double(steady),
                             double(has_permeability), relative_change, remaining_change, k[0], k[1], k[2],
                             u[0], u[1], u[2], double(neighbour_rebuilds), double(steady_solve),
                             double(solver_converged), double(nonlinear_iterations), double(linear_iterations),
                             double(rate_evaluations), solver_residual, solver_setup_seconds, solver_solve_seconds,
                             solver_bytes_per_particle, double(inner_iterations),
                             double(partial_rate_evaluations), double(has_phases),
                             double(has_relative_permeability), saturation[0], saturation[1],
                             relative_permeability[0], relative_permeability[1]};
    values.insert(values.end(), v, v + kSize);
  }
  static StageRecord read(const double* v) {
    StageRecord r;
    r.level = int(v[0]), r.axis = int(v[1]), r.half_force = v[2] != 0, r.spacing = v[3];
    r.steps = static_cast<long long>(v[4]), r.simulated_time = v[5], r.wall_seconds = v[6];
    r.warm_started = v[7] != 0, r.steady = v[8] != 0, r.has_permeability = v[9] != 0;
    r.relative_change = v[10], r.remaining_change = v[11];
    r.k[0] = v[12], r.k[1] = v[13], r.k[2] = v[14];
    r.u[0] = v[15], r.u[1] = v[16], r.u[2] = v[17];
    r.neighbour_rebuilds = static_cast<long long>(v[18]);
    r.steady_solve = v[19] != 0, r.solver_converged = v[20] != 0;
    r.nonlinear_iterations = static_cast<long long>(v[21]), r.linear_iterations = static_cast<long long>(v[22]);
    r.rate_evaluations = static_cast<long long>(v[23]);
    r.solver_residual = v[24], r.solver_setup_seconds = v[25], r.solver_solve_seconds = v[26];
    r.solver_bytes_per_particle = v[27];
    r.inner_iterations = static_cast<long long>(v[28]);
    r.partial_rate_evaluations = static_cast<long long>(v[29]);
    r.has_phases = v[30] != 0, r.has_relative_permeability = v[31] != 0;
    r.saturation[0] = v[32], r.saturation[1] = v[33];
    r.relative_permeability[0] = v[34], r.relative_permeability[1] = v[35];
    return r;
  }
};

}  // namespace poresph
