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

// Grains of their own densities (the grain file's column): each body's
// mass is its density times its volume, the heavier and the lighter grain
// exchange momentum with the fluid as exactly as grains of one density.
TEST(RigidGrains, GrainsOfTheirOwnDensitiesConserveMomentum) {
  SceneConfig scene = free_grains(30);
  scene.grain_density = 0;
  scene.grains[0].density = 1.5;
  scene.grains[1].density = 6.0;
  Simulation<2, Space> sim(scene);
  const auto& bodies = sim.rigid_grains().bodies();
  for (int g = 0; g < 2; ++g)
    EXPECT_DOUBLE_EQ(bodies[g].mass, scene.grains[g].density * M_PI * scene.grains[g].radius * scene.grains[g].radius);
  testing::randomise_velocities(sim.particles(), 0.02, 11);
  sim.compute_rates();
  double scale = 0;
  const Vec<2> before = total_momentum(sim, scale);
  for (int s = 0; s < 200; ++s) sim.step();
  const Vec<2> after = total_momentum(sim, scale);
  for (int d = 0; d < 2; ++d) EXPECT_LT(std::abs(after[d] - before[d]), 1e-13 * scale) << "direction " << d;
  EXPECT_GT(std::hypot(bodies[0].velocity[0], bodies[0].velocity[1]), 0.0);
}

// Each grain given Grains/Density's value in the file runs as Grains/Density, bit for bit.
TEST(RigidGrains, OwnDensitiesAllAlikeAreGrainsDensity) {
  SceneConfig common = free_grains(20);
  common.gravity = {0.0, -0.5, 0.0};
  SceneConfig own = common;
  own.grain_density = 0;
  for (Grain& g : own.grains) g.density = common.grain_density;
  Simulation<2, Space> a(common), b(own);
  for (int s = 0; s < 100; ++s) a.step(), b.step();
  for (int g = 0; g < 2; ++g)
    for (int d = 0; d < 2; ++d) {
      EXPECT_EQ(a.rigid_grains().bodies()[g].centre[d], b.rigid_grains().bodies()[g].centre[d]);
      EXPECT_EQ(a.rigid_grains().bodies()[g].velocity[d], b.rigid_grains().bodies()[g].velocity[d]);
    }
  EXPECT_LT(a.rigid_grains().bodies()[0].velocity[1], 0.0);  // they fall
}

// Moving fluid cannot leave through a channel's wall: a particle carried
// past the top wall into the wall's layers is put back on the wall at the
// step's end, without its velocity into the wall, and the correction counts.
TEST(RigidGrains, MovingFluidPastAChannelWallIsPutBack) {
  SceneConfig scene = testing::channel(10);
  scene.particle_motion = ParticleMotion::Lagrangian;
  scene.velocity_scale = 1e-4;
  Simulation<2, Space> sim(scene);
  const double H = scene.cell_size[1], dx = scene.particle_spacing;
  auto& P = sim.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.id);
  int top = -1;
  for (int i = 0; i < P.owned; ++i)
    if (kind(i) == kFluid && (top < 0 || x(i, 1) > x(top, 1))) top = i;
  ASSERT_GE(top, 0);
  const long long carried = id(top);
  x(top, 1) = H + 0.3 * dx;  // among the wall's first layer
  v(top, 0) = 1e-5, v(top, 1) = 1e-4;
  Kokkos::deep_copy(P.x, x);
  Kokkos::deep_copy(P.v, v);
  sim.compute_rates();
  sim.step();
  EXPECT_EQ(sim.fluid_inside_grains().particles, 0);
  EXPECT_GE(sim.grain_surface_corrections().particles, 1);
  EXPECT_NEAR(sim.grain_surface_corrections().max_depth, 0.3 * dx, 0.05 * dx);  // where it was, give or take a step's motion
  Kokkos::deep_copy(x, P.x);
  Kokkos::deep_copy(v, P.v);
  Kokkos::deep_copy(id, P.id);
  int found = 0;
  for (int i = 0; i < P.owned; ++i)
    if (id(i) == carried) {
      ++found;
      EXPECT_LT(x(i, 1), H);
      EXPECT_GT(x(i, 1), H - 1e-3 * dx);  // on the wall, not pushed deep into the fluid
      EXPECT_LE(v(i, 1), 0.0);            // nothing left of its velocity into the wall
    }
  EXPECT_EQ(found, 1);
}

// A grain turning with the fluid around it, as one rigid body, feels no
// torque. The pair sums' moment alone is the traction of mu grad v, which
// holds the turning grain by +2 mu V omega (physics/RigidGrains.hpp,
// turning_stress_torque); with its correction the torque is what the
// stress mu (grad v + grad v^T) of a rigid turn gives: none.
TEST(RigidGrains, TurningWithTheFluidAsOneBodyTakesNoTorque) {
  SceneConfig scene = testing::periodic_box(2, 40);
  scene.grains = grains_from_list({0.5, 0.5, 0.2}, 2);
  scene.particle_motion = ParticleMotion::Lagrangian;
  scene.grain_motion = GrainMotion::Rotating;
  scene.grain_density = 2.5;
  scene.velocity_scale = 0.05;
  const double omega = 0.1;
  scene.grain_spin = {omega};
  Simulation<2, Space> sim(scene);
  {  // the fluid turning with the grain, about its centre (far from the cell's edges the grain reaches)
    const auto& P = sim.particles();
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
    auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
    auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
    for (int i = 0; i < P.owned; ++i)
      if (kind(i) == kFluid) v(i, 0) = -omega * (x(i, 1) - 0.5), v(i, 1) = omega * (x(i, 0) - 0.5);
    Kokkos::deep_copy(P.v, v);
  }
  const double torque = sim.surface_loads().grain_torque[0][0];
  const auto& b = sim.rigid_grains().bodies()[0];
  const double mu = scene.density * scene.kinematic_viscosity, scale = 2 * mu * b.volume * omega;
  const double pairs_alone = torque - sim.rigid_grains().torque_beyond_pairs(0)[0];
  std::printf("torque %.3e, the pair sums' moment alone %.3e, 2 mu V omega %.3e\n", torque, pairs_alone, scale);
  EXPECT_NEAR(pairs_alone, scale, 0.1 * scale) << "the pair sums hold the turning grain by 2 mu V omega";
  EXPECT_LT(std::abs(torque), 0.05 * scale);
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

// Under gravity, a cell resting on a held grain is held up by the
// hydrostatic pressure gradient: a free grain of the fluid's density and
// the fluid stay at rest (were the fluid's weight not held, it would flow
// down through the held grain), and a heavier grain sinks.
TEST(RigidGrains, ACellRestingOnHeldGrainsIsHydrostatic) {
  for (const double density : {1.0, 2.5}) {
    SceneConfig scene = free_grains(30);
    scene.held_grains = {0};
    scene.grain_density = density;  // the fluid's is 1
    scene.gravity = {0.0, -0.01, 0.0};
    Simulation<2, Space> sim(scene);
    for (int s = 0; s < 200; ++s) sim.step();
    const auto& P = sim.particles();
    auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
    auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
    double fastest = 0;
    for (int i = 0; i < P.owned; ++i)
      if (kind(i) == kFluid) fastest = std::max(fastest, std::hypot(v(i, 0), v(i, 1)));
    const double sinking = -sim.rigid_grains().bodies()[1].velocity[1];
    const double free_fall = 0.01 * sim.time();  // the speed gravity alone would give by now
    std::printf("grain density %.1f: fastest fluid %.2e, the free grain sinks at %.2e (free fall %.2e)\n", density,
                fastest, sinking, free_fall);
    if (density == 1.0) {
      EXPECT_LT(fastest, 1e-6 * free_fall);
      EXPECT_LT(std::abs(sinking), 1e-6 * free_fall);
    } else {
      EXPECT_GT(sinking, 1e-3 * free_fall);
    }
  }
}

// Grains set moving are moving walls to the sound-speed rule: a grain pulled
// at U and turning at omega moves its surface at up to |U| + |omega| r, and
// the speed of sound follows it as it follows a channel wall's speed.
TEST(RigidGrains, MovingGrainsSetTheVelocityScale) {
  SceneConfig scene = free_grains(30);
  scene.velocity_scale = 0;
  scene.sound_speed = 0;  // the rule's, not the test box's
  scene.prescribed_grains = {0};
  scene.grain_velocity = {0.02, -0.01, 0.0, 0.0};
  scene.grain_spin = {0.5, 0.0};
  const double surface = std::hypot(0.02, -0.01) + 0.5 * 0.15;  // grain 0: r = 0.15
  EXPECT_DOUBLE_EQ(scene.fastest_grain_surface(), surface);
  const DerivedParameters derived = derive_parameters(scene);
  EXPECT_GE(derived.velocity_scale, surface);
  // Started at once, it compresses the fluid ahead by V / c: at most half the checked limit.
  EXPECT_LE(surface / derived.sound_speed, 0.5 * scene.density_variation_limit * (1 + 1e-12));
  // Held grains stay at rest, whatever the start velocity says of all grains.
  scene.prescribed_grains = {};
  scene.held_grains = {0, 1};
  scene.grain_velocity = {0.02, -0.01};
  scene.grain_spin = {0.5};
  EXPECT_EQ(scene.fastest_grain_surface(), 0.0);
  // Fixed grains are no moving walls.
  scene.held_grains = {};
  scene.grain_motion = GrainMotion::Fixed;
  EXPECT_EQ(scene.fastest_grain_surface(), 0.0);
}

// Grains/Prescribed with Initial Velocity and Spin: the prescribed grain
// keeps its velocity and spin whatever the fluid does, its centre moving
// and its particles turning as set; the other is free.
TEST(RigidGrains, PrescribedGrainsMoveAsSet) {
  SceneConfig scene = free_grains(30);
  scene.prescribed_grains = {0};
  scene.grain_velocity = {0.02, -0.01, 0.0, 0.0};
  scene.grain_spin = {0.5, 0.0};
  Simulation<2, Space> sim(scene);
  const auto start = sim.rigid_grains().bodies()[0];
  for (int s = 0; s < 300; ++s) sim.step();
  const auto& b = sim.rigid_grains().bodies();
  const double t = sim.time();
  EXPECT_EQ(b[0].velocity[0], 0.02);
  EXPECT_EQ(b[0].velocity[1], -0.01);
  EXPECT_EQ(b[0].spin[0], 0.5);
  for (int d = 0; d < 2; ++d)  // the centre, wrapped into the unit cell
    EXPECT_NEAR(std::remainder(b[0].centre[d] - start.centre[d] - t * b[0].velocity[d], 1.0), 0.0, 1e-13);
  EXPECT_NEAR(b[0].turned[0], 0.5 * t, 1e-13);
  EXPECT_NE(b[0].fluid_torque[0], 0.0) << "the fluid resists the prescribed turn";
  EXPECT_GT(std::hypot(b[1].velocity[0], b[1].velocity[1]), 1e-6) << "the stirred fluid carries the free grain";
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
