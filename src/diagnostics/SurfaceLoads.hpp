#pragma once
// The fluid's force on the solid, surface by surface: on each grain its
// force and its torque about its centre, on the plane walls and on an
// image's solid their totals. Each boundary particle's force is the
// reaction to what the fluid gains from it in the pair loop
// (Simulation::surface_load_sums), so that the loads and the fluid's momentum
// change from its surfaces add to zero to round-off; at a steady state the
// loads hold up the body force on the fluid (body_force_on_fluid).
#include <Kokkos_Core.hpp>
#include <array>
#include <vector>

#include "core/Particles.hpp"

namespace poresph {

template <int Dim>
struct SurfaceLoads {
  static constexpr int kTorqueComponents = Dim == 2 ? 1 : 3;  // about the axis out of the plane in 2D
  using Force = std::array<double, Dim>;
  using Torque = std::array<double, kTorqueComponents>;
  std::vector<Force> grain_force;  // by the scene's grain index
  std::vector<Torque> grain_torque;
  Force walls{}, image{};
  Force body_force_on_fluid{};  // the fluid's mass times the body force

  // Over every surface.
  Force total() const {
    Force sum{};
    for (int d = 0; d < Dim; ++d) {
      for (const Force &f : grain_force) sum[d] += f[d];
      sum[d] += walls[d] + image[d];
    }
    return sum;
  }
};

// The loads of the simulation's state, summed over all processes (every
// process returns them): Simulation::surface_load_sums, unpacked.
template <int Dim, class Sim>
SurfaceLoads<Dim> surface_loads(Sim& sim) {
  constexpr int kT = SurfaceLoads<Dim>::kTorqueComponents;
  const std::vector<double> sums = sim.surface_load_sums();
  const int grains = static_cast<int>(sim.scene().grains.size());
  const double* walls = sums.data() + grains * (Dim + kT);
  const double* image = walls + Dim;
  const double fluid_mass = image[Dim];
  SurfaceLoads<Dim> loads;
  loads.grain_force.resize(grains);
  loads.grain_torque.resize(grains);
  for (int g = 0; g < grains; ++g) {
    const double* s = sums.data() + g * (Dim + kT);
    for (int d = 0; d < Dim; ++d) loads.grain_force[g][d] = s[d];
    for (int c = 0; c < kT; ++c) loads.grain_torque[g][c] = s[Dim + c];
  }
  const auto body_force = sim.scene().body_force;
  for (int d = 0; d < Dim; ++d) {
    loads.walls[d] = walls[d], loads.image[d] = image[d];
    loads.body_force_on_fluid[d] = fluid_mass * body_force[d];
  }
  return loads;
}

}  // namespace poresph
