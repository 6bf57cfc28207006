#pragma once
// The pressure of boundary particles extrapolated from the fluid around them
// (Adami, Hu & Adams, J. Comput. Phys. 231, 2012, eq. 27):
//   p_w = (sum_f p_f W_wf + (F - a_w) . sum_f rho_f r_wf W_wf) / sum_f W_wf,
// r_wf = x_w - x_f, over the fluid particles f within the support, F the
// body acceleration, a_w the wall's own acceleration: zero for walls and
// held grains, A + alpha x r + omega x (omega x r) for a boundary particle
// at r from the centre of a moving grain (WallAcceleration). The wall then
// pushes back on the fluid with the pressure the fluid has next to it, plus
// the part of the body force and of its own acceleration across the gap.
//
// Why: evolved by the continuity equation, as in the paper, a boundary
// particle's density integrates sum_f m_f (v_w - v_f) . grad W, which a
// steady flow past a curved surface does not bring to zero; the wall
// pressure then creeps on for as long as the run goes, and k with it
// (docs/method.md, "A steady state that stays"). Extrapolated, the wall has
// no state of its own, so the scheme has a true steady state.
#include <Kokkos_Core.hpp>

#include <string>

#include "core/CellList.hpp"
#include "core/NeighbourList.hpp"
#include "core/Kernel.hpp"
#include "core/Math.hpp"
#include "core/PairGeometry.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

// The wall pressure of one boundary particle from the three sums above;
// `fallback` where no fluid is in reach (such a particle touches no fluid).
KOKKOS_INLINE_FUNCTION double extrapolated_wall_pressure(double sum_w, double sum_pw, double force_dot_sum_rho_r_w,
                                                         double fallback) {
  return sum_w > 0 ? (sum_pw + force_dot_sum_rho_r_w) / sum_w : fallback;
}

// The body force on the fluid next to a wall when it differs by phase
// (Phases/Driven Phase): a particle of phase p takes force[p], so that the
// wall's pressure carries the hydrostatic share of the phase beside it.
// Empty (no phase view): one force for all the fluid.
template <int Dim, class MemorySpace>
struct PhaseBodyForce {
  Kokkos::View<const int*, MemorySpace> phase;
  Vec<Dim> force[2] = {Vec<Dim>::zero(), Vec<Dim>::zero()};
  bool active() const { return phase.extent(0) > 0; }
  KOKKOS_INLINE_FUNCTION const Vec<Dim>& of(int particle) const { return force[phase(particle)]; }
};

// The acceleration of moving grains' boundary particles, from each grain's
// acceleration A, angular acceleration alpha and spin omega (physics/
// RigidGrains.hpp, as of its last loads): a_w = A + alpha x r + omega x
// (omega x r), r the particle's offset from the centre (wall_vector).
// Empty: every wall at rest or moving uniformly.
template <int Dim, class MemorySpace>
struct WallAcceleration {
  static constexpr int kSpin = spin_components<Dim>();
  Kokkos::View<double**, Kokkos::LayoutRight, MemorySpace> acceleration, spin, spin_rate;  // per grain
  bool active() const { return acceleration.extent(0) > 0; }
  KOKKOS_INLINE_FUNCTION Vec<Dim> of(int grain, const Vec<Dim>& r) const {
    double omega[kSpin], alpha[kSpin], offset[Dim], turning[Dim], swinging[Dim], inward[Dim];
    for (int k = 0; k < kSpin; ++k) omega[k] = spin(grain, k), alpha[k] = spin_rate(grain, k);
    for (int d = 0; d < Dim; ++d) offset[d] = r[d];
    spin_cross<Dim>(alpha, offset, turning);
    spin_cross<Dim>(omega, offset, swinging);
    spin_cross<Dim>(omega, swinging, inward);
    Vec<Dim> a;
    for (int d = 0; d < Dim; ++d) a[d] = acceleration(grain, d) + turning[d] + inward[d];
    return a;
  }
};

// For each owned boundary particle, the fluid particles (owned or ghost)
// within a radius: built with the neighbour list, from the same cell list.
template <int Dim, class ExecSpace>
class WallNeighbours {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using IndexView = Kokkos::View<int*, MemorySpace>;

  void build(const ExecSpace& space, const CellList<Dim, ExecSpace>& cells,
             const Particles<Dim, MemorySpace>& P, double radius) {
    const int owned = P.owned;
    if (static_cast<int>(offsets_.extent(0)) < owned + 1)
      offsets_ = IndexView("WallNeighbours::offsets", owned + owned / 4 + 1);
    const auto offsets = offsets_;
    const auto x = P.x;
    const auto kind = P.kind;
    const double radius_sq = radius * radius;
    auto for_each_fluid_neighbour = [=](int i, auto&& f) {
      const Vec<Dim> xi = row<Dim>(x, i);
      cells.for_each_candidate(xi, [&](int j) {
        const Vec<Dim> r = xi - row<Dim>(x, j);
        if (kind(j) == kFluid && dot(r, r) < radius_sq) f(j);
      });
    };
    static const std::string label_count = "poresph::WallNeighbours::count";
    Kokkos::parallel_for(
        label_count, Kokkos::RangePolicy<ExecSpace>(space, 0, owned), KOKKOS_LAMBDA(int i) {
          int n = 0;
          if (kind(i) != kFluid) for_each_fluid_neighbour(i, [&](int) { ++n; });
          offsets(i + 1) = n;
        });
    int total = 0;
    static const std::string label_offsets = "poresph::WallNeighbours::offsets";
    Kokkos::parallel_scan(
        label_offsets, Kokkos::RangePolicy<ExecSpace>(space, 0, owned + 1),
        KOKKOS_LAMBDA(int i, int& running, bool final) {
          running += i == 0 ? 0 : offsets(i);
          if (final) offsets(i) = running;
        },
        total);
    if (static_cast<int>(indices_.extent(0)) < total)
      indices_ = IndexView("WallNeighbours::indices", total + total / 4 + 1);
    entries_ = total;
    geometry_.clear();
    const auto indices = indices_;
    static const std::string label_fill = "poresph::WallNeighbours::fill";
    Kokkos::parallel_for(
        label_fill, Kokkos::RangePolicy<ExecSpace>(space, 0, owned), KOKKOS_LAMBDA(int i) {
          int k = offsets(i);
          if (kind(i) != kFluid) for_each_fluid_neighbour(i, [&](int j) { indices(k++) = j; });
        });
    space.fence();
  }

  KOKKOS_INLINE_FUNCTION int begin(int i) const { return offsets_(i); }
  KOKKOS_INLINE_FUNCTION int end(int i) const { return offsets_(i + 1); }
  KOKKOS_INLINE_FUNCTION int neighbour(int k) const { return indices_(k); }
  int entries() const { return entries_; }

  // Fixed particles: the separation r_wf and the kernel value W_wf of every
  // entry, found once after the build (as NeighbourList's geometry is for the
  // pair loop, from the lattice stencil or else per entry), so that the
  // extrapolation at every stage reads them instead of evaluating a square
  // root and the kernel per pair.
  template <class PositionView>
  bool find_stencil_ids(const ExecSpace& space, const PositionView& x, int owned,
                        const LatticeStencil<Dim, MemorySpace>& stencil) {
    static const std::string label = "poresph::WallNeighbours::find_stencil_ids";
    return geometry_.find_stencil_ids(space, label, offsets_, indices_, x, owned, entries_, stencil);
  }
  void use_stencil(const LatticeStencil<Dim, MemorySpace>& stencil) { geometry_.use_stencil(stencil); }
  template <class PositionView, class Kernel>
  void cache_geometry(const ExecSpace& space, const PositionView& x, int owned, const Kernel& kernel) {
    static const std::string label = "poresph::WallNeighbours::cache_geometry";
    geometry_.cache(space, label, offsets_, indices_, x, owned, entries_,
                    KOKKOS_LAMBDA(double r) { return kernel.value(r); });
  }
  bool has_geometry() const { return geometry_.has_geometry(); }
  bool on_stencil() const { return geometry_.on_stencil(); }
  KOKKOS_INLINE_FUNCTION double separation(int k, int d) const { return geometry_.separation(k, d); }
  KOKKOS_INLINE_FUNCTION double weight(int k) const { return geometry_.of_distance(k); }

 private:
  IndexView offsets_, indices_;
  PairGeometry<Dim, ExecSpace> geometry_;
  int entries_ = 0;
};

// Entry k of the list of a boundary particle at x_w: the separation r_wf
// (into r) and the kernel's value W_wf, read from the cache or evaluated.
template <int Dim, class ExecSpace, class PositionView>
KOKKOS_INLINE_FUNCTION double wall_entry(const WallNeighbours<Dim, ExecSpace>& walls, bool cached, int k,
                                         const Vec<Dim>& x_w, const PositionView& x, const QuinticKernel<Dim>& kernel,
                                         Vec<Dim>& r) {
  if (cached) {
    for (int d = 0; d < Dim; ++d) r[d] = walls.separation(k, d);
    return walls.weight(k);
  }
  r = x_w - row<Dim>(x, walls.neighbour(k));
  return kernel.value(math::sqrt(dot(r, r)));
}

// Sets p, rho = p / c^2 and the pair loop's factors of every owned boundary
// particle from the fluid around it (fluid pressures, owned and ghost, must
// be current). reference_pressure and volume_density as in update_pressure
// (physics/Density.hpp); without fluid in reach, the rest pressure c^2 rho0.
template <int Dim, class ExecSpace>
void extrapolate_wall_pressure(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                               const WallNeighbours<Dim, ExecSpace>& walls, const QuinticKernel<Dim>& kernel,
                               const Vec<Dim>& body_force, double sound_speed_sq, double rest_density,
                               double reference_pressure, double volume_density,
                               const WallAcceleration<Dim, typename ExecSpace::memory_space>& wall_acceleration = {},
                               const PhaseBodyForce<Dim, typename ExecSpace::memory_space>& phase_force = {}) {
  const auto Q = P;
  const bool cached = walls.has_geometry();
  const bool accelerating = wall_acceleration.active();
  const bool by_phase = phase_force.active();
  static const std::string label = "poresph::extrapolate_wall_pressure";
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned), KOKKOS_LAMBDA(int w) {
        if (Q.kind(w) == kFluid) return;
        const Vec<Dim> x_w = row<Dim>(Q.x, w);
        double sum_w = 0, sum_pw = 0;
        Vec<Dim> sum_rho_r_w = Vec<Dim>::zero();
        double sum_phase_force = 0;  // by phase: sum_f rho_f W F_f . r
        for (int k = walls.begin(w); k < walls.end(w); ++k) {
          const int f = walls.neighbour(k);
          Vec<Dim> r;
          const double W = wall_entry(walls, cached, k, x_w, Q.x, kernel, r);
          sum_w += W;
          sum_pw += Q.p(f) * W;
          sum_rho_r_w += (Q.rho(f) * W) * r;
          if (by_phase) sum_phase_force += Q.rho(f) * W * dot(phase_force.of(f), r);
        }
        Vec<Dim> relative_force = by_phase ? Vec<Dim>::zero() : body_force;
        if (accelerating && Q.grain(w) >= 0) relative_force -= wall_acceleration.of(Q.grain(w), row<Dim>(Q.wall_vector, w));
        const double p = extrapolated_wall_pressure(sum_w, sum_pw, dot(relative_force, sum_rho_r_w) + sum_phase_force,
                                                    sound_speed_sq * rest_density);
        const double rho = p / sound_speed_sq;
        Q.p(w) = p;
        Q.rho(w) = rho;
        Q.pressure_term(w) = pressure_term(p - reference_pressure, rho);
        if (!Q.fixed_positions) Q.inverse_density(w) = 1.0 / (volume_density > 0 ? volume_density : rho);
      });
}

// The change of each owned boundary particle's extrapolated pressure for a
// change dp of the fluid's pressures (a value per slot, owned and ghosts):
// extrapolate_wall_pressure differentiated for walls at rest, with the
// fluid's density following its pressure (d rho_f = dp_f / c^2),
//   dp_w = sum_f a_wf dp_f,   a_wf = W_wf (1 + F . r_wf / c^2) / sum_f W_wf
// (F the force on f's phase, given phase_force): linear in dp, with
// weights a_wf that depend on the geometry alone. WallPressureWeights holds
// them, one per entry of the wall list, so that each product (the steady
// solver makes thousands) is a gather and a multiply-add per entry, not a
// division and a dot product.
template <int Dim, class ExecSpace>
class WallPressureWeights {
 public:
  using MemorySpace = typename ExecSpace::memory_space;

  WallPressureWeights() = default;
  WallPressureWeights(const ExecSpace& space, const Particles<Dim, MemorySpace>& P,
                      const WallNeighbours<Dim, ExecSpace>& walls, const QuinticKernel<Dim>& kernel,
                      const Vec<Dim>& body_force, double sound_speed_sq,
                      const PhaseBodyForce<Dim, MemorySpace>& phase_force = {})
      : weights_("poresph::WallPressureWeights", walls.entries()) {
    const auto Q = P;
    const auto a = weights_;
    const bool cached = walls.has_geometry();
    const bool by_phase = phase_force.active();
    static const std::string label = "poresph::WallPressureWeights";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned), KOKKOS_LAMBDA(int w) {
          if (Q.kind(w) == kFluid) return;
          const Vec<Dim> x_w = row<Dim>(Q.x, w);
          double sum_w = 0;
          for (int k = walls.begin(w); k < walls.end(w); ++k) {
            const int f = walls.neighbour(k);
            Vec<Dim> r;
            const double W = wall_entry(walls, cached, k, x_w, Q.x, kernel, r);
            sum_w += W;
            a(k) = (1.0 + dot(by_phase ? phase_force.of(f) : body_force, r) / sound_speed_sq) * W;
          }
          for (int k = walls.begin(w); k < walls.end(w); ++k) a(k) = sum_w > 0 ? a(k) / sum_w : 0.0;
        });
    space.fence();
  }
  long long entries() const { return static_cast<long long>(weights_.extent(0)); }
  KOKKOS_INLINE_FUNCTION double operator()(int k) const { return weights_(k); }

 private:
  Kokkos::View<double*, MemorySpace> weights_;
};

// dp_w = sum_f a_wf dp_f into dp(w) of every owned boundary particle (see
// WallPressureWeights); fluid slots are left as they are. Without fluid in
// reach, 0.
template <int Dim, class ExecSpace, class Values>
void extrapolate_wall_pressure_change(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                                      const WallNeighbours<Dim, ExecSpace>& walls,
                                      const WallPressureWeights<Dim, ExecSpace>& weights, const Values& dp) {
  const auto kind = P.kind;
  static const std::string label = "poresph::extrapolate_wall_pressure_change";
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned), KOKKOS_LAMBDA(int w) {
        if (kind(w) == kFluid) return;
        // Four running sums, so that the gathers of dp overlap instead of
        // waiting on one chain of additions (a wall particle has tens of
        // fluid neighbours; in 3D this loop was 8 % of a steady solve).
        double sum[4] = {0, 0, 0, 0};
        const int begin = walls.begin(w), end = walls.end(w);
        int k = begin;
        for (; k + 4 <= end; k += 4)
          for (int j = 0; j < 4; ++j) sum[j] += weights(k + j) * dp(walls.neighbour(k + j));
        for (; k < end; ++k) sum[0] += weights(k) * dp(walls.neighbour(k));
        dp(w) = (sum[0] + sum[1]) + (sum[2] + sum[3]);
      });
}

}  // namespace poresph
