#pragma once
// Grains that move (Grains/Motion = free or rotating): each grain is a rigid
// body, a disc in 2D (per metre of depth) or a sphere in 3D, of the solid's
// density. The fluid's force and torque on it are the sums over its boundary
// particles of the reactions to what the fluid gains from them in the pair
// loop (PairLoopOptions::surface_reactions), so that fluid and grains
// exchange momentum exactly. Every process holds every grain's state and
// advances it alike, from loads summed over the processes; each process
// then places its own boundary particles: x = c + R b, v = U + omega x R b
// for a particle at b from the centre, R the grain's turn.
//
// The grains step with the fluid's predictor-corrector (physics/
// PredictorCorrector.hpp): to the mid-point with the old accelerations,
// then the whole step from the start with the mid-point's, the centre by
// the trapezoidal rule. Gravity acts on grains and fluid; in a periodic
// direction a uniform pressure gradient on both by volume holds the cell's
// contents up as a whole (it has nothing else to rest on), so the grains
// settle against the fluid and the total momentum stays what it was.
// Free grains also touch one another and the channel's walls through a
// contact law (physics/ContactLaw.hpp), evaluated where the fluid's loads
// are, at the state of the step's start and of its mid-point.
//
// A turning grain's torque takes one term beyond the pair sums
// (turning_stress_torque): the viscous pair term is Morris's, the
// divergence of mu grad v, where the fluid's stress is
// mu (grad v + grad v^T). Where div v = 0 the two give the fluid the same
// force, and on a wall at rest (v = 0 on it) the same traction; on a solid
// turning at omega the first's traction exceeds the second's by
// mu W n = mu omega x n (W the turn's antisymmetric velocity gradient),
// whose moment over the surface is mu \oint x x (omega x n) dS = 2 mu V omega
// by the divergence theorem, for any shape (V the volume, the area in 2D).
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "core/Math.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"
#include "physics/ContactLaw.hpp"
#include "physics/WallPressure.hpp"
#include "parallel/Communicator.hpp"
#include "scene/SceneConfig.hpp"

namespace poresph {

// The rotation by angle (2D) or rotation vector (3D, Rodrigues) theta, as a
// row-major Dim x Dim matrix.
template <int Dim>
std::array<double, Dim * Dim> rotation_by(const double* theta) {
  std::array<double, Dim * Dim> R{};
  if constexpr (Dim == 2) {
    const double c = std::cos(theta[0]), s = std::sin(theta[0]);
    R = {c, -s, s, c};
  } else {
    const double angle = std::sqrt(theta[0] * theta[0] + theta[1] * theta[1] + theta[2] * theta[2]);
    for (int d = 0; d < 3; ++d) R[d * 3 + d] = 1.0;
    if (angle == 0) return R;
    const double k[3] = {theta[0] / angle, theta[1] / angle, theta[2] / angle};
    const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
    R = {c + t * k[0] * k[0],        t * k[0] * k[1] - s * k[2], t * k[0] * k[2] + s * k[1],
         t * k[1] * k[0] + s * k[2], c + t * k[1] * k[1],        t * k[1] * k[2] - s * k[0],
         t * k[2] * k[0] - s * k[1], t * k[2] * k[1] + s * k[0], c + t * k[2] * k[2]};
  }
  return R;
}

// The torque about a grain's centre of the force F on its boundary
// particle at `offset` from the centre, the force taken where it crosses
// the grain's surface: at radius R on the particle's radial line. The
// fluid's momentum reaches the grain through its surface; the boundary
// particle that takes it lies up to a kernel's reach inside, and a moment
// about its own place would be short by its depth (10 % of a disc's
// torque at R = 6 spacings, 5 % at 12).
template <int Dim>
KOKKOS_INLINE_FUNCTION void grain_moment(const double* offset, double radius, const double* F, double* torque) {
  double length2 = 0;
  for (int d = 0; d < Dim; ++d) length2 += offset[d] * offset[d];
  const double scale = length2 > 0 ? radius / math::sqrt(length2) : 0.0;
  double arm[Dim];
  for (int d = 0; d < Dim; ++d) arm[d] = scale * offset[d];
  moment_of<Dim>(arm, F, torque);
}

// What the fluid's torque on a solid of volume `volume` (area in 2D)
// turning at `spin` takes beyond the pair sums' moment: -2 mu V omega, for
// the fluid's dynamic viscosity mu (see above).
template <int Dim>
std::array<double, spin_components<Dim>()> turning_stress_torque(double viscosity, double volume,
                                                                  const std::array<double, spin_components<Dim>()>& spin) {
  std::array<double, spin_components<Dim>()> torque{};
  for (int k = 0; k < spin_components<Dim>(); ++k) torque[k] = -2.0 * viscosity * volume * spin[k];
  return torque;
}

template <int Dim, class ExecSpace>
class RigidGrains {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using View = Kokkos::View<double**, Kokkos::LayoutRight, MemorySpace>;
  static constexpr int kSpin = spin_components<Dim>();
  using Vector = std::array<double, Dim>;
  using Spin = std::array<double, kSpin>;

  // One grain's state.
  struct Body {
    Vector centre{}, velocity{}, acceleration{};
    Spin spin{}, spin_rate{};  // angular velocity and acceleration
    Spin turned{};             // the angle turned since the start (2D; in 3D the steps' rotation vectors, summed)
    Vector fluid_force{};      // the fluid's force and torque at the last loads
    Spin fluid_torque{};
    Vector contact_force{};    // the contacts' force and torque at the last loads, and their count
    Spin contact_torque{};
    int contacts = 0;
    double mass = 0, inertia = 0, volume = 0, radius = 0;
    bool prescribed = false;  // Grains/Held or Prescribed: moves as set, not by its loads
  };

  RigidGrains() = default;

  // The scene's grains at Grains/Initial Velocity; fluid_mass over all
  // processes. Sets the fluid's share of gravity and of the support
  // (fluid_body_force()). Free grains touch with Young's modulus
  // contact_modulus (DerivedParameters).
  RigidGrains(const SceneConfig& scene, double fluid_mass, double contact_modulus)
      : motion_(scene.grain_motion), fluid_mass_(fluid_mass), viscosity_(scene.density * scene.kinematic_viscosity) {
    frame_.dimension = scene.dimension;
    frame_.cell_size = scene.cell_size;
    frame_.periodic = scene.periodic;
    frame_.walls = scene.walls;
    if (motion_ == GrainMotion::Fixed) return;
    if (motion_ == GrainMotion::Free && contact_modulus > 0)
      contact_ = ContactLaw<Dim>(contact_modulus, scene.grain_contact, scene.particle_spacing);
    double grain_mass = 0, grain_volume = 0;
    for (const Grain& g : scene.grains) {
      Body b;
      const int index = static_cast<int>(bodies_.size());
      const bool held = scene.held(index);
      b.prescribed = held || std::find(scene.prescribed_grains.begin(), scene.prescribed_grains.end(), index) !=
                                 scene.prescribed_grains.end();
      for (int d = 0; d < Dim; ++d) b.centre[d] = g.centre[d];
      // Grains/Initial Velocity and Spin: one set for every grain, or one a grain.
      auto start = [&](const std::vector<double>& values, int per_grain, double* out) {
        const size_t first = SceneConfig::first_start_value(values, index, per_grain);
        if (!values.empty() && !held)
          for (int k = 0; k < per_grain; ++k) out[k] = values[first + k];
      };
      start(scene.grain_velocity, Dim, b.velocity.data());
      start(scene.grain_spin, kSpin, b.spin.data());
      b.radius = g.radius;
      b.volume = ball_volume(g.radius, Dim);
      b.mass = scene.density_of(g) * b.volume;
      b.inertia = (Dim == 2 ? 0.5 : 0.4) * b.mass * g.radius * g.radius;
      grain_mass += b.mass, grain_volume += b.volume;
      bodies_.push_back(b);
    }
    // The support: a uniform force per unit volume s on fluid (s / rho0 per
    // unit mass, the fluid's volume its mass over rho0) and grains, along
    // each periodic direction, such that the external forces add to zero.
    // Where held or prescribed grains hold the cell, the support is the
    // hydrostatic pressure gradient, s = -rho0 g: fluid at rest stays at
    // rest, and a grain feels its weight less its buoyancy.
    const double volume = fluid_mass / scene.density + grain_volume;
    const bool anchored = !scene.held_grains.empty() || !scene.prescribed_grains.empty();
    for (int d = 0; d < Dim; ++d) {
      const double support = !frame_.periodic[d] ? 0.0
                             : anchored          ? -scene.density * scene.gravity[d]
                                                 : -(fluid_mass + grain_mass) * scene.gravity[d] / volume;
      fluid_body_force_[d] = scene.body_force[d] + scene.gravity[d] + support / scene.density;
      // A grain's: gravity on its mass, the support and the driving pressure
      // gradient rho0 F (Fluid/Body Force) on its volume.
      gravity_[d] = scene.gravity[d];
      volume_force_[d] = support + scene.density * scene.body_force[d];
    }
    const int n = static_cast<int>(bodies_.size());
    centre_start_ = View("RigidGrains::centre_start", n, Dim);
    centre_ = View("RigidGrains::centre", n, Dim);
    velocity_ = View("RigidGrains::velocity", n, Dim);
    spin_ = View("RigidGrains::spin", n, kSpin);
    acceleration_ = View("RigidGrains::acceleration", n, Dim);
    spin_rate_ = View("RigidGrains::spin_rate", n, kSpin);
    turn_ = View("RigidGrains::turn", n, Dim * Dim);
    begin_ = bodies_;
    upload({});
  }

  bool moving() const { return motion_ != GrainMotion::Fixed && !bodies_.empty(); }
  double fluid_mass() const { return fluid_mass_; }
  // The grains' angular velocities on the device, a row a grain (kept up to date by the steps).
  const View& spin_view() const { return spin_; }
  // Grain g's torque beyond its pair sums' moment, at its present spin.
  Spin torque_beyond_pairs(int g) const {
    return turning_stress_torque<Dim>(viscosity_, bodies_[g].volume, bodies_[g].spin);
  }

  // The grains' state as numbers, for a checkpoint: what a run needs to go
  // on bit for bit (restore()).
  std::vector<double> state() const {
    std::vector<double> values;
    for (const Body& b : bodies_) for_each_number(b, [&](double v) { values.push_back(v); });
    return values;
  }
  // The state a checkpoint saved; throws if it holds another number of grains.
  void restore(const std::vector<double>& values) {
    size_t k = 0;
    for (Body& b : bodies_) for_each_number(b, [&](double& v) { v = k < values.size() ? values[k] : 0.0; ++k; });
    if (k != values.size())
      throw std::invalid_argument("the checkpoint holds the state of another set of moving grains (" +
                                  std::to_string(values.size()) + " numbers for " + std::to_string(bodies_.size()) +
                                  " grains)");
    begin_ = bodies_;
    upload({});
  }
  const std::vector<Body>& bodies() const { return bodies_; }
  // What the fluid feels per unit mass: the body force, gravity and the support.
  const Vector& fluid_body_force() const { return fluid_body_force_; }

  // To the step's mid-point with the accelerations of the last loads.
  void predict(double dt) {
    begin_ = bodies_;
    for (size_t g = 0; g < bodies_.size(); ++g) {
      Body& b = bodies_[g];
      const Body& s = begin_[g];
      for (int d = 0; d < Dim; ++d) {
        if (motion_ == GrainMotion::Free) b.centre[d] = s.centre[d] + 0.5 * dt * s.velocity[d];
        b.velocity[d] = s.velocity[d] + 0.5 * dt * s.acceleration[d];
      }
      for (int c = 0; c < kSpin; ++c) b.spin[c] = s.spin[c] + 0.5 * dt * s.spin_rate[c];
    }
    upload(half_turns(dt, false));
  }
  // The whole step from its start with the mid-point's accelerations.
  void correct(double dt) {
    for (size_t g = 0; g < bodies_.size(); ++g) {
      Body& b = bodies_[g];
      const Body& s = begin_[g];
      for (int d = 0; d < Dim; ++d) {
        b.velocity[d] = s.velocity[d] + dt * b.acceleration[d];
        if (motion_ == GrainMotion::Free) b.centre[d] = s.centre[d] + 0.5 * dt * (s.velocity[d] + b.velocity[d]);
      }
      for (int c = 0; c < kSpin; ++c) {
        b.spin[c] = s.spin[c] + dt * b.spin_rate[c];
        b.turned[c] = s.turned[c] + 0.5 * dt * (s.spin[c] + b.spin[c]);
      }
    }
    upload(half_turns(dt, true));
  }

  // Puts every owned boundary particle of a grain where its grain is now,
  // turned with it, at its velocity; x_start holds the positions at the
  // start of the step (the grains' begin state). The particles' own
  // predictor and corrector have moved them by their velocity: replaced here.
  void place(const ExecSpace& space, const Particles<Dim, MemorySpace>& P) const {
    const auto Q = P;
    const auto c0 = centre_start_, c = centre_, U = velocity_, w = spin_, R = turn_;
    Kokkos::Array<double, Dim> side;
    Kokkos::Array<bool, Dim> wrap;
    for (int d = 0; d < Dim; ++d) side[d] = frame_.cell_size[d], wrap[d] = frame_.periodic[d];
    static const std::string label = "poresph::RigidGrains::place";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned), KOKKOS_LAMBDA(int i) {
          const int g = Q.grain(i);
          if (g < 0) return;
          double from_start[Dim], turned[Dim], moved[Dim];
          for (int d = 0; d < Dim; ++d) {  // its offset from the centre at the start, nearest image
            double r = Q.x_start(i, d) - c0(g, d);
            if (wrap[d]) r -= side[d] * math::floor(r / side[d] + 0.5);
            from_start[d] = r;
          }
          for (int d = 0; d < Dim; ++d) {
            turned[d] = 0;
            for (int e = 0; e < Dim; ++e) turned[d] += R(g, d * Dim + e) * from_start[e];
          }
          point_velocity(U, w, g, turned, moved);
          for (int d = 0; d < Dim; ++d) {
            Q.x(i, d) = Q.x_start(i, d) + (c(g, d) - c0(g, d)) + (turned[d] - from_start[d]);
            Q.v(i, d) = moved[d];
            Q.wall_vector(i, d) = turned[d];
          }
        });
  }

  // At the start: every owned boundary particle of a grain at its grain's
  // velocity (Grains/Initial Velocity), where place() sets it in the steps.
  void set_particle_velocities(const ExecSpace& space, const Particles<Dim, MemorySpace>& P) const {
    const auto Q = P;
    const auto U = velocity_, w = spin_;
    static const std::string label = "poresph::RigidGrains::set_particle_velocities";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned), KOKKOS_LAMBDA(int i) {
          const int g = Q.grain(i);
          if (g < 0) return;
          double r[Dim], v[Dim];
          for (int d = 0; d < Dim; ++d) r[d] = Q.wall_vector(i, d);
          point_velocity(U, w, g, r, v);
          for (int d = 0; d < Dim; ++d) Q.v(i, d) = v[d];
        });
  }

  // The loads on the grains from their owned boundary particles' dv/dt (the
  // reactions of the pair loop just run), summed over the processes, and
  // the grains' accelerations from them.
  void take_loads(const Particles<Dim, MemorySpace>& P, const Communicator& comm) {
    const int n = static_cast<int>(bodies_.size());
    std::vector<double> sums(n * (Dim + kSpin), 0.0);
    const auto grain = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.grain);
    const auto dvdt = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.dvdt);
    const auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.m);
    const auto offset = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.wall_vector);
    for (int i = 0; i < P.owned; ++i) {
      const int g = grain(i);
      if (g < 0) continue;
      double F[Dim], r[Dim], T[kSpin];
      for (int d = 0; d < Dim; ++d) F[d] = m(i) * dvdt(i, d), r[d] = offset(i, d);
      grain_moment<Dim>(r, bodies_[g].radius, F, T);
      double* s = sums.data() + g * (Dim + kSpin);
      for (int d = 0; d < Dim; ++d) s[d] += F[d];
      for (int k = 0; k < kSpin; ++k) s[Dim + k] += T[k];
    }
    comm.sum(sums.data(), static_cast<int>(sums.size()));
    for (int g = 0; g < n; ++g) {
      Body& b = bodies_[g];
      const double* s = sums.data() + g * (Dim + kSpin);
      for (int d = 0; d < Dim; ++d) b.fluid_force[d] = s[d];
      const Spin beyond_pairs = torque_beyond_pairs(g);
      for (int k = 0; k < kSpin; ++k) b.fluid_torque[k] = s[Dim + k] + beyond_pairs[k];
    }
    accelerate();
  }

  // The grains' accelerations from the fluid's loads (Body::fluid_force,
  // fluid_torque), the contacts at the present state, and the external forces.
  void accelerate() {
    std::vector<ContactBody<Dim>> touching(bodies_.size());
    for (size_t g = 0; g < bodies_.size(); ++g) {
      const Body& b = bodies_[g];
      touching[g] = {b.centre, b.velocity, b.spin, b.mass, b.radius, b.prescribed};
    }
    const ContactLoads<Dim> contact = contact_loads<Dim>(touching, contact_, frame_);
    for (size_t g = 0; g < bodies_.size(); ++g) {
      Body& b = bodies_[g];
      b.contacts = contact.contacts[g];
      for (int d = 0; d < Dim; ++d) {
        b.contact_force[d] = contact.force[g][d];
        const double external = b.mass * gravity_[d] + b.volume * volume_force_[d];
        const double total = b.fluid_force[d] + b.contact_force[d] + external;
        b.acceleration[d] = motion_ == GrainMotion::Free && !b.prescribed ? total / b.mass : 0.0;
      }
      for (int k = 0; k < kSpin; ++k) {
        b.contact_torque[k] = contact.torque[g][k];
        b.spin_rate[k] = b.prescribed ? 0.0 : (b.fluid_torque[k] + b.contact_torque[k]) / b.inertia;
      }
    }
  }
  // What the wall pressure takes of the grains' motion (empty when they hold still).
  WallAcceleration<Dim, MemorySpace> wall_acceleration() const {
    if (!moving()) return {};
    return {acceleration_, spin_, spin_rate_};
  }

 private:
  // f(number) for every number of a body's state that changes in a run.
  template <class B, class F>
  static void for_each_number(B& b, F&& f) {
    for (auto* part : {&b.centre, &b.velocity, &b.acceleration, &b.fluid_force, &b.contact_force})
      for (auto& v : *part) f(v);
    for (auto* part : {&b.spin, &b.spin_rate, &b.turned, &b.fluid_torque, &b.contact_torque})
      for (auto& v : *part) f(v);
    if constexpr (std::is_const_v<B>) {
      f(static_cast<double>(b.contacts));
    } else {
      double contacts = b.contacts;
      f(contacts);
      b.contacts = static_cast<int>(contacts);
    }
  }

  // The velocity U + omega x r of the point at r from grain g's centre.
  KOKKOS_INLINE_FUNCTION static void point_velocity(const View& U, const View& w, int g, const double* r, double* v) {
    double omega[kSpin], turning[Dim];
    for (int k = 0; k < kSpin; ++k) omega[k] = w(g, k);
    spin_cross<Dim>(omega, r, turning);
    for (int d = 0; d < Dim; ++d) v[d] = U(g, d) + turning[d];
  }

  // Each grain's rotation over half the step (predictor: at its start
  // spin; corrector: over the whole step at the mean of both spins).
  std::vector<std::array<double, Dim * Dim>> half_turns(double dt, bool whole) const {
    std::vector<std::array<double, Dim * Dim>> turns;
    for (size_t g = 0; g < bodies_.size(); ++g) {
      double theta[kSpin];
      for (int k = 0; k < kSpin; ++k)
        theta[k] = whole ? 0.5 * dt * (begin_[g].spin[k] + bodies_[g].spin[k]) : 0.5 * dt * begin_[g].spin[k];
      turns.push_back(rotation_by<Dim>(theta));
    }
    return turns;
  }
  // The accelerations of the last loads, for the wall pressure.
  void upload_accelerations() {
    auto A = Kokkos::create_mirror_view(acceleration_);
    auto alpha = Kokkos::create_mirror_view(spin_rate_);
    for (size_t g = 0; g < bodies_.size(); ++g) {
      for (int d = 0; d < Dim; ++d) A(g, d) = bodies_[g].acceleration[d];
      for (int k = 0; k < kSpin; ++k) alpha(g, k) = bodies_[g].spin_rate[k];
    }
    Kokkos::deep_copy(acceleration_, A);
    Kokkos::deep_copy(spin_rate_, alpha);
  }
  // The state the kernels read.
  void upload(const std::vector<std::array<double, Dim * Dim>>& turns) {
    auto c0 = Kokkos::create_mirror_view(centre_start_);
    auto c = Kokkos::create_mirror_view(centre_);
    auto U = Kokkos::create_mirror_view(velocity_);
    auto w = Kokkos::create_mirror_view(spin_);
    auto R = Kokkos::create_mirror_view(turn_);
    upload_accelerations();
    for (size_t g = 0; g < bodies_.size(); ++g) {
      for (int d = 0; d < Dim; ++d) c0(g, d) = begin_[g].centre[d], c(g, d) = bodies_[g].centre[d];
      for (int d = 0; d < Dim; ++d) U(g, d) = bodies_[g].velocity[d];
      for (int k = 0; k < kSpin; ++k) w(g, k) = bodies_[g].spin[k];
      for (int e = 0; e < Dim * Dim; ++e) R(g, e) = turns.empty() ? (e % (Dim + 1) == 0 ? 1.0 : 0.0) : turns[g][e];
    }
    Kokkos::deep_copy(centre_start_, c0);
    Kokkos::deep_copy(centre_, c);
    Kokkos::deep_copy(velocity_, U);
    Kokkos::deep_copy(spin_, w);
    Kokkos::deep_copy(turn_, R);
  }

  GrainMotion motion_ = GrainMotion::Fixed;
  SceneConfig frame_;        // the cell, its periodic directions and walls (no grains)
  ContactLaw<Dim> contact_;  // inactive unless the grains are free
  double fluid_mass_ = 0;     // over all processes, at the start
  double viscosity_ = 0;      // the fluid's dynamic viscosity, for turning_stress_torque
  std::vector<Body> bodies_, begin_;
  Vector fluid_body_force_{}, gravity_{}, volume_force_{};
  View centre_start_, centre_, velocity_, spin_, turn_, acceleration_, spin_rate_;
};

}  // namespace poresph
