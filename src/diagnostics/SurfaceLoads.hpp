#pragma once
// The fluid's force on the solid, surface by surface: on each grain its
// force and its torque about its centre, on the plane walls and on an
// image's solid their totals. Each boundary particle's force is the
// reaction to what the fluid gains from it in the pair loop
// (Simulation::surface_forces), so that the loads and the fluid's momentum
// change from its surfaces add to zero to round-off; at a steady state the
// loads hold up the body force on the fluid (body_force_on_fluid).
#include <Kokkos_Core.hpp>
#include <array>
#include <stdexcept>
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

// r x F: the torque's one component in 2D, three in 3D.
template <int Dim>
typename SurfaceLoads<Dim>::Torque torque_of(const double *r, const double *F) {
  if constexpr (Dim == 2) {
    return {r[0] * F[1] - r[1] * F[0]};
  } else {
    return {r[1] * F[2] - r[2] * F[1], r[2] * F[0] - r[0] * F[2], r[0] * F[1] - r[1] * F[0]};
  }
}

// The loads of the simulation's state, summed over all processes (every
// process returns them).
template <int Dim, class Sim>
SurfaceLoads<Dim> surface_loads(Sim &sim) {
  const auto force = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sim.surface_forces());
  const auto grain = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sim.grain_ids());
  const auto &P = sim.particles();
  const auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  const auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.m);
  const auto wall_vector = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.wall_vector);
  const int grains = static_cast<int>(sim.scene().grains.size());
  constexpr int kT = SurfaceLoads<Dim>::kTorqueComponents;
  // grain forces, grain torques, walls, image, the fluid's mass: one reduction
  std::vector<double> sums(grains * (Dim + kT) + 2 * Dim + 1, 0.0);
  double *walls = sums.data() + grains * (Dim + kT);
  double *image = walls + Dim;
  double &fluid_mass = image[Dim];
  for (int i = 0; i < P.owned; ++i) {
    double F[Dim];
    for (int d = 0; d < Dim; ++d) F[d] = force(i, d);
    if (kind(i) == kFluid) {
      fluid_mass += m(i);
    } else if (kind(i) == kGrainBoundary) {
      if (grain(i) < 0) throw std::logic_error("surface_loads: a grain's boundary particle that no grain has");
      double *g = sums.data() + grain(i) * (Dim + kT);
      double r[Dim];  // from the grain's centre
      for (int d = 0; d < Dim; ++d) g[d] += F[d], r[d] = wall_vector(i, d);
      const auto torque = torque_of<Dim>(r, F);
      for (int c = 0; c < kT; ++c) g[Dim + c] += torque[c];
    } else {
      double *total = kind(i) == kSampledBoundary ? image : walls;
      for (int d = 0; d < Dim; ++d) total[d] += F[d];
    }
  }
  sim.communicator().sum(sums.data(), static_cast<int>(sums.size()));
  SurfaceLoads<Dim> loads;
  loads.grain_force.resize(grains);
  loads.grain_torque.resize(grains);
  for (int g = 0; g < grains; ++g) {
    const double *s = sums.data() + g * (Dim + kT);
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
