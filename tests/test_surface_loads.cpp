// The fluid's force on grains and walls (diagnostics/SurfaceLoads.hpp):
// each boundary particle takes the reaction to what the fluid gains from it
// in the pair loop, so that the loads and the fluid's momentum change from
// its surfaces add to zero to round-off, whatever the state.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "Scenes.hpp"
#include "TestSpaces.hpp"
#include "app/Simulation.hpp"
#include "diagnostics/SurfaceLoads.hpp"
#include "geometry/Grains.hpp"

namespace poresph {
namespace {

template <class Space>
class SurfaceLoadsTest : public ::testing::Test {};
TYPED_TEST_SUITE(SurfaceLoadsTest, testing::ExecutionSpaces);

// A periodic cell with a grain across the corner and one inside, driven.
SceneConfig grain_cell(ParticleMotion motion, WallPressure wall_pressure, std::array<double, 3> force) {
  SceneConfig s = testing::periodic_box(2, 30);
  s.grains = grains_from_list({0.0, 0.0, 0.2, 0.55, 0.5, 0.15}, 2);
  s.body_force = force;
  s.velocity_scale = 0.05;
  s.particle_motion = motion;
  s.convection = false;
  s.wall_pressure = wall_pressure;
  return s;
}

// Channel walls and a grain between them.
SceneConfig channel_with_grain() {
  SceneConfig s = testing::channel(20);
  s.grains = grains_from_list({0.25e-3, 0.4e-3, 0.15e-3}, 2);
  s.body_force = {1e-4, 0, 0};
  s.velocity_scale = 1e-5;
  s.convection = false;
  return s;
}

struct Balance {
  double residual = 0;  // |sum of the fluid's m (dv/dt - g) + the loads|
  double scale = 0;     // sum of |m (dv/dt - g)| over the fluid
};

// The fluid's momentum change from its pairs, m (dv/dt - g) with dv/dt =
// dvdt - wall_drag v, summed, plus the loads on every surface.
template <int Dim, class Space>
Balance momentum_balance(Simulation<Dim, Space> &sim, const SurfaceLoads<Dim> &loads) {
  const auto &P = sim.particles();
  auto dvdt = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.dvdt);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.m);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  auto drag = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.wall_drag);
  double sum[Dim] = {}, scale = 0;
  for (int i = 0; i < P.owned; ++i) {
    if (kind(i) != kFluid) continue;
    double size = 0;
    for (int d = 0; d < Dim; ++d) {
      const double change = m(i) * (dvdt(i, d) - drag(i) * v(i, d) - sim.scene().body_force[d]);
      sum[d] += change;
      size += change * change;
    }
    scale += std::sqrt(size);
  }
  const auto total = loads.total();
  Balance b;
  for (int d = 0; d < Dim; ++d) b.residual += (sum[d] + total[d]) * (sum[d] + total[d]);
  b.residual = std::sqrt(b.residual);
  b.scale = scale;
  return b;
}

// A disturbed flow a few steps on, its rates, and the loads of that state.
template <int Dim, class Space>
void expect_balance(SceneConfig scene, const std::string &what) {
  Simulation<Dim, Space> sim(scene);
  testing::randomise_velocities(sim.particles(), 0.2 * scene.velocity_scale, 7);
  for (int s = 0; s < 5; ++s) sim.step();
  sim.compute_rates();
  const SurfaceLoads<Dim> loads = sim.surface_loads();
  const Balance b = momentum_balance(sim, loads);
  ASSERT_GT(b.scale, 0) << what;
  EXPECT_LT(b.residual, 1e-13 * b.scale) << what;
  // The surfaces take a share that is not round-off.
  double surfaces = 0;
  for (double f : loads.total()) surfaces += f * f;
  EXPECT_GT(std::sqrt(surfaces), 1e-3 * b.scale) << what;
}

TYPED_TEST(SurfaceLoadsTest, BalanceTheFluidsMomentumChangeFixedAndMoving) {
  const std::array<double, 3> force{0.05, 0.02, 0};
  for (const auto motion : {ParticleMotion::Fixed, ParticleMotion::Lagrangian})
    for (const auto wall_pressure : {WallPressure::Extrapolated, WallPressure::Continuity})
      expect_balance<2, TypeParam>(grain_cell(motion, wall_pressure, force),
                                   std::string(motion == ParticleMotion::Fixed ? "fixed" : "moving") +
                                       (wall_pressure == WallPressure::Extrapolated ? ", extrapolated wall pressure"
                                                                                    : ", boundary continuity"));
}

TYPED_TEST(SurfaceLoadsTest, BalanceTheFluidsMomentumChangeWallsAndGrains) {
  expect_balance<2, TypeParam>(channel_with_grain(), "channel walls and a grain");
}

TYPED_TEST(SurfaceLoadsTest, BalanceTheFluidsMomentumChangeIn3D) {
  SceneConfig s = testing::periodic_box(3, 12);
  s.grains = grains_from_list({0.5, 0.5, 0.5, 0.3}, 3);
  s.body_force = {0.05, 0.0, 0.02};
  s.velocity_scale = 0.05;
  s.convection = false;
  expect_balance<3, TypeParam>(s, "3D sphere");
}

// Driven along x, the grain cell is symmetric about the grains' centre
// lines y = 0 and y = 0.5: no torque, and the drag points along the flow.
TYPED_TEST(SurfaceLoadsTest, SymmetricFlowTurnsNoGrain) {
  Simulation<2, TypeParam> sim(grain_cell(ParticleMotion::Fixed, WallPressure::Extrapolated, {0.05, 0, 0}));
  for (int s = 0; s < 50; ++s) sim.step();
  const SurfaceLoads<2> loads = sim.surface_loads();
  const double radius[2] = {0.2, 0.15};
  for (int g = 0; g < 2; ++g) {
    const double drag = loads.grain_force[g][0];
    EXPECT_GT(drag, 0) << "grain " << g;
    EXPECT_LT(std::abs(loads.grain_force[g][1]), 1e-10 * drag) << "grain " << g;
    EXPECT_LT(std::abs(loads.grain_torque[g][0]), 1e-10 * drag * radius[g]) << "grain " << g;
  }
}

// A grain off the centre line of a channel, near the lower wall, turns: the
// flow is faster on its side away from that wall, so the viscous pull is
// greater on its upper side: a clockwise, negative torque, with x along the
// flow and y up.
TYPED_TEST(SurfaceLoadsTest, GrainNearAWallTurnsAwayFromIt) {
  SceneConfig s = channel_with_grain();
  s.grains = grains_from_list({0.25e-3, 0.3e-3, 0.1e-3}, 2);
  Simulation<2, TypeParam> sim(s);
  for (int step = 0; step < 400; ++step) sim.step();
  const SurfaceLoads<2> loads = sim.surface_loads();
  const double drag = loads.grain_force[0][0];
  EXPECT_GT(drag, 0);
  EXPECT_LT(loads.grain_torque[0][0], -1e-3 * drag * 0.1e-3);
}

}  // namespace
}  // namespace poresph
