#pragma once
// Where a run stands, besides its particles: what a checkpoint stores
// (io/Checkpoint.hpp) so that a restart goes on exactly, and what each
// observer of the time loop saves into it (diagnostics/Observer.hpp).
#include <cmath>
#include <vector>

namespace poresph {

// What a checkpoint holds besides the particles: where the run stands.
struct RunState {
  int drive_axis = -1;                     // the body-force direction being run (tensor runs), or -1
  // The run's stages (app/RunPlan.hpp): which one the checkpoint is of, and
  // what the ones before it measured, StageRecord::kSize values each
  // (app/StageRecord.hpp).
  double stage = 0;
  double stage_warm = 0;  // whether that stage started from the end of the one before it
  std::vector<double> completed_stages;
  std::vector<double> steady_times, steady_values;  // the steady-state detector's window
  double steady_first_time = 0;
  // Its verdict on the last of them (SteadyStateDetector::save_verdict), so
  // that a run continued with no step left reports what the run it
  // continues reported.
  std::vector<double> steady_verdict;
  // The channel profile's samples so far: sample time, time, error, each.
  std::vector<double> profile_samples;
  // Neighbour-list builds of the stage up to the checkpoint.
  double neighbour_rebuilds = 0;
  std::vector<double> frame_steps, frame_times;     // field files so far
  double field_interval = 0, next_field_time = INFINITY;  // Output/Field Interval, and when the next file is due
  // Data rows of permeability_history*.csv, profiles.csv,
  // grains_history*.csv and balance_history*.csv that belong to the run up
  // to the checkpoint: a restart keeps these and drops what a killed run
  // wrote after it, or an end-of-run row it continues past.
  double history_rows = 0, profile_rows = 0, grains_history_rows = 0, balance_history_rows = 0;
  double phases_history_rows = 0;  // phases_history*.csv
  double max_density_variation = 0, max_density_drift = 0;
  double particles_inside_grains = 0, max_grain_penetration = 0;
  double grain_surface_corrections = 0, max_corrected_depth = 0;

  // f(name, member) for every member but drive_axis: the checkpoint writes
  // and reads the same list, scalars as attributes, vectors as run/NAME.
  template <class State, class F>
  static void for_each_value(State& state, F&& f) {
    f("stage", state.stage);
    f("stage_warm", state.stage_warm);
    f("completed_stages", state.completed_stages);
    f("steady_times", state.steady_times);
    f("steady_values", state.steady_values);
    f("steady_first_time", state.steady_first_time);
    f("steady_verdict", state.steady_verdict);
    f("profile_samples", state.profile_samples);
    f("neighbour_rebuilds", state.neighbour_rebuilds);
    f("frame_steps", state.frame_steps);
    f("frame_times", state.frame_times);
    f("field_interval", state.field_interval);
    f("next_field_time", state.next_field_time);
    f("history_rows", state.history_rows);
    f("profile_rows", state.profile_rows);
    f("grains_history_rows", state.grains_history_rows);
    f("balance_history_rows", state.balance_history_rows);
    f("phases_history_rows", state.phases_history_rows);
    f("max_density_variation", state.max_density_variation);
    f("max_density_drift", state.max_density_drift);
    f("particles_inside_grains", state.particles_inside_grains);
    f("max_grain_penetration", state.max_grain_penetration);
    f("grain_surface_corrections", state.grain_surface_corrections);
    f("max_corrected_depth", state.max_corrected_depth);
  }
};

}  // namespace poresph
