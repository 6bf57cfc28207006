#include "app/SceneCheck.hpp"

#include "app/RunPlan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/Kernel.hpp"
#include "core/MemoryAvailable.hpp"
#include "geometry/Grains.hpp"
#include "geometry/Lattice.hpp"
#include "io/Parameters.hpp"
#include "solver/SteadyOptions.hpp"

namespace poresph {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Counts beyond this are refused rather than computed: 2^62 leaves room for
// the sums and products the run makes of them without overflow.
constexpr double kMostCount = 4611686018427387904.0;
constexpr double kMostIndex = 2147483647.0;  // int: particle, pair and cell indices on a process

template <class... Parts>
[[noreturn]] void refuse(const Parts&... parts) {
  std::ostringstream msg;
  msg.precision(4);
  (msg << ... << parts);
  throw ParameterError(msg.str());
}

// Lattice points within the neighbour-list radius of a particle: 3h, and
// the skin for particles that move (fixed ones are listed without).
double list_reach(const SceneConfig& s) {
  const double skin = s.particle_motion == ParticleMotion::Fixed ? 0.0 : s.neighbour_skin;
  return (kSupportRadiusInH + skin) * s.smoothing_length_ratio;  // in spacings
}
double neighbour_ball(const SceneConfig& s) {
  const double r = list_reach(s);
  return s.dimension == 2 ? kPi * r * r : 4.0 / 3.0 * kPi * r * r * r;
}

// Bytes one particle slot (owned or ghost) of a process costs while the run
// steps, and at set-up. An estimate from the storage the code allocates,
// not a measurement: core/Particles.hpp, the half neighbour list, the
// per-thread pair sums, the cell list, and at set-up the lattice seeds.
struct SlotBytes {
  double run, setup;
};
SlotBytes bytes_per_slot(const SceneConfig& s, int threads) {
  const int D = s.dimension;
  const bool surfaces = s.walls != WallType::None || s.has_solid();
  const bool shifting = s.shifting_coefficient > 0;
  const bool fixed = s.particle_motion == ParticleMotion::Fixed;
  // x, v, x_start, v_start, dvdt; rho, p, m, pressure_term, inverse_density, rho_start, drhodt; kind; id.
  // Fixed particles keep no x_start and no inverse_density (core/Particles.hpp, fix_positions).
  double fields = (fixed ? 4.0 : 5.0) * D * 8 + (fixed ? 6 : 7) * 8 + 4 + 8;
  if (surfaces) fields += (D + 2) * 8.0;  // wall_vector, wall_scalar, wall_drag
  if (shifting) fields += 2.0 * D * 8;
  if (!fixed) fields *= 1.25;  // Particles::reserve grows by a quarter for moving particles
  // Moving particles: half of the neighbours within 3h + skin, 4-byte
  // indices grown by a quarter, plus offsets. Fixed particles: rows as
  // masks over the lattice's offsets within 3h (core/LatticeRows.hpp), two
  // masks of 64-bit words, the site and its place in the map; with surfaces
  // a no-slip factor for each fluid-boundary pair, counted here for a
  // quarter of the pairs (all of a particle's at a surface, none inside the pore).
  const double pairs = 0.5 * neighbour_ball(s);
  double list = (pairs * 4 + 2 * 4) * 1.25;
  if (fixed) list = 2 * 8 * std::ceil(2 * pairs / 64) + 4 + 4 + (surfaces ? pairs / 4 * 8.0 : 0.0);
  // Fixed particles' first copy of the sums is their rates in 3D (core/PairSums.hpp).
  const double sums = (std::max(1, threads) - (fixed && D == 3 ? 1 : 0)) * (D + 1.0 + (shifting ? D + 1.0 : 0.0)) * 8;
  const double cells = 2 * 4;
  // SeedParticle (x, v, wall_vector, wall_scalar, id, kind) and, with a
  // solid, every lattice point's mark (kind, surface) and depth.
  double seeds = (3.0 * D + 2) * 8 + 8;
  if (s.has_solid()) seeds += 4 + 8.0 * (D + 2);
  const double run = fields + list + sums + cells;
  return {run, fields + seeds};
}

// Points across each direction of the lattice (wall layers included), as
// Lattice.hpp will make it; refuses what an int cannot index.
std::vector<long long> lattice_counts(const SceneConfig& s) {
  std::vector<long long> counts;
  try {
    for (int d = 0; d < s.dimension; ++d)
      counts.push_back(lattice_points_across(s.cell_size[d], s.particle_spacing, d));
  } catch (const std::invalid_argument& e) {
    throw ParameterError(e.what());
  }
  if (s.walls == WallType::Channel)
    counts[1] += 2LL * boundary_layers(s.particle_spacing, s.smoothing_length_ratio * s.particle_spacing);
  return counts;
}

// The product of counts, or refused naming `what` when it exceeds kMostCount.
long long checked_product(const std::vector<long long>& counts, const std::string& what) {
  double product = 1;
  std::string shape;
  for (size_t d = 0; d < counts.size(); ++d) {
    product *= static_cast<double>(counts[d]);
    shape += (d ? " x " : "") + std::to_string(counts[d]);
  }
  if (!(product <= kMostCount)) refuse(what, " holds ", shape, " = ", product, " points, more than PoreSPH counts (2^62)");
  long long exact = 1;
  for (long long c : counts) exact *= c;  // no overflow: bounded above
  return exact;
}

// A body force is held by pressure differences, so by density differences
// of about |F| L / c^2 of rho0, and the state holds rho itself, to 1.1e-16
// of it: differences near that are round-off. Measured on the square array
// c = 0.2 (one grain a cell, where |F| L / c^2 is the largest variation
// seen): k moves from the steady solve's by 2e-7, 6e-6, 1.9e-4, 1.7e-3 and
// 1.9e-2 at variations of 3e-10, 3e-11, 2.8e-12, 2.6e-13 and 2.4e-14 (about
// 2.3 x 2.2e-16 over the variation), and at 1e-30 m/s^2 the march reported
// k = -1.5e4 m^2 as steady. The estimate uses the cell's largest side, so
// a medium of many pores, whose variations are smaller, is judged leniently.
void check_density_resolution(SceneConfig& scene, const DerivedParameters& derived) {
  const double force = body_force_magnitude(scene) * scene.largest_force_factor();
  const double c = derived.sound_speed, length = derived.length_scale;
  if (!(force > 0) || !(c > 0) || !(length > 0)) return;
  const double variation = force * length / (c * c);
  constexpr double kRefused = 1e-13, kWarned = 1e-10;
  if (variation >= kWarned) return;
  std::ostringstream msg;
  msg.precision(3);
  msg << "Fluid/Body Force of " << force << " m/s^2 holds density differences of about |F| L / c^2 = " << variation
      << " of the fluid's density (L = " << length << " m, speed of sound c = " << c
      << " m/s), and the density is held to 1.1e-16 of itself: ";
  const double error = 5e-16 / variation;
  if (error >= 0.01)
    msg << "k would be round-off more than flow. ";
  else
    msg << "k carries a round-off error of about " << error << " of itself. ";
  if (scene.sound_speed > 0) {
    msg << "A Fluid/Sound Speed of " << std::sqrt(force * length / kWarned) << " m/s or less keeps it below 5e-6";
  } else {
    // Where c is raised to the viscous limit (fixed particles) a larger
    // force helps; where c follows the flow's speed, F L^2 / (8 nu), a larger
    // force gives a faster flow and smaller differences, and the way out is
    // a slower one. The nearest power of ten of the force that does it is
    // found by the same rule the run will use.
    double advised = 0;
    for (int decade = 1; decade <= 40 && advised == 0; ++decade)
      for (const double factor : {std::pow(10.0, decade), std::pow(10.0, -decade)}) {
        SceneConfig trial = scene;
        for (int d = 0; d < scene.dimension; ++d) trial.body_force[d] *= factor;
        try {
          const DerivedParameters p = derive_parameters(trial);
          if (force * factor * p.length_scale / (p.sound_speed * p.sound_speed) >= kWarned) {
            advised = factor;
            break;
          }
        } catch (const std::invalid_argument&) {
        }
      }
    if (advised > 1)
      msg << "Creeping-flow k does not depend on the force: a Fluid/Body Force of " << force * advised
          << " m/s^2 keeps it below 5e-6";
    else if (advised > 0)
      msg << "The speed of sound follows the flow's speed here (F L^2 / (8 nu) = " << derived.velocity_scale
          << " m/s, a fast flow), so a smaller force holds larger differences: a Fluid/Body Force of "
          << force * advised << " m/s^2 keeps it below 5e-6";
    else
      msg << "Fluid/Sound Speed or Fluid/Velocity Scale, given, sets c for the flow";
  }
  if (variation < kRefused) refuse(msg.str());
  scene.warnings.push_back(msg.str());
}

}  // namespace

long long steps_to_end_time(double end_time, double dt) {
  const double steps = std::round(end_time / dt);
  if (!(steps < kMostCount)) return std::numeric_limits<long long>::max();
  return std::max(1LL, static_cast<long long>(steps));
}

long long last_step(double end_time, double dt, long long max_steps) {
  const long long to_end = steps_to_end_time(end_time, dt);
  if (max_steps > 0) return std::min(to_end, max_steps);
  if (to_end == std::numeric_limits<long long>::max()) {
    std::ostringstream msg;
    msg << "Run/End Time = " << end_time << " s at a time step of " << dt << " s is " << end_time / dt
        << " steps: more than PoreSPH counts (2^62); shorten Run/End Time or set Run/Max Steps";
    throw ParameterError(msg.str());
  }
  return to_end;
}

std::string human_bytes(double bytes) {
  const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (bytes >= 1000 && u < 6) bytes /= 1000, ++u;
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, bytes < 10 ? "%.2g %s" : "%.0f %s", bytes, units[u]);
  return buffer;
}

MemoryBudget memory_budget(const SceneConfig& scene, int processes_on_machine) {
  return machine_memory_budget(scene.memory_limit_bytes, processes_on_machine);
}

RunEstimate check_scene(SceneConfig& scene, int ranks, const MemoryBudget& budget) {
  RunEstimate e;
  const int D = scene.dimension;
#ifndef KOKKOS_ENABLE_OPENMP
  if (scene.backend == Backend::OpenMP)
    refuse("Run/Backend = openmp, but this build's Kokkos has no OpenMP backend (Debian's is Serial only); "
           "build one with scripts/build-trilinos-openmp.sh and configure with cmake --preset openmp");
  if (scene.threads > 1)
    scene.warnings.push_back("Run/Threads = " + std::to_string(scene.threads) +
                             ", but this build's Kokkos has no OpenMP backend: each process runs one thread "
                             "(run more processes with mpirun, or build the OpenMP backend: docs/building.md)");
#endif
  try {
    e.derived = derive_parameters(scene);
    // The paper's process grid must match the number of processes (RCB fits any).
    if (scene.grid_decomposition) D == 2 ? static_cast<void>(decompose<2>(scene, ranks))
                                         : static_cast<void>(decompose<3>(scene, ranks));
  } catch (const std::invalid_argument& error) {
    throw ParameterError(error.what());
  }
  check_density_resolution(scene, e.derived);
  // Every level of the resolution ladder must fit the cell too.
  std::vector<double> spacings;
  try {
    spacings = level_spacings(scene);
  } catch (const std::invalid_argument& error) {
    throw ParameterError(error.what());
  }
  // A periodic side must hold the kernel's reach (3h, and the skin of moving
  // particles) at every level's spacing: a particle must not meet its own image.
  for (size_t l = 0; l < spacings.size(); ++l)
    for (int d = 0; d < D; ++d) {
      const double reach = list_reach(scene) * spacings[l];
      if (!scene.periodic[d] || scene.cell_size[d] > reach) continue;
      std::ostringstream level;
      if (spacings.size() > 1) level << " (level " << l + 1 << " of Convergence/Levels " << spacings.size() << ")";
      refuse("Domain/Cell Size[", d, "] = ", scene.cell_size[d], " is not wider than the kernel's reach at spacing ",
             spacings[l], level.str(), ", ", reach, " (3h",
             scene.particle_motion == ParticleMotion::Fixed ? "" : " + Discretization/Neighbour Skin",
             ", h = Discretization/Smoothing Length Ratio x spacing): a periodic cell must be wider. "
             "Use a spacing smaller than ", scene.cell_size[d] / list_reach(scene),
             spacings.size() > 1 ? " at the coarsest level (fewer levels, or a smaller ratio)" : "");
    }
  for (size_t l = 0; l + 1 < spacings.size(); ++l) {
    SceneConfig level = scene;
    level.particle_spacing = spacings[l];
    lattice_counts(level);
    // A throat a coarser level cannot resolve would carry no flow there; its
    // warnings (under three spacings) are the coarse levels' lot and not repeated.
    try {
      check_pores(level);
    } catch (const std::invalid_argument& error) {
      std::ostringstream msg;
      msg << "Convergence/Levels: level " << l + 1 << " of " << spacings.size() << " (spacing " << spacings[l]
          << "): " << error.what();
      throw ParameterError(msg.str());
    }
  }
  const auto counts = lattice_counts(scene);
  e.lattice_points = checked_product(counts, "the particle lattice (Domain/Cell Size / Discretization/Particle Spacing)");
  e.particles = e.lattice_points;
  if (!scene.grid_points.empty()) {
    e.grid_nodes = checked_product(std::vector<long long>(scene.grid_points.begin(), scene.grid_points.end()),
                                   "the grid of Output/Grid Points");
  }

  // Per process: its share of the lattice and the ghosts around it (a layer
  // (3 + skin) h deep on every side of a box of that many points).
  const int threads = std::max(1, scene.threads);
  const SlotBytes slot = bytes_per_slot(scene, threads);
  const double owned = static_cast<double>(e.particles) / ranks;
  const double side = std::pow(std::max(owned, 1.0), 1.0 / D);
  const double layer = list_reach(scene);  // ghosts reach as far as the lists
  const double slots = owned * std::pow((side + 2 * layer) / side, D);
  const double pairs = 0.5 * owned * neighbour_ball(scene);
  std::ostringstream lattice;
  lattice.precision(4);
  for (int d = 0; d < D; ++d) lattice << (d ? " x " : "") << counts[d];
  // The gridded view: each process interpolates its share of the nodes into
  // a View, copies it to the host and splits it into the written arrays.
  const double grid_per_process = static_cast<double>(e.grid_nodes) / ranks * (3.0 * (D + 2) + 5) * 8;
  e.bytes_per_process = std::max(slots * slot.run + grid_per_process, owned * slot.setup + slots * slot.run / 2);
  // Every process holds its piece of the image (its box and a halo,
  // scene/ImagePieces.hpp): its values (2 bytes a voxel) and its distance
  // field, on the host and in the kernels' memory (4 + 4).
  if (scene.image.voxels) e.bytes_per_process += 10.0 * static_cast<double>(scene.image.voxels->count());
  // A moving interface's phase field is whole on every process (physics/PhaseField.hpp):
  // at its peak, in the interface stage, per lattice point the fluid flag (1), phi,
  // the fluid points' list, the update's change, the gathered points, the fluid
  // particles' points and the solids' cos(theta) (8 each), the neighbours (2 D
  // values of 8 bytes), the layer's distance s (8), and four vectors of D
  // values: the velocities gathered and on the lattice, the normals and the
  // surface force; and on the lattice padded by twice the kernel's reach each
  // side, the surface force's phi, each point's source and at most one
  // reached wall point's index (8 each).
  if (scene.moving_interface) {
    const double reach = std::ceil(kSupportRadiusInH * scene.smoothing_length_ratio - 1e-9);
    double padded = 1;
    for (int d = 0; d < D; ++d) padded *= static_cast<double>(counts[d]) + 4 * reach;
    e.bytes_per_process += (57.0 + 48.0 * D) * static_cast<double>(e.lattice_points) + 24.0 * padded;
  }
  // The steady solver (as its bytes_per_particle counts): its vectors for
  // the owned particles with the Krylov bases at their whole restart
  // (steady_vector_values); per process, the two lattice preconditioners,
  // gathered whole, at most about 10.5 values a lattice point each
  // (LatticePreconditioner::values_held: the multigrid's levels in floats
  // 4, the gathered values and their indices 4.5 a fluid point, the wide
  // one's sharpening 1.5, the gathered result 1 with more than one process).
  double steady_per_process = 0;
  if (scene.steady_solver) {
    const int restart = std::max(1, scene.solver.restart);
    // The inner cap may be raised (Solver/Raised Inner Iterations), and the restart with it.
    const int inner_cap = std::max(scene.solver.max_inner_iterations, scene.solver.raised_inner_iterations);
    const int inner_restart = std::max(1, std::min(scene.solver.inner_restart, inner_cap));
    const double vectors = steady_vector_values(2.0 * restart + 1, 2.0 * inner_restart + 1, D * owned, owned);
    steady_per_process = 8.0 * (vectors + 21.0 * static_cast<double>(e.lattice_points));
    // Solver/DG Preconditioner = schwarz: the blocks' factors, shared out
    // among the processes ('auto' switches to them only where they fit).
    if (scene.solver.dg_preconditioner == DgPreconditioner::Schwarz)
      steady_per_process += 8.0 * owned * schwarz_factor_values(D);
    e.bytes_per_process += steady_per_process;
  }
  // A warm start holds the stage before it while it sets up: the next
  // coarser level, or the finest level itself for the Darcy check.
  if (scene.linearity_check) e.bytes_per_process *= 2;
  else if (spacings.size() > 1) e.bytes_per_process *= 1 + std::pow(spacings[spacings.size() - 1] / spacings[spacings.size() - 2], D);
  e.bytes = e.bytes_per_process * ranks;

  const double need = e.bytes_per_process * budget.processes_on_machine;
  if (need > budget.available_bytes) {
    std::ostringstream grid;
    if (e.grid_nodes > 0 && grid_per_process > 0.5 * e.bytes_per_process)
      grid << "; the grid of Output/Grid Points alone (" << e.grid_nodes << " nodes) needs "
           << human_bytes(grid_per_process * budget.processes_on_machine);
    if (steady_per_process > 0.5 * e.bytes_per_process)
      grid << "; the steady solver's vectors alone need " << human_bytes(steady_per_process * budget.processes_on_machine)
           << " (Solver/Krylov Restart and Solver/Inner Krylov Restart set how many it keeps)";
    refuse("the run needs about ", e.particles, " particles (lattice ", lattice.str(),
           " at Discretization/Particle Spacing = ", scene.particle_spacing, ") and about ", human_bytes(need),
           " of memory on this machine (", budget.processes_on_machine, " process",
           budget.processes_on_machine == 1 ? "" : "es", ")", grid.str(), ", but it has ",
           human_bytes(budget.available_bytes), " (", budget.source,
           "). Coarsen the spacing, shrink the grid, or run on more machines; Run/Memory Limit sets the limit");
  }
  if (slots * 1.25 > kMostIndex || pairs * 1.25 > kMostIndex) {
    const double needed = std::ceil(ranks * std::max(slots, pairs) * 1.25 / kMostIndex);
    refuse("about ", e.particles, " particles (lattice ", lattice.str(), ") on ", ranks, " process",
           ranks == 1 ? "" : "es", " is ", owned, " particles and ", pairs,
           " neighbour pairs per process: more than a process indexes (2^31 - 1); run on at least ", needed,
           " processes or coarsen Discretization/Particle Spacing");
  }
  // Moving fluid particles cannot keep their own distance to an image's
  // surface (Solid.hpp): they see the boundary particles' tangent planes.
  if (scene.image.voxels && scene.particle_motion == ParticleMotion::Lagrangian)
    scene.warnings.push_back(
        "Discretization/Particle Motion = lagrangian with Image/File: moving fluid particles measure the no-slip "
        "distances from the boundary particles' tangent planes, not from their own distance to the surface, which "
        "underestimates k on curved walls (-11 % on a sphere of 6 spacings' radius; docs/method.md)");
  // A steady solve makes no time steps: Run/End Time and Run/Max Steps are the march's.
  if (scene.steady_solver) return e;
  e.steps = last_step(scene.end_time, e.derived.time_step, scene.max_steps);
  if (scene.end_time < 0.5 * e.derived.time_step) {
    std::ostringstream msg;
    msg << "Run/End Time = " << scene.end_time << " s is less than half the time step (" << e.derived.time_step
        << " s): the run makes one step, to t = " << e.derived.time_step << " s";
    scene.warnings.push_back(msg.str());
  }
  return e;
}

}  // namespace poresph
