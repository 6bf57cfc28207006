#pragma once
// Small scenes built in code for tests.
#include <Kokkos_Core.hpp>

#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "geometry/DistanceTransform.hpp"
#include "geometry/VoxelImage.hpp"
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

// A channel of 16 x 5 voxels (one particle a voxel) and pockets of pore
// space above it, in a periodic cell of 16 x 24: B, 5 x 3 voxels behind a
// wall of 2; A, 4 x 4, sealed by 9 voxels of solid or more (beyond the
// kernel's reach). with_wall_pocket: B is pore space.
inline SceneConfig pocket_cell(bool with_wall_pocket) {
  constexpr int nx = 16, ny = 24;
  VoxelImage image;
  image.shape = {nx, ny, 1};
  image.values.assign(nx * ny, 1);  // solid
  auto open = [&](int x0, int x1, int y0, int y1) {
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) image.values[image.index(x, y)] = 0;
  };
  open(0, nx - 1, 0, 4);                   // the channel
  if (with_wall_pocket) open(2, 6, 7, 9);  // B
  open(8, 11, 14, 17);                     // A
  SceneConfig s = periodic_box(2, nx);
  const double voxel = 1.0 / nx;
  s.cell_size = {1.0, ny * voxel, 0};
  s.image.solid_values = {1};
  s.image.voxel_size = voxel;
  s.image.distance = std::make_shared<const std::vector<float>>(surface_distance(image, {1}, voxel, s.periodic));
  s.image.voxels = std::make_shared<const VoxelImage>(std::move(image));
  s.body_force = {1e-3, 0, 0};
  s.sound_speed = 0;
  s.particle_motion = ParticleMotion::Fixed;
  s.convection = false;
  return s;
}

}  // namespace poresph::testing
