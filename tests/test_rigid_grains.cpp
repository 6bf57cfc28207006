// Grains that move (physics/RigidGrains.hpp): rigid, driven by the same
// pair terms as the fluid so that fluid and grains exchange momentum
// exactly, and settling at the speed that the drag of the same array held
// still gives.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include "Scenes.hpp"
#include "app/Simulation.hpp"
#include "geometry/Grains.hpp"
#include "physics/WallPressure.hpp"

namespace poresph {
namespace {

using Space = Kokkos::Serial;

// A periodic cell with two free grains in a moving fluid.
SceneConfig free_grains(int n) {
  SceneConfig s = testing::periodic_box(2, n);
  s.grains = grains_from_list({0.3, 0.35, 0.15, 0.72, 0.68, 0.12}, 2);
  s.particle_motion = ParticleMotion::Lagrangian;
  s.grain_motion = GrainMotion::Free;
  s.grain_density = 2.5;
  s.velocity_scale = 0.05;
  return s;
}

// Sum over fluid particles of m v, plus each grain's m U.
Vec<2> total_momentum(const Simulation<2, Space>& sim, double& scale) {
  const auto& P = sim.particles();
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.m);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  Vec<2> total = Vec<2>::zero();
  scale = 0;
  for (int i = 0; i < P.owned; ++i) {
    if (kind(i) != kFluid) continue;
    for (int d = 0; d < 2; ++d) total[d] += m(i) * v(i, d);
    scale += m(i) * std::hypot(v(i, 0), v(i, 1));
  }
  for (const auto& b : sim.rigid_grains().bodies())
    for (int d = 0; d < 2; ++d) total[d] += b.mass * b.velocity[d];
  return total;
}

// No external force: what the fluid loses the grains gain, step by step.
TEST(RigidGrains, FluidAndGrainsConserveMomentum) {
  SceneConfig scene = free_grains(30);
  Simulation<2, Space> sim(scene);
  testing::randomise_velocities(sim.particles(), 0.02, 11);
  sim.compute_rates();
  double scale = 0;
  const Vec<2> before = total_momentum(sim, scale);
  for (int s = 0; s < 200; ++s) sim.step();
  double scale_after = 0;
  const Vec<2> after = total_momentum(sim, scale_after);
  double grain_momentum = 0;
  for (const auto& b : sim.rigid_grains().bodies()) grain_momentum += b.mass * std::hypot(b.velocity[0], b.velocity[1]);
  EXPECT_GT(grain_momentum, 1e-3 * scale) << "the grains were set moving";
  for (int d = 0; d < 2; ++d) EXPECT_LT(std::abs(after[d] - before[d]), 1e-13 * scale) << "direction " << d;
  std::printf("momentum change %.2e, %.2e of sum |m v| %.3e; the grains' %.3e\n", after[0] - before[0],
              after[1] - before[1], scale, grain_momentum);
}

// The acceleration of a point of a turning, accelerating grain, which the
// wall pressure takes: A + alpha x r + omega x (omega x r).
TEST(RigidGrains, WallAccelerationOfAPointOnATurningGrain) {
  WallAcceleration<2, Kokkos::HostSpace> two;
  two.acceleration = decltype(two.acceleration)("A", 1, 2);
  two.spin = decltype(two.spin)("omega", 1, 1);
  two.spin_rate = decltype(two.spin_rate)("alpha", 1, 1);
  two.acceleration(0, 0) = 0.5, two.acceleration(0, 1) = -1.0;
  two.spin(0, 0) = 2.0, two.spin_rate(0, 0) = 3.0;
  Vec<2> r;
  r[0] = 1.0, r[1] = 0.0;
  const Vec<2> a = two.of(0, r);
  EXPECT_DOUBLE_EQ(a[0], 0.5 - 4.0);      // centripetal -omega^2 r
  EXPECT_DOUBLE_EQ(a[1], -1.0 + 3.0);     // alpha r along the turn
  WallAcceleration<3, Kokkos::HostSpace> three;
  three.acceleration = decltype(three.acceleration)("A", 1, 3);
  three.spin = decltype(three.spin)("omega", 1, 3);
  three.spin_rate = decltype(three.spin_rate)("alpha", 1, 3);
  three.spin(0, 2) = 2.0;  // about z
  Vec<3> q;
  q[0] = 0.0, q[1] = 1.5, q[2] = 7.0;  // the part along the axis feels nothing
  const Vec<3> b = three.of(0, q);
  EXPECT_DOUBLE_EQ(b[0], 0.0);
  EXPECT_DOUBLE_EQ(b[1], -4.0 * 1.5);
  EXPECT_DOUBLE_EQ(b[2], 0.0);
  EXPECT_FALSE((WallAcceleration<3, Kokkos::HostSpace>{}.active()));
}

// A grain's boundary particles keep their places on it as it moves and
// turns: each lies at its wall_vector from the grain's centre, at the
// distance it started at.
TEST(RigidGrains, StayRigid) {
  SceneConfig scene = free_grains(30);
  scene.body_force = {0.02, 0.01, 0};  // drives the fluid past the grains: they move and turn
  Simulation<2, Space> sim(scene);
  testing::randomise_velocities(sim.particles(), 0.01, 5);
  sim.compute_rates();
  auto distances = [&]() {
    const auto& P = sim.particles();
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
    auto offset = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.wall_vector);
    auto grain = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.grain);
    auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.id);
    std::map<long long, double> radius;  // |x - c| by particle id
    double worst = 0;                    // |x - offset - c|, nearest image
    for (int i = 0; i < P.owned; ++i) {
      const int g = grain(i);
      if (g < 0) continue;
      const auto& c = sim.rigid_grains().bodies()[g].centre;
      double mismatch = 0;
      for (int d = 0; d < 2; ++d) {
        double r = x(i, d) - offset(i, d) - c[d];
        r -= std::round(r);  // unit cell
        mismatch += r * r;
      }
      worst = std::max(worst, std::sqrt(mismatch));
      radius[id(i)] = std::hypot(offset(i, 0), offset(i, 1));
    }
    EXPECT_LT(worst, 1e-12);
    return radius;
  };
  const auto before = distances();
  for (int s = 0; s < 300; ++s) sim.step();
  const auto after = distances();
  ASSERT_EQ(before.size(), after.size());
  for (const auto& [id, r] : before) EXPECT_NEAR(after.at(id), r, 1e-13) << "particle " << id;
  const auto& b = sim.rigid_grains().bodies();
  EXPECT_GT(std::abs(b[0].velocity[0]), 0.0);
  EXPECT_GT(std::abs(b[0].turned[0]), 1e-6) << "the grain turned";
}

// Grains/Held: in a driven flow the held grain and its boundary particles
// stay where they are while the free grain is carried along.
TEST(RigidGrains, HeldGrainsStayWhileTheOthersMove) {
  SceneConfig scene = free_grains(30);
  scene.held_grains = {0};
  scene.body_force = {0.02, 0.01, 0};
  Simulation<2, Space> sim(scene);
  auto held_positions = [&]() {
    const auto& P = sim.particles();
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
    auto grain = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.grain);
    auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.id);
    std::map<long long, std::array<double, 2>> at;
    for (int i = 0; i < P.owned; ++i)
      if (grain(i) == 0) at[id(i)] = {x(i, 0), x(i, 1)};
    return at;
  };
  const auto before = held_positions();
  for (int s = 0; s < 300; ++s) sim.step();
  const auto after = held_positions();
  ASSERT_EQ(before.size(), after.size());
  ASSERT_GT(before.size(), 0u);
  for (const auto& [id, x] : before) {
    // a wrap by the cell side is the same place
    EXPECT_NEAR(std::remainder(after.at(id)[0] - x[0], 1.0), 0.0, 1e-15) << "particle " << id;
    EXPECT_NEAR(std::remainder(after.at(id)[1] - x[1], 1.0), 0.0, 1e-15) << "particle " << id;
  }
  const auto& b = sim.rigid_grains().bodies();
  EXPECT_EQ(b[0].velocity[0], 0.0);
  EXPECT_EQ(b[0].spin[0], 0.0);
  EXPECT_GT(std::abs(b[1].velocity[0]), 1e-6) << "the free grain is carried";
  EXPECT_NE(b[0].fluid_force[0], 0.0) << "the flow pushes on the held grain";
}

// A square array of discs settling under gravity. In the grains' frame the
// fluid flows through the array held still, driven by the force per unit
// mass the fluid feels, f = g (1 - rho_mix / rho0) (the support of the
// periodic cell): so the settling speed is U = -q / (phi (1 + m_s / M_f)),
// q the superficial velocity through the held array under f (Galilean
// invariance, and the cell's momentum staying zero).
TEST(RigidGrains, SettleAtTheSpeedTheHeldArraysDragGives) {
  SceneConfig settling = testing::periodic_box(2, 25);
  settling.grains = grains_from_list({0.5, 0.5, 0.25231325220201599}, 2);
  settling.particle_motion = ParticleMotion::Lagrangian;
  settling.kinematic_viscosity = 0.01;
  settling.grain_motion = GrainMotion::Free;
  settling.grain_density = 2.0;
  settling.gravity = {0.0, -2e-3, 0.0};
  settling.sound_speed = 0.3;  // the same fluid in both runs
  const double end_time = 40.0;
  Simulation<2, Space> falling(settling);
  const auto& bodies = falling.rigid_grains().bodies();
  // rho0 = 1 and a unit cell: the fluid's mass is its fraction of the cell.
  const double dx = settling.particle_spacing;
  const double fluid_mass = static_cast<double>(falling.fluid_particles()) * dx * dx;
  double held_force[2];
  for (int d = 0; d < 2; ++d) held_force[d] = falling.rigid_grains().fluid_body_force()[d];
  while (falling.time() < end_time) falling.step();

  SceneConfig held = settling;
  held.grain_motion = GrainMotion::Fixed;
  held.gravity = {0, 0, 0};
  held.body_force = {held_force[0], held_force[1], 0};
  Simulation<2, Space> still(held);
  while (still.time() < end_time) still.step();
  const double q = still.superficial_velocity()[1];
  const double fluid_fraction = fluid_mass;  // of the unit cell
  const double predicted = -q / (fluid_fraction * (1 + bodies[0].mass / fluid_mass));
  const double settling_speed = bodies[0].velocity[1];
  std::printf("settling at %.6e m/s, the held array's drag gives %.6e (ratio %.5f)\n", settling_speed, predicted,
              settling_speed / predicted);
  ASSERT_LT(settling_speed, 0.0);
  EXPECT_NEAR(settling_speed / predicted, 1.0, 0.02) << settling_speed << " against " << predicted;
  EXPECT_NEAR(bodies[0].velocity[0], 0.0, 1e-10 * std::abs(settling_speed));
}

}  // namespace
}  // namespace poresph
