#pragma once
// The one place where a scene is checked as a whole before a run, after its
// parameters were read and checked one by one (io/Parameters.hpp): the
// derived physics (sound speed, time step), the counts that follow from it
// (steps, lattice points, particles, grid nodes) in checked arithmetic, and
// the memory the run will need against what the machine has. It allocates
// nothing and writes nothing, so a refused run leaves no trace.
#include <string>
#include <vector>

#include "app/Simulation.hpp"
#include "core/MemoryAvailable.hpp"
#include "scene/SceneConfig.hpp"

namespace poresph {

// What a run of the scene will need, estimated before anything is allocated.
struct RunEstimate {
  DerivedParameters derived{};
  long long steps = 0;           // to Run/End Time, or Run/Max Steps if that comes first (0 for a steady solve)
  long long lattice_points = 0;  // of the whole lattice, wall layers included
  // At most this many particles: every lattice point (the interiors of grains
  // deeper than their boundary shell are dropped later).
  long long particles = 0;
  long long grid_nodes = 0;      // of Output/Grid Points
  double bytes = 0;              // all processes together, at the peak (set-up or run)
  double bytes_per_process = 0;
};

// The steps from t = 0 to end_time at dt: the nearest whole number, at least
// one; LLONG_MAX for more than 2^62 (no run gets there).
long long steps_to_end_time(double end_time, double dt);
// The step a run stops at: steps_to_end_time, or max_steps when that is
// smaller (max_steps 0: no limit). Refuses a run to an end time beyond 2^62
// steps rather than letting the count wrap, which stopped the run after one
// step "at its end time".
long long last_step(double end_time, double dt, long long max_steps);

// What the machine offers the run: Run/Memory Limit, or the memory Linux
// reports available (/proc/meminfo), for `processes_on_machine` processes.
MemoryBudget memory_budget(const SceneConfig& scene, int processes_on_machine);

// Checks the scene for a run on `ranks` processes and returns its needs;
// throws ParameterError naming the parameters and the numbers. Warnings
// (a run shorter than half a step) are appended to scene.warnings.
RunEstimate check_scene(SceneConfig& scene, int ranks, const MemoryBudget& budget);

// "1.5 GB", "320 kB": for messages.
std::string human_bytes(double bytes);

}  // namespace poresph
