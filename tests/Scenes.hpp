#pragma once
// Small scenes built in code for tests.
#include <Kokkos_Core.hpp>

#include <random>

#include "scene/SceneConfig.hpp"

namespace poresph::testing {

// Periodic box of n x n (x n) particles of spacing dx = 1/n, unit density.
inline SceneConfig periodic_box(int dim, int n) {
  SceneConfig s;
  s.name = "periodic-box";
  s.dimension = dim;
  for (int d = 0; d < 3; ++d) s.cell_size[d] = 1.0, s.periodic[d] = true;
  s.density = 1.0;
  s.kinematic_viscosity = 0.01;
  s.particle_spacing = 1.0 / n;
  s.sound_speed = 1.0;
  s.end_time = 1.0;
  return s;
}

// Morris et al. (1997) channel: L = 1 mm, nu = 1e-6, rho = 1000, `across`
// particles between the walls, periodic length half the width.
inline SceneConfig channel(int across) {
  SceneConfig s;
  s.name = "channel";
  s.dimension = 2;
  s.cell_size = {0.5e-3, 1e-3, 0};
  s.periodic = {true, false, true};
  s.density = 1000;
  s.kinematic_viscosity = 1e-6;
  s.particle_spacing = 1e-3 / across;
  s.walls = WallType::Channel;
  s.end_time = 1.0;
  return s;
}

// Adds a random velocity of the given amplitude to every fluid particle.
template <class ParticleSet>
void randomise_velocities(ParticleSet& P, double amplitude, unsigned seed) {
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  for (int i = 0; i < P.owned; ++i)
    for (int d = 0; d < static_cast<int>(v.extent(1)); ++d)
      if (kind(i) == 0) v(i, d) += u(rng);
  Kokkos::deep_copy(P.v, v);
}

}  // namespace poresph::testing
