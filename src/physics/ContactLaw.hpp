#pragma once
// Contact between moving grains, and between a grain and a channel wall: a
// soft-sphere (DEM) law acting where the gap between two surfaces closes
// below a cut-off. Below about one particle spacing no fluid particle fits
// between two surfaces, so the lubrication force that would keep them apart
// is not resolved; the contact takes over there.
//
// Normal force, for an overlap d = cutoff - gap >= 0 closing at rate d':
//   F = k d^p + zeta sqrt(m* k) d^((p-1)/2) d',   never pulling (F >= 0),
// m* = m_a m_b / (m_a + m_b) (m_a for a wall). In 3D the elastic part is
// Hertz's, p = 3/2, k = 4/3 E* sqrt(R*) with R* = R_a R_b / (R_a + R_b); in
// 2D (discs, per metre of depth) two cylinders pressed along a line, p = 1,
// k = pi/4 E*. E* = E / (2 (1 - nu^2)) for two grains of one solid, E /
// (1 - nu^2) against a rigid wall. The damping term scales with the
// contact's stiffness (Tsuji et al. 1992), so that the coefficient of
// restitution does not depend on the speed of impact; zeta is found at
// set-up from the restitution asked for (damping_for_restitution), by
// integrating the normalised collision.
//
// Tangential force: Coulomb friction mu F, reached through a viscous
// regularisation gamma |v_t| below it, gamma = sqrt(m* dF/dd) (no spring,
// no history between steps). It acts at the contact point and turns both.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/Vec.hpp"
#include "geometry/GrainBins.hpp"
#include "geometry/Grains.hpp"
#include "scene/SceneConfig.hpp"

namespace poresph {

// The time steps a collision at the flow's velocity scale spans, at least.
inline constexpr double kStepsPerCollision = 40;

// The normalised collision X'' = -X^p - zeta X^((p-1)/2) X', X(0) = 0,
// X'(0) = 1, force clamped at zero, to separation: the restitution (the
// speed it leaves with) and the duration. Lengths in (m v^2 / k)^(1/(p+1)),
// times in that over v: every collision of the law is this one, scaled.
struct NormalisedCollision {
  double restitution, duration;
};
inline NormalisedCollision normalised_collision(double p, double zeta) {
  const double damping_power = 0.5 * (p - 1);
  auto acceleration = [&](double x, double v) {
    if (x <= 0) return 0.0;
    return std::min(0.0, -std::pow(x, p) - zeta * std::pow(x, damping_power) * v);
  };
  const double dt = 2e-4;
  double x = 0, v = 1, t = 0;
  // Runge-Kutta 4 until the surfaces part (t < 100: some 30 undamped durations).
  while (t < 100) {
    const double k1x = v, k1v = acceleration(x, v);
    const double k2x = v + 0.5 * dt * k1v, k2v = acceleration(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v);
    const double k3x = v + 0.5 * dt * k2v, k3v = acceleration(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v);
    const double k4x = v + dt * k3v, k4v = acceleration(x + dt * k3x, v + dt * k3v);
    const double x_next = x + dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double v_next = v + dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (x_next <= 0 && t > 0) {  // parted within this step: the time by linear interpolation
      return {-v_next, t + dt * x / (x - x_next)};
    }
    x = x_next, v = v_next, t += dt;
  }
  return {0.0, t};  // the surfaces stay pressed: no rebound
}

// zeta for a restitution e in (0, 1], by bisection on the normalised
// collision (the restitution falls as zeta grows).
inline double damping_for_restitution(double p, double e) {
  if (!(e > 0 && e <= 1)) throw std::invalid_argument("the restitution of a contact lies in (0, 1]");
  if (e == 1) return 0.0;
  double lo = 0, hi = 1;
  while (normalised_collision(p, hi).restitution > e) hi *= 2;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (normalised_collision(p, mid).restitution > e ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The contact law of a scene's grains in Dim dimensions.
template <int Dim>
struct ContactLaw {
  static constexpr double power = Dim == 3 ? 1.5 : 1.0;
  double modulus = 0;   // E* of two grains (a wall's is twice it)
  double zeta = 0;      // damping, from the restitution
  double friction = 0;
  double cutoff_gap = 0;
  double duration = 0;  // of the normalised collision at zeta

  ContactLaw() = default;
  ContactLaw(double young_modulus, const ContactMaterial& material, double spacing)
      : modulus(young_modulus / (2 * (1 - material.poisson_ratio * material.poisson_ratio))),
        zeta(damping_for_restitution(power, material.restitution)),
        friction(material.friction),
        cutoff_gap(material.cutoff_spacings * spacing),
        duration(normalised_collision(power, zeta).duration) {}

  bool active() const { return modulus > 0; }
  // k of the elastic force k d^p, for effective radius R* and modulus E*.
  static double stiffness(double effective_modulus, double effective_radius) {
    return Dim == 3 ? 4.0 / 3.0 * effective_modulus * std::sqrt(effective_radius) : M_PI / 4 * effective_modulus;
  }
  // How long a head-on collision at speed v lasts.
  double collision_time(double mass, double radius, double speed, bool wall) const {
    const double k = stiffness(wall ? 2 * modulus : modulus, radius);
    const double length = std::pow(mass * speed * speed / k, 1.0 / (power + 1));
    return duration * length / speed;
  }
  // The normal force (positive: pushing apart) at overlap d closing at d'.
  double normal_force(double overlap, double closing, double mass, double radius, bool wall) const {
    if (overlap <= 0) return 0;
    const double k = stiffness(wall ? 2 * modulus : modulus, radius);
    const double elastic = k * std::pow(overlap, power);
    const double damping = zeta * std::sqrt(mass * k) * std::pow(overlap, 0.5 * (power - 1)) * closing;
    return std::max(0.0, elastic + damping);
  }
  // gamma of the regularised friction: sqrt(m* dF/dd).
  double tangential_damping(double overlap, double mass, double radius, bool wall) const {
    const double k = stiffness(wall ? 2 * modulus : modulus, radius);
    return std::sqrt(mass * k * power * std::pow(overlap, power - 1));
  }
};

// The scene's shortest collision: two grains alike meeting head on at
// `speed`, for Young's modulus `young`, the shortest over the scene's
// grains (the smallest, or with densities of their own the lightest for
// its size). A grain against a wall, or a lighter against a heavier one,
// takes longer.
template <int Dim>
double shortest_collision(const SceneConfig& scene, double young, double speed) {
  const ContactLaw<Dim> law(young, scene.grain_contact, 0.0);
  double shortest = std::numeric_limits<double>::infinity();
  for (const Grain& g : scene.grains) {
    const double mass = scene.density_of(g) * ball_volume(g.radius, Dim);
    shortest = std::min(shortest, law.collision_time(0.5 * mass, 0.5 * g.radius, speed, false));
  }
  return shortest;
}

// The Young's modulus that makes the scene's shortest collision at `speed`
// last kStepsPerCollision time steps of dt: soft, but resolved.
template <int Dim>
double soft_contact_modulus(const SceneConfig& scene, double speed, double dt) {
  // The duration scales as E^(-1/(p+1)): from the one at E = 1.
  return std::pow(shortest_collision<Dim>(scene, 1.0, speed) / (kStepsPerCollision * dt), ContactLaw<Dim>::power + 1);
}

// One grain as the contact sees it.
template <int Dim>
struct ContactBody {
  std::array<double, Dim> centre{}, velocity{};
  std::array<double, spin_components<Dim>()> spin{};
  double mass = 0, radius = 0;
  bool prescribed = false;  // moves as set (a held grain, at rest): of infinite mass to the contact
};

// The contact forces and torques on each body, and the count of contacts:
// between every two bodies (nearest periodic images) and between a body and
// the channel's walls at y = 0 and y = wall_height (wall_height 0: none).
// Each pair's force is formed once and added to both, so that the contacts
// conserve momentum to round-off.
template <int Dim>
struct ContactLoads {
  static constexpr int kSpin = spin_components<Dim>();
  std::vector<std::array<double, Dim>> force;
  std::vector<std::array<double, kSpin>> torque;
  std::vector<int> contacts;
};

// `frame` gives the cell, its periodic directions and its walls (its
// grains are not read); the pairs near enough to touch are found through
// grain bins (geometry/GrainBins.hpp), so the cost grows with the grains'
// number, not its square.
template <int Dim>
ContactLoads<Dim> contact_loads(const std::vector<ContactBody<Dim>>& bodies, const ContactLaw<Dim>& law,
                                const SceneConfig& frame) {
  const std::array<double, 3>& cell = frame.cell_size;
  const std::array<bool, 3>& periodic = frame.periodic;
  const double wall_height = frame.walls == WallType::Channel ? cell[1] : 0.0;
  constexpr int kSpin = spin_components<Dim>();
  const int n = static_cast<int>(bodies.size());
  ContactLoads<Dim> loads;
  loads.force.assign(n, {});
  loads.torque.assign(n, {});
  loads.contacts.assign(n, 0);
  if (!law.active()) return loads;
  // The pair (a, b) along the unit normal from a to b, at the gap between
  // their surfaces; b < 0: the wall, of infinite mass and radius.
  auto touch = [&](int a, int b, const double* normal, double gap) {
    const ContactBody<Dim>& A = bodies[a];
    const bool wall = b < 0;
    const double overlap = law.cutoff_gap - gap;
    if (overlap <= 0 || (A.prescribed && (wall || bodies[b].prescribed))) return;
    // The reduced mass; a prescribed grain, as a wall, is of infinite mass.
    const double mass = wall || bodies[b].prescribed ? A.mass
                        : A.prescribed              ? bodies[b].mass
                                              : A.mass * bodies[b].mass / (A.mass + bodies[b].mass);
    const double radius = wall ? A.radius : A.radius * bodies[b].radius / (A.radius + bodies[b].radius);
    // Both forces act at one point, midway across the gap, so that the
    // contacts keep the angular momentum too; the velocity there on a
    // relative to b's.
    double arm_a[Dim], arm_b[Dim], turn_a[Dim], turn_b[Dim], relative[Dim];
    for (int d = 0; d < Dim; ++d) {
      arm_a[d] = (A.radius + 0.5 * gap) * normal[d];
      arm_b[d] = wall ? 0 : -(bodies[b].radius + 0.5 * gap) * normal[d];
    }
    spin_cross<Dim>(A.spin.data(), arm_a, turn_a);
    if (wall) std::fill(turn_b, turn_b + Dim, 0.0);
    else spin_cross<Dim>(bodies[b].spin.data(), arm_b, turn_b);
    double closing = 0;
    for (int d = 0; d < Dim; ++d) {
      relative[d] = A.velocity[d] + turn_a[d] - (wall ? 0.0 : bodies[b].velocity[d] + turn_b[d]);
      closing += relative[d] * normal[d];
    }
    const double normal_force = law.normal_force(overlap, closing, mass, radius, wall);
    double tangential[Dim], slip = 0;
    for (int d = 0; d < Dim; ++d) tangential[d] = relative[d] - closing * normal[d], slip += tangential[d] * tangential[d];
    slip = std::sqrt(slip);
    const double friction =
        slip > 0 ? std::min(law.friction * normal_force, law.tangential_damping(overlap, mass, radius, wall) * slip)
                 : 0.0;
    double on_a[Dim], torque_a[kSpin], torque_b[kSpin];
    for (int d = 0; d < Dim; ++d) on_a[d] = -normal_force * normal[d] - (slip > 0 ? friction * tangential[d] / slip : 0);
    moment_of<Dim>(arm_a, on_a, torque_a);
    double on_b[Dim];
    for (int d = 0; d < Dim; ++d) on_b[d] = -on_a[d];
    moment_of<Dim>(arm_b, on_b, torque_b);
    for (int d = 0; d < Dim; ++d) loads.force[a][d] += on_a[d];
    for (int k = 0; k < kSpin; ++k) loads.torque[a][k] += torque_a[k];
    ++loads.contacts[a];
    if (wall) return;
    for (int d = 0; d < Dim; ++d) loads.force[b][d] += on_b[d];
    for (int k = 0; k < kSpin; ++k) loads.torque[b][k] += torque_b[k];
    ++loads.contacts[b];
  };
  std::vector<Grain> placed(n);
  for (int a = 0; a < n; ++a) {
    for (int d = 0; d < Dim; ++d) placed[a].centre[d] = bodies[a].centre[d];
    placed[a].radius = bodies[a].radius;
  }
  for_each_close_pair(placed, frame, law.cutoff_gap, [&](size_t a, size_t b) {
    double between[Dim], distance = 0;
    for (int d = 0; d < Dim; ++d) {
      double r = bodies[b].centre[d] - bodies[a].centre[d];
      if (periodic[d]) r -= cell[d] * std::round(r / cell[d]);
      between[d] = r, distance += r * r;
    }
    distance = std::sqrt(distance);
    const double gap = distance - bodies[a].radius - bodies[b].radius;
    if (gap >= law.cutoff_gap || distance == 0) return;
    for (double& r : between) r /= distance;
    touch(static_cast<int>(a), static_cast<int>(b), between, gap);
  });
  for (int a = 0; a < n; ++a) {
    if (wall_height > 0) {
      double down[Dim] = {}, up[Dim] = {};
      down[1] = -1, up[1] = 1;
      touch(a, -1, down, bodies[a].centre[1] - bodies[a].radius);
      touch(a, -1, up, wall_height - bodies[a].centre[1] - bodies[a].radius);
    }
  }
  return loads;
}

}  // namespace poresph
