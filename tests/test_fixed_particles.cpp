// Fixed particles (Discretization/Particle Motion = fixed) and the wall
// pressure extrapolated from the fluid (physics/WallPressure.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "Scenes.hpp"
#include "TestSpaces.hpp"
#include "app/Simulation.hpp"
#include "geometry/Grains.hpp"
#include "physics/Density.hpp"
#include "physics/PredictorCorrector.hpp"
#include "physics/WallPressure.hpp"

namespace poresph {
namespace {

template <class Space>
class FixedParticles : public ::testing::Test {};
TYPED_TEST_SUITE(FixedParticles, testing::ExecutionSpaces);

// A periodic cell with a grain across the corner and one inside, driven.
// Boundary densities from the continuity equation: they start at rho0 like
// the fluid's (the extrapolated ones carry the hydrostatic part), so that
// both modes see the same volumes.
SceneConfig grain_cell(ParticleMotion motion) {
  SceneConfig s = testing::periodic_box(2, 30);
  s.grains = grains_from_list({0.0, 0.0, 0.2, 0.55, 0.5, 0.15}, 2);
  s.body_force = {0.05, 0.02, 0};
  s.velocity_scale = 0.05;
  s.particle_motion = motion;
  s.convection = false;
  s.wall_pressure = WallPressure::Continuity;
  return s;
}

template <class Space>
std::vector<double> host_values(const Kokkos::View<double* [2], typename Space::memory_space>& view, int n) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view);
  std::vector<double> values;
  for (int i = 0; i < n; ++i) values.push_back(h(i, 0)), values.push_back(h(i, 1));
  return values;
}

// Distance from x to the nearest surface of grain_cell's grains (periodic unit cell).
double distance_to_grains(double x, double y) {
  const double grains[2][3] = {{0.0, 0.0, 0.2}, {0.55, 0.5, 0.15}};
  double nearest = 1e300;
  for (const auto& g : grains)
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j) nearest = std::min(nearest, std::hypot(x - g[0] - i, y - g[1] - j) - g[2]);
  return nearest;
}

// Particles that do not move need no positions in the pair loop: the list
// caches each pair's separation and kernel derivative, and next to a
// surface each pair's no-slip factor. The rates on the lattice must be
// those of moving particles, which evaluate all of it afresh, in a stirred
// box and in a grain cell. Fixed particles carry a boundary neighbour's
// drag kappa apart (FluidProperties::separate_wall_drag): their rate is
// dv/dt - kappa v. Compared where both bound the distance to the surface
// alike: farther than moving particles' bound, sqrt(3)/4 dx.
template <class Space>
void expect_rates_of_moving_particles(SceneConfig scene) {
  scene.particle_motion = ParticleMotion::Fixed;
  Simulation<2, Space> fixed(scene);
  scene.particle_motion = ParticleMotion::Lagrangian;
  Simulation<2, Space> moving(scene);
  testing::randomise_velocities(fixed.particles(), 0.05, 3);
  testing::randomise_velocities(moving.particles(), 0.05, 3);
  fixed.compute_rates();
  moving.compute_rates();
  const int n = fixed.particles().owned;
  ASSERT_EQ(n, moving.particles().owned);
  auto a = host_values<Space>(fixed.particles().dvdt, n);
  const auto b = host_values<Space>(moving.particles().dvdt, n);
  const auto x = host_values<Space>(fixed.particles().x, n), v = host_values<Space>(fixed.particles().v, n);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fixed.particles().kind);
  int next_to_surface = 0;
  if (fixed.particles().has_surfaces) {
    auto drag = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fixed.particles().wall_drag);
    for (int i = 0; i < n; ++i)
      for (int d = 0; d < 2; ++d) a[2 * i + d] -= drag(i) * v[2 * i + d];
    for (int i = 0; i < n; ++i) next_to_surface += kind(i) == kFluid && drag(i) != 0;
  }
  double largest = 0;
  for (double value : b) largest = std::max(largest, std::abs(value));
  int compared = 0, compared_next_to_surface = 0;
  const double bound = std::sqrt(3.0) / 4.0 * scene.particle_spacing;
  for (int i = 0; i < n; ++i) {
    if (kind(i) != kFluid) continue;
    const double distance = scene.grains.empty() ? 1.0 : distance_to_grains(x[2 * i], x[2 * i + 1]);
    if (distance <= bound) continue;
    ++compared;
    compared_next_to_surface += distance < 3 * scene.smoothing_length_ratio * scene.particle_spacing;
    for (int d = 0; d < 2; ++d) EXPECT_NEAR(a[2 * i + d], b[2 * i + d], 1e-12 * largest) << i;
  }
  EXPECT_GT(compared, n / 2);
  EXPECT_GE(compared_next_to_surface, next_to_surface / 2);  // the particles that see a surface are in
}

TYPED_TEST(FixedParticles, CachedPairsGiveTheRatesOfMovingParticles) {
  SceneConfig box = testing::periodic_box(2, 30);
  box.convection = false;
  expect_rates_of_moving_particles<TypeParam>(box);
  expect_rates_of_moving_particles<TypeParam>(grain_cell(ParticleMotion::Fixed));
}

// On the lattice, the pairs' geometry comes from the stencil of lattice
// offsets (core/PairGeometry.hpp), and the pairs from rows as masks over it
// (core/LatticeRows.hpp) without a list. A cell side that is a whole number of
// spacings only to the 1e-6 the lattice allows puts the periodic ghosts a
// little off it: the lists then cache each entry's geometry, and the rates
// are still those of moving particles. A side that misses by what a spacing
// given to ten digits leaves (1e-10 of the side: 3e-9 spacings across the
// seam here) stays on the lattice.
TYPED_TEST(FixedParticles, OffTheLatticeThePairsFallBackToThePerEntryCache) {
  SceneConfig box = testing::periodic_box(2, 30);
  box.convection = false;
  box.particle_motion = ParticleMotion::Fixed;
  for (const double side : {1.0, 1.0 + 1e-10, 1.0 + 1e-7}) {
    box.cell_size[0] = side;
    Simulation<2, TypeParam> sim(box);
    sim.compute_rates();
    const bool on_lattice = side < 1.0 + 1e-8;
    EXPECT_EQ(sim.pairs_on_stencil(), on_lattice) << side;
    EXPECT_EQ(sim.pairs_on_lattice_rows(), on_lattice) << side;  // no list on the lattice
  }
  expect_rates_of_moving_particles<TypeParam>(box);
  SceneConfig grains = grain_cell(ParticleMotion::Fixed);
  grains.wall_pressure = WallPressure::Extrapolated;
  Simulation<2, TypeParam> on_lattice(grains);
  on_lattice.compute_rates();
  EXPECT_TRUE(on_lattice.pairs_on_stencil());
  EXPECT_TRUE(on_lattice.pairs_on_lattice_rows());
}

// The wall pressure extrapolated from the fluid reads, for fixed particles,
// each wall-fluid pair's separation and kernel value cached at the build;
// moving particles evaluate them at every stage. With the same fluid
// densities (perturbed) and body force, both give every boundary particle
// the same pressure.
TYPED_TEST(FixedParticles, CachedWallWeightsGiveTheWallPressureOfMovingParticles) {
  SceneConfig scene = grain_cell(ParticleMotion::Fixed);
  scene.wall_pressure = WallPressure::Extrapolated;
  Simulation<2, TypeParam> fixed(scene);
  scene.particle_motion = ParticleMotion::Lagrangian;
  Simulation<2, TypeParam> moving(scene);
  for (auto* sim : {&fixed, &moving}) {
    auto& P = sim->particles();
    auto rho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.rho);
    auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-0.01, 0.01);
    for (int i = 0; i < P.owned; ++i)
      if (kind(i) == kFluid) rho(i) *= 1 + u(rng);
    Kokkos::deep_copy(P.rho, rho);
    sim->compute_rates();
  }
  const int n = fixed.particles().owned;
  ASSERT_EQ(n, moving.particles().owned);
  auto p_fixed = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fixed.particles().p);
  auto p_moving = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), moving.particles().p);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fixed.particles().kind);
  double lowest = 1e300, highest = -1e300;  // the fluid's pressures differ: the walls' are not a plain copy
  for (int i = 0; i < n; ++i)
    if (kind(i) == kFluid) lowest = std::min(lowest, p_fixed(i)), highest = std::max(highest, p_fixed(i));
  ASSERT_GT(highest - lowest, 1e-3 * std::abs(highest));
  int walls = 0;
  for (int i = 0; i < n; ++i) {
    if (kind(i) == kFluid) continue;
    ++walls;
    EXPECT_NEAR(p_fixed(i), p_moving(i), 1e-12 * std::abs(p_moving(i))) << i;
  }
  EXPECT_GT(walls, 0);
}

// The corrector checks the fixed particles it writes (the per-step check's
// pass over the particles is skipped when it found none unhealthy): a NaN
// velocity must still stop the very step that carries it.
TYPED_TEST(FixedParticles, ANaNVelocityStopsTheStep) {
  Simulation<2, TypeParam> sim(grain_cell(ParticleMotion::Fixed));
  for (int s = 0; s < 3; ++s) sim.step();
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sim.particles().v);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sim.particles().kind);
  int fluid = 0;
  while (kind(fluid) != kFluid) ++fluid;
  v(fluid, 1) = std::numeric_limits<double>::quiet_NaN();
  Kokkos::deep_copy(sim.particles().v, v);
  std::string message;
  try {
    sim.step();
  } catch (const SimulationFailure& failure) {
    message = failure.what();
  }
  EXPECT_NE(message.find("NaN or Inf"), std::string::npos) << message;
  EXPECT_EQ(sim.steps(), 4);
}

// The pair loop takes m and 1/rho as constants when every particle has the
// same mass (a fixed lattice): common_mass must see a single odd one.
TYPED_TEST(FixedParticles, CommonMassIsZeroIfOneParticleDiffers) {
  Simulation<2, TypeParam> sim(grain_cell(ParticleMotion::Fixed));
  auto& P = sim.particles();
  const TypeParam space;
  const double mass = common_mass(space, P, P.total());
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.m);
  EXPECT_EQ(mass, m(0));
  EXPECT_GT(mass, 0.0);
  m(P.total() - 1) *= 1 + 1e-15;  // the last ghost
  Kokkos::deep_copy(P.m, m);
  EXPECT_EQ(common_mass(space, P, P.total()), 0.0);
  EXPECT_EQ(common_mass(space, P, P.total() - 1), mass);
}

TYPED_TEST(FixedParticles, StayOnTheirLatticeWithTheirFirstList) {
  Simulation<2, TypeParam> sim(grain_cell(ParticleMotion::Fixed));
  const int n = sim.particles().owned;
  const auto before = host_values<TypeParam>(sim.particles().x, n);
  for (int s = 0; s < 200; ++s) sim.step();
  EXPECT_EQ(host_values<TypeParam>(sim.particles().x, n), before);
  EXPECT_EQ(sim.neighbour_rebuilds(), 1);
  EXPECT_GT(std::abs(sim.superficial_velocity()[0]), 0.0);  // the fluid did flow
}

TEST(WallDrag, IsIntegratedExactlyHoweverStiff) {
  // dv/dt = a - kappa v from v0: v0 e^{-kappa t} + (a / kappa)(1 - e^{-kappa t}).
  EXPECT_NEAR(velocity_after(1.0, 2.0, 0.5, 3.0), std::exp(-1.5) + 4.0 * (1 - std::exp(-1.5)), 1e-15);
  EXPECT_DOUBLE_EQ(velocity_after(1.0, 2.0, 0.0, 3.0), 7.0);         // no wall: the explicit step
  EXPECT_NEAR(velocity_after(1.0, 2.0, 1e-12, 3.0), 7.0, 1e-10);      // and continuously so
  EXPECT_DOUBLE_EQ(velocity_after(1.0, 2.0, 1e12, 3.0), 2.0 / 1e12);  // a wall a hair away: its limit at once
}

// A lattice point 1e-7 dx outside a grain: its no-slip factor is about
// 3e7. Integrated exactly, it neither blows up nor moves (the bound of
// sqrt(3)/4 dx that moving particles need would let it slip).
TYPED_TEST(FixedParticles, KeepAPointAHairFromTheSurfaceStill) {
  SceneConfig scene = testing::periodic_box(2, 30);
  const double dx = scene.particle_spacing;
  const double distance = std::sqrt(3.5 * 3.5 + 0.5 * 0.5) * dx;  // from (15, 15) dx to the point (18.5, 15.5) dx
  scene.grains = grains_from_list({15 * dx, 15 * dx, distance - 1e-7 * dx}, 2);
  scene.body_force = {0.05, 0, 0};
  scene.velocity_scale = 0.05;
  Simulation<2, TypeParam> sim(scene);
  for (int s = 0; s < 300; ++s) sim.step();
  const auto& P = sim.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  double near = -1, fastest = 0;
  for (int i = 0; i < P.owned; ++i) {
    const double speed = std::hypot(v(i, 0), v(i, 1));
    fastest = std::max(fastest, speed);
    if (std::abs(x(i, 0) - 18.5 * dx) < 1e-9 && std::abs(x(i, 1) - 15.5 * dx) < 1e-9) near = speed;
  }
  ASSERT_GE(near, 0.0) << "the lattice point next to the surface is fluid";
  EXPECT_GT(fastest, 0.0);
  EXPECT_LT(near, 1e-5 * fastest);
}

TEST(WallPressure, IsTheShepardMeanPlusTheHydrostaticPart) {
  // Fluid pressures 1 and 3 with weights 1 and 3 average to 2.5; the body
  // force adds F . sum rho r W / sum W.
  EXPECT_DOUBLE_EQ(extrapolated_wall_pressure(4.0, 1.0 * 1.0 + 3.0 * 3.0, 2.0, 7.0), 3.0);
  EXPECT_DOUBLE_EQ(extrapolated_wall_pressure(0.0, 0.0, 0.0, 7.0), 7.0);  // nothing in reach
}

// Fluid at rest between walls under a body force towards the lower wall:
// the pressure must rise towards it as rho g, and nothing may flow. The
// wall's pressure carries the hydrostatic part across the gap; without it
// the fluid next to the wall would sink towards it.
TYPED_TEST(FixedParticles, HoldHydrostaticFluidAtRestBetweenWalls) {
  SceneConfig scene = testing::channel(20);
  const double g = 2e-4;
  scene.body_force = {0, -g, 0};
  scene.velocity_scale = 2.5e-5;
  Simulation<2, TypeParam> sim(scene);
  for (int s = 0; s < 3000; ++s) sim.step();
  const auto& P = sim.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto p = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.p);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  // Least-squares slope of p against y over the fluid, and the largest speed.
  double sy = 0, sp = 0, syy = 0, syp = 0, n = 0, fastest = 0;
  for (int i = 0; i < P.owned; ++i) {
    if (kind(i) != kFluid) continue;
    sy += x(i, 1), sp += p(i), syy += x(i, 1) * x(i, 1), syp += x(i, 1) * p(i), ++n;
    fastest = std::max(fastest, std::hypot(v(i, 0), v(i, 1)));
  }
  const double slope = (n * syp - sy * sp) / (n * syy - sy * sy), intercept = (sp - slope * sy) / n;
  EXPECT_NEAR(slope, -scene.density * g, 0.01 * scene.density * g);
  EXPECT_LT(fastest, 1e-3 * g * 1.0);  // g times a second: far below what free fall would give
  // The walls continue the fluid's profile: the Shepard mean alone would
  // give each wall particle the pressure of the fluid about two spacings away.
  const double dx = scene.particle_spacing;
  int walls = 0;
  const double width = scene.cell_size[1];
  for (int i = 0; i < P.owned; ++i) {
    const double depth = std::max(-x(i, 1), x(i, 1) - width);
    if (kind(i) != kWallBoundary || depth > 2.4 * dx) continue;  // deeper: no fluid within 3h to see it
    ++walls;
    EXPECT_NEAR(p(i), intercept + slope * x(i, 1), 0.05 * scene.density * g * dx) << "wall particle at y = " << x(i, 1);
  }
  EXPECT_GT(walls, 0);
}

}  // namespace
}  // namespace poresph
