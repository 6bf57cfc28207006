// Contact between moving grains (physics/ContactLaw.hpp): the law's
// normalised collision, the restitution it is set to at every speed of
// impact with the fluid removed (the grains alone, stepped as a run steps
// them), momentum and angular momentum kept to round-off, a grain bouncing
// off a channel wall, and two grains colliding through the fluid.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "Scenes.hpp"
#include "app/Simulation.hpp"
#include "geometry/Grains.hpp"
#include "physics/ContactLaw.hpp"
#include "physics/RigidGrains.hpp"

namespace poresph {
namespace {

using Space = Kokkos::Serial;

// Undamped, the normalised collision is half a period of the unit
// oscillator (p = 1) or Hertz's (p = 3/2: t = 2.868 (m*^2 / (R* E*^2 v))^(1/5)
// for k = 4/3 E* sqrt(R*), 3.218 in the normalised time), and gives the
// speed back.
TEST(ContactLaw, UndampedCollisionsTakeTheirKnownTimes) {
  const NormalisedCollision line = normalised_collision(1.0, 0.0);
  EXPECT_NEAR(line.duration, M_PI, 1e-6);
  EXPECT_NEAR(line.restitution, 1.0, 1e-9);
  const NormalisedCollision hertz = normalised_collision(1.5, 0.0);
  EXPECT_NEAR(hertz.duration * std::pow(4.0 / 3.0, -0.4), 2.868, 1e-3);
  EXPECT_NEAR(hertz.restitution, 1.0, 1e-9);
}

TEST(ContactLaw, DampingGivesTheRestitutionAskedFor) {
  for (double p : {1.0, 1.5})
    for (double e : {0.2, 0.5, 0.9, 0.99}) {
      const double zeta = damping_for_restitution(p, e);
      EXPECT_GT(zeta, 0);
      EXPECT_NEAR(normalised_collision(p, zeta).restitution, e, 1e-9) << "p " << p << " e " << e;
    }
  EXPECT_EQ(damping_for_restitution(1.5, 1.0), 0.0);
  EXPECT_THROW(damping_for_restitution(1.5, 0.0), std::invalid_argument);
}

// The contact pushes apart, never pulls, and is zero beyond the cut-off.
TEST(ContactLaw, PushesOnlyWithinTheCutoff) {
  ContactMaterial material;
  material.cutoff_spacings = 1.0;
  const ContactLaw<3> law(1e6, material, 0.01);
  EXPECT_EQ(law.cutoff_gap, 0.01);
  EXPECT_EQ(law.normal_force(0.0, 1.0, 1.0, 0.1, false), 0.0);
  EXPECT_GT(law.normal_force(1e-4, 0.0, 1.0, 0.1, false), 0.0);
  EXPECT_EQ(law.normal_force(1e-4, -1e3, 1.0, 0.1, false), 0.0) << "parting fast: no pull";
  // Against a wall (rigid) the same overlap presses twice as hard as
  // against a grain of the same solid.
  EXPECT_NEAR(law.normal_force(1e-4, 0.0, 1.0, 0.1, true), 2 * law.normal_force(1e-4, 0.0, 1.0, 0.1, false), 1e-12);
}

// Two free grains of the scene, no fluid, stepped as a run steps them:
// predictor, loads at the mid-point, corrector.
template <int Dim>
struct DryGrains {
  SceneConfig scene;
  RigidGrains<Dim, Space> grains;
  double dt;

  DryGrains(std::vector<double> list, std::vector<double> velocity, double restitution, double friction,
            double speed, std::vector<int> held = {}) {
    scene = testing::periodic_box(Dim, 50);
    scene.grains = grains_from_list(list, Dim);
    scene.particle_motion = ParticleMotion::Lagrangian;
    scene.grain_motion = GrainMotion::Free;
    scene.grain_density = 2.5;
    scene.grain_velocity = velocity;
    scene.grain_contact.restitution = restitution;
    scene.grain_contact.friction = friction;
    scene.grain_contact.cutoff_spacings = 0;
    scene.held_grains = held;
    dt = 1e-4;
    // The lightest two collide at `speed` in kStepsPerCollision steps.
    const double modulus = soft_contact_modulus<Dim>(scene, speed, dt);
    grains = RigidGrains<Dim, Space>(scene, 0.0, modulus);
    grains.accelerate();
  }
  void step() {
    grains.predict(dt);
    grains.accelerate();
    grains.correct(dt);
  }
  const auto& bodies() const { return grains.bodies(); }
};

template <int Dim>
void expect_restitution(double e, double speed) {
  std::vector<double> list, velocity;
  if constexpr (Dim == 2) list = {0.3, 0.5, 0.1, 0.7, 0.5, 0.1}, velocity = {speed / 2, 0, -speed / 2, 0};
  else list = {0.3, 0.5, 0.5, 0.1, 0.7, 0.5, 0.5, 0.1}, velocity = {speed / 2, 0, 0, -speed / 2, 0, 0};
  // Collisions at twice and half the speed the law was made for.
  for (double impact : {2 * speed, 0.5 * speed}) {
    for (double& v : velocity) v *= impact / speed;
    DryGrains<Dim> dry(list, velocity, e, 0.3, speed);
    const auto& b = dry.bodies();
    double momentum_before[Dim];
    for (int d = 0; d < Dim; ++d) momentum_before[d] = b[0].mass * b[0].velocity[d] + b[1].mass * b[1].velocity[d];
    const double approach = b[0].velocity[0] - b[1].velocity[0];
    int touched = 0, steps = 0;
    bool apart = false;
    while (!apart && steps < 200000) {
      dry.step();
      ++steps;
      touched += b[0].contacts > 0;
      apart = touched > 0 && b[0].contacts == 0 && b[0].velocity[0] < b[1].velocity[0];
    }
    ASSERT_TRUE(apart);
    const double leave = b[1].velocity[0] - b[0].velocity[0];
    EXPECT_NEAR(leave / approach, e, 0.01 * e) << "restitution, impact at " << impact << " m/s";
    for (int d = 0; d < Dim; ++d) {
      const double after = b[0].mass * b[0].velocity[d] + b[1].mass * b[1].velocity[d];
      EXPECT_LT(std::abs(after - momentum_before[d]), 1e-12 * b[0].mass * std::abs(approach)) << "direction " << d;
    }
    std::printf("%dD e %.2f, impact %.3g m/s: restitution %.5f over %d steps in contact\n", Dim, e, impact,
                leave / approach, touched);
    for (double& v : velocity) v *= speed / impact;
  }
}

TEST(GrainContact, DryCollisionsRestituteAsSetAtAnySpeed) {
  for (double e : {0.5, 0.9}) {
    expect_restitution<2>(e, 0.2);
    expect_restitution<3>(e, 0.2);
  }
}

// A glancing collision with friction: the grains spin up, and linear and
// angular momentum (about the origin, orbital plus spin) are kept.
TEST(GrainContact, FrictionTurnsTheGrainsAndKeepsAngularMomentum) {
  DryGrains<2> dry({0.3, 0.45, 0.1, 0.7, 0.55, 0.1}, {0.1, 0, -0.1, 0}, 0.7, 0.5, 0.2);
  const auto& b = dry.bodies();
  auto angular = [&]() {
    double L = 0;
    for (const auto& g : b) L += g.mass * (g.centre[0] * g.velocity[1] - g.centre[1] * g.velocity[0]) + g.inertia * g.spin[0];
    return L;
  };
  const double before = angular();
  int touched = 0;
  for (int s = 0; s < 40000 && !(touched && b[0].contacts == 0); ++s) {
    dry.step();
    touched += b[0].contacts > 0;
  }
  ASSERT_GT(touched, 0);
  EXPECT_GT(std::abs(b[0].spin[0]), 1e-3) << "friction turned the grain";
  EXPECT_NEAR(b[0].spin[0], b[1].spin[0], 1e-12) << "equal grains, opposite contact points: the same spin";
  // Orbital terms are of order m |x| |v|: the sum holds to round-off of them.
  const double scale = b[0].mass * 0.7 * 0.1;
  EXPECT_LT(std::abs(angular() - before), 1e-13 * scale);
  std::printf("glancing: spin %.4f rad/s, angular momentum change %.2e of %.2e\n", b[0].spin[0],
              angular() - before, scale);
}

// Among many grains, the contacts found through the grain bins are every
// pair closer than the cut-off (nearest periodic images), counted by brute
// force; and their forces add to zero.
TEST(GrainContact, FindsEveryCloseGrainPairAmongMany) {
  SceneConfig frame = testing::periodic_box(3, 20);
  ContactMaterial material;
  const ContactLaw<3> law(1e5, material, 0.02);
  std::vector<ContactBody<3>> bodies;
  unsigned state = 12345;
  auto uniform = [&]() { return (state = state * 1103515245u + 12345u) / 4294967296.0; };
  for (int g = 0; g < 400; ++g) {
    ContactBody<3> b;
    for (int d = 0; d < 3; ++d) b.centre[d] = uniform(), b.velocity[d] = uniform() - 0.5;
    b.radius = 0.04 + 0.03 * uniform();
    b.mass = 1.0;
    bodies.push_back(b);
  }
  const ContactLoads<3> loads = contact_loads<3>(bodies, law, frame);
  std::vector<int> expected(bodies.size(), 0);
  for (size_t a = 0; a < bodies.size(); ++a)
    for (size_t b = a + 1; b < bodies.size(); ++b) {
      double distance = 0;
      for (int d = 0; d < 3; ++d) {
        double r = bodies[b].centre[d] - bodies[a].centre[d];
        r -= std::round(r);
        distance += r * r;
      }
      if (std::sqrt(distance) - bodies[a].radius - bodies[b].radius < law.cutoff_gap) ++expected[a], ++expected[b];
    }
  int pairs = 0;
  double total[3] = {}, magnitude = 0;
  for (size_t g = 0; g < bodies.size(); ++g) {
    EXPECT_EQ(loads.contacts[g], expected[g]) << "grain " << g;
    pairs += expected[g];
    for (int d = 0; d < 3; ++d) total[d] += loads.force[g][d], magnitude += std::abs(loads.force[g][d]);
  }
  EXPECT_GT(pairs, 100);
  for (int d = 0; d < 3; ++d) EXPECT_LT(std::abs(total[d]), 1e-15 * magnitude);
}

// A free grain thrown at a held one (Grains/Held) bounces off it as off a
// wall, at the restitution set, and the held grain does not move.
TEST(GrainContact, BouncesOffAHeldGrain) {
  const double e = 0.7;
  DryGrains<2> dry({0.3, 0.5, 0.1, 0.7, 0.5, 0.1}, {0.2, 0, 0, 0}, e, 0.3, 0.2, {1});
  const auto& b = dry.bodies();
  int touched = 0;
  for (int s = 0; s < 40000 && !(touched && b[0].contacts == 0); ++s) {
    dry.step();
    touched += b[0].contacts > 0;
  }
  ASSERT_GT(touched, 0);
  EXPECT_NEAR(b[0].velocity[0] / 0.2, -e, 0.01 * e);
  EXPECT_EQ(b[1].velocity[0], 0.0);
  EXPECT_EQ(b[1].centre[0], 0.7);
  EXPECT_EQ(b[1].spin[0], 0.0);
}

// A grain thrown at the channel's lower wall bounces off it at the
// restitution set (a rigid wall: the grain's own mass).
TEST(GrainContact, BouncesOffAChannelWall) {
  SceneConfig scene = testing::periodic_box(2, 50);
  scene.walls = WallType::Channel;
  scene.periodic[1] = false;
  scene.grains = grains_from_list({0.5, 0.3, 0.1}, 2);
  scene.particle_motion = ParticleMotion::Lagrangian;
  scene.grain_motion = GrainMotion::Free;
  scene.grain_density = 2.5;
  scene.grain_velocity = {0, -0.2};
  scene.grain_contact.restitution = 0.6;
  scene.grain_contact.cutoff_spacings = 0;
  const double dt = 1e-4;
  const double modulus = soft_contact_modulus<2>(scene, 0.2, dt);
  RigidGrains<2, Space> grains(scene, 0.0, modulus);
  grains.accelerate();
  const auto& b = grains.bodies();
  int touched = 0;
  for (int s = 0; s < 40000 && !(touched && b[0].contacts == 0); ++s) {
    grains.predict(dt), grains.accelerate(), grains.correct(dt);
    touched += b[0].contacts > 0;
  }
  ASSERT_GT(touched, 0);
  EXPECT_NEAR(b[0].velocity[1] / 0.2, 0.6, 0.006);
  EXPECT_GT(b[0].centre[1], 0.1) << "it never went through";
}

// Two grains driven into each other through the fluid: the contact and the
// fluid's loads together keep the momentum of fluid and grains.
TEST(GrainContact, CollisionThroughTheFluidKeepsMomentum) {
  SceneConfig scene = testing::periodic_box(2, 40);
  scene.grains = grains_from_list({0.36, 0.5, 0.12, 0.64, 0.51, 0.12}, 2);
  scene.particle_motion = ParticleMotion::Lagrangian;
  scene.grain_motion = GrainMotion::Free;
  scene.grain_density = 10;  // heavy, and a thin fluid: they coast into each other
  scene.kinematic_viscosity = 0.002;
  scene.velocity_scale = 0.1;
  scene.grain_velocity = {0.02, 0, -0.02, 0};
  scene.grain_contact.cutoff_spacings = 1;
  Simulation<2, Space> sim(scene);
  auto momentum = [&](double& scale) {
    const auto& P = sim.particles();
    auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
    auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.m);
    auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
    std::array<double, 2> total{};
    scale = 0;
    for (int i = 0; i < P.owned; ++i)
      if (kind(i) == kFluid)
        for (int d = 0; d < 2; ++d) total[d] += m(i) * v(i, d);
    for (const auto& b : sim.rigid_grains().bodies())
      for (int d = 0; d < 2; ++d) total[d] += b.mass * b.velocity[d], scale += b.mass * std::abs(b.velocity[d]);
    return total;
  };
  double scale = 0;
  const auto before = momentum(scale);
  int touched = 0;
  const auto& b = sim.rigid_grains().bodies();
  for (int s = 0; s < 3000 && !(touched && b[0].contacts == 0); ++s) {  // through the whole contact
    sim.step();
    touched += b[0].contacts > 0;
  }
  double unused = 0;
  const auto after = momentum(unused);
  EXPECT_GT(touched, 0) << "the grains met";
  EXPECT_EQ(b[0].contacts, 0) << "and parted";
  EXPECT_LT(b[0].velocity[0], 0) << "bounced back";
  for (int d = 0; d < 2; ++d) EXPECT_LT(std::abs(after[d] - before[d]), 1e-12 * scale) << "direction " << d;
  std::printf("through the fluid: %d steps in contact, parted at step %lld at %.4f m/s; momentum change %.2e, %.2e "
              "of %.3e\n", touched, sim.steps(), b[0].velocity[0], after[0] - before[0], after[1] - before[1], scale);
}

}  // namespace
}  // namespace poresph
