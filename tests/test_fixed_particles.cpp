// Fixed particles (Discretization/Particle Motion = fixed) and the wall
// pressure extrapolated from the fluid (physics/WallPressure.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "Scenes.hpp"
#include "TestSpaces.hpp"
#include "app/Simulation.hpp"
#include "geometry/Grains.hpp"
#include "physics/WallPressure.hpp"

namespace poresph {
namespace {

template <class Space>
class FixedParticles : public ::testing::Test {};
TYPED_TEST_SUITE(FixedParticles, testing::ExecutionSpaces);

// A periodic cell with a grain across the corner and one inside, driven.
// Boundary densities from the continuity equation: at rest they start at
// rho0 like the fluid's (the extrapolated ones carry the hydrostatic part),
// so that both modes see the same volumes in the first step.
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

// Particles that do not move need no positions in the pair loop: the list
// caches each pair's separation and kernel derivative. From rest the first
// step's mid-point is the lattice in both modes, so the velocities after it
// must be those of moving particles, which evaluate the kernel afresh.
TYPED_TEST(FixedParticles, FirstStepMatchesMovingParticlesThroughTheCachedPairs) {
  Simulation<2, TypeParam> fixed(grain_cell(ParticleMotion::Fixed));
  Simulation<2, TypeParam> moving(grain_cell(ParticleMotion::Lagrangian));
  fixed.step();
  moving.step();
  const int n = fixed.particles().owned;
  ASSERT_EQ(n, moving.particles().owned);
  const auto a = host_values<TypeParam>(fixed.particles().v, n), b = host_values<TypeParam>(moving.particles().v, n);
  double largest = 0;
  for (double v : b) largest = std::max(largest, std::abs(v));
  ASSERT_GT(largest, 0.0);
  for (size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(a[k], b[k], 1e-12 * largest) << k;
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
