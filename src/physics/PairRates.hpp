#pragma once
// The one pair-interaction loop: for every owned particle, a single pass over
// its neighbours gives the continuity density rate, the pressure term and the
// Morris viscous term together. The neighbour list is a half list: a pair of
// owned particles is evaluated once and adds to both, into the calling
// thread's copy of the sums (core/PairSums.hpp), so threads never race.
#include <Kokkos_Core.hpp>

#include "core/NeighbourList.hpp"
#include "core/Kernel.hpp"
#include "core/Math.hpp"
#include "core/PairSums.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"
#include "physics/NoSlip.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

// Particle shifting (Lind et al. 2012): each step a fluid particle moves by
// dr = -A h |v| dt grad C, C = sum_b (m_b/rho_b) W_ab its concentration,
// capped at a fraction of dx, and its velocity follows by v += (grad v) dr.
struct ShiftingParameters {
  double coefficient = 0;  // A; 0 = off
  double h_dt = 0;         // h * dt
  double max_shift = 0;    // cap on |dr|
};

struct FluidProperties {
  double kinematic_viscosity;
  double min_surface_distance;  // lower bound of d_a in the no-slip extrapolation
};

// Where each rate sits among a particle's pair sums: d rho/dt, dv/dt, and
// with particle shifting grad C and grad v (row-major, d v_i / d x_j).
template <int Dim>
struct RateComponents {
  static constexpr int density = 0;
  static constexpr int acceleration = 1;
  static constexpr int grad_concentration = 1 + Dim;
  static constexpr int grad_velocity = 1 + 2 * Dim;
  static constexpr int count(bool shifting) { return shifting ? 1 + 2 * Dim + Dim * Dim : 1 + Dim; }
};

// What the pair loop reads of one particle.
template <int Dim>
struct PairEnd {
  Vec<Dim> x, v;
  double m, inverse_density, pressure_term;
  int kind, index;
};

// What a pair gives, per unit mass of the particle on the other end, shared
// by both ends; r = x_a - x_b, v = v_a - v_b, F = (1/r) dW/dr.
template <int Dim>
struct SharedPairTerms {
  Vec<Dim> r, v;
  double F;
  double continuity;   // F v.r, the same from either end
  Vec<Dim> pressure;   // -(P_a + P_b) F r, as seen from a (b sees minus it)
  double viscous;      // nu (1/rho_a + 1/rho_b) F
};

// One particle's rates from its neighbours.
template <int Dim>
struct PairRateSums {
  double drho = 0.0;
  Vec<Dim> acceleration = Vec<Dim>::zero();
  Vec<Dim> grad_concentration = Vec<Dim>::zero();
  double grad_velocity[Dim][Dim] = {};
};

// The per-pair helpers are force-inlined: GCC 12 left add() as a call,
// which spilled the sums to memory at every pair (27 % of the step).
// WithSurfaces = false compiles the loop without any boundary-particle code:
// a scene without walls or grains pays nothing for them. The sums are
// finished (body force, particle shifting) after the loop by FinishRates.
template <int Dim, class ExecSpace, bool WithSurfaces, bool WithShifting>
struct PairRates {
  using MemorySpace = typename ExecSpace::memory_space;
  using Components = RateComponents<Dim>;
  Particles<Dim, MemorySpace> P;
  NeighbourList<Dim, ExecSpace> neighbours;
  PairSums<ExecSpace> sums;
  QuinticKernel<Dim> kernel;
  FluidProperties fluid;

  KOKKOS_FORCEINLINE_FUNCTION PairEnd<Dim> end_of(int i) const {
    int kind = kFluid;
    if constexpr (WithSurfaces) kind = P.kind(i);
    return {row<Dim>(P.x, i), row<Dim>(P.v, i), P.m(i), P.inverse_density(i), P.pressure_term(i), kind, i};
  }

  // r = x_a - x_b and r_sq = |r|^2, as the cutoff test computed them.
  KOKKOS_FORCEINLINE_FUNCTION SharedPairTerms<Dim> shared_terms(const PairEnd<Dim>& a, const PairEnd<Dim>& b,
                                                                const Vec<Dim>& r, double r_sq) const {
    SharedPairTerms<Dim> t;
    t.r = r;
    t.v = a.v - b.v;
    t.F = kernel.derivative_over_r(math::sqrt(r_sq));
    t.continuity = continuity_rate(1.0, t.v, t.r, t.F);
    t.pressure = pressure_acceleration(1.0, a.pressure_term, b.pressure_term, t.r, t.F);
    t.viscous = fluid.kinematic_viscosity * (a.inverse_density + b.inverse_density) * t.F;
    return t;
  }

  KOKKOS_FORCEINLINE_FUNCTION Vec<Dim> separation(const PairEnd<Dim>& a, int b) const {
    return a.x - row<Dim>(P.x, b);
  }

  // The viscous velocity difference fluid particle `self` sees for `other`
  // at separation r, velocity difference v: v itself, or for a boundary
  // particle its no-slip extrapolation.
  KOKKOS_FORCEINLINE_FUNCTION Vec<Dim> viscous_velocity(const PairEnd<Dim>& other, const Vec<Dim>& v,
                                                        const Vec<Dim>& r) const {
    if constexpr (WithSurfaces) {
      if (other.kind != kFluid) {
        const SurfaceDistances<Dim> s = surface_distances<Dim>(other.kind, row<Dim>(P.wall_vector, other.index),
                                                               P.wall_scalar(other.index), r);
        return no_slip_factor(s, fluid.min_surface_distance) * v;
      }
    }
    (void)other, (void)r;
    return v;
  }

  // Adds to `sum` what `self` gains from `other`; sign = +1 when self is the
  // pair's a, -1 when it is b (r and v change sign, the continuity does not).
  KOKKOS_FORCEINLINE_FUNCTION void add(PairRateSums<Dim>& sum, const PairEnd<Dim>& self, const PairEnd<Dim>& other,
                                       const SharedPairTerms<Dim>& t, double sign) const {
    sum.drho += other.m * t.continuity;
    if (WithSurfaces && self.kind != kFluid) return;  // boundary particles move as their surface prescribes
    const Vec<Dim> r = sign * t.r, v = sign * t.v;
    sum.acceleration += other.m * (sign * t.pressure + t.viscous * viscous_velocity(other, v, r));
    if constexpr (WithShifting) {
      const double volume_F = other.m * other.inverse_density * t.F;  // (m/rho) grad W = volume_F r
      sum.grad_concentration += volume_F * r;
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) sum.grad_velocity[i][j] -= volume_F * v[i] * r[j];
    }
  }

  KOKKOS_FORCEINLINE_FUNCTION void add_to_sums(int copy, int i, const PairRateSums<Dim>& sum) const {
    sums.add(copy, i, Components::density, sum.drho);
    for (int d = 0; d < Dim; ++d) sums.add(copy, i, Components::acceleration + d, sum.acceleration[d]);
    if constexpr (WithShifting) {
      for (int d = 0; d < Dim; ++d) sums.add(copy, i, Components::grad_concentration + d, sum.grad_concentration[d]);
      for (int d = 0; d < Dim; ++d)
        for (int e = 0; e < Dim; ++e)
          sums.add(copy, i, Components::grad_velocity + d * Dim + e, sum.grad_velocity[d][e]);
    }
  }

  KOKKOS_INLINE_FUNCTION void operator()(int a) const {
    const PairEnd<Dim> end_a = end_of(a);
    PairRateSums<Dim> sum_a;
    const int copy = sums.acquire();
    const int ghosts_begin = neighbours.ghosts_begin(a), end = neighbours.end(a);
    // The list holds the skin too: pairs beyond the support are skipped
    // before anything but the position is read.
    for (int k = neighbours.begin(a); k < ghosts_begin; ++k) {  // owned: both ends
      const int b = neighbours.neighbour(k);
      const Vec<Dim> r = separation(end_a, b);
      const double r_sq = dot(r, r);
      if (r_sq >= kernel.cutoff_sq) continue;
      const PairEnd<Dim> end_b = end_of(b);
      const SharedPairTerms<Dim> t = shared_terms(end_a, end_b, r, r_sq);
      add(sum_a, end_a, end_b, t, 1.0);
      PairRateSums<Dim> sum_b;
      add(sum_b, end_b, end_a, t, -1.0);
      add_to_sums(copy, end_b.index, sum_b);
    }
    for (int k = ghosts_begin; k < end; ++k) {  // ghosts: their owners evaluate the pair for them
      const int b = neighbours.neighbour(k);
      const Vec<Dim> r = separation(end_a, b);
      const double r_sq = dot(r, r);
      if (r_sq >= kernel.cutoff_sq) continue;
      const PairEnd<Dim> end_b = end_of(b);
      add(sum_a, end_a, end_b, shared_terms(end_a, end_b, r, r_sq), 1.0);
    }
    add_to_sums(copy, a, sum_a);
    sums.release(copy);
  }
};

// After the pair loop: the sums into the particles' rates, the body force on
// fluid particles, none on boundary particles, and the particle-shifting
// displacement from the summed gradients.
template <int Dim, class ExecSpace, bool WithShifting>
struct FinishRates {
  using Components = RateComponents<Dim>;
  Particles<Dim, typename ExecSpace::memory_space> P;
  PairSums<ExecSpace> sums;
  Vec<Dim> body_force;
  ShiftingParameters shifting;

  KOKKOS_INLINE_FUNCTION void operator()(int a) const {
    const bool a_is_fluid = P.kind(a) == kFluid;
    P.drhodt(a) = sums.take(a, Components::density);
    for (int d = 0; d < Dim; ++d) {
      const double pairs = sums.take(a, Components::acceleration + d);
      P.dvdt(a, d) = a_is_fluid ? pairs + body_force[d] : 0.0;
    }
    if constexpr (WithShifting) {
      Vec<Dim> grad_concentration;
      double grad_velocity[Dim][Dim];
      for (int i = 0; i < Dim; ++i) {
        grad_concentration[i] = sums.take(a, Components::grad_concentration + i);
        for (int j = 0; j < Dim; ++j) grad_velocity[i][j] = sums.take(a, Components::grad_velocity + i * Dim + j);
      }
      Vec<Dim> shift = Vec<Dim>::zero(), dv = Vec<Dim>::zero();
      if (a_is_fluid) {
        const Vec<Dim> v_a = row<Dim>(P.v, a);
        shift = (-shifting.coefficient * shifting.h_dt * math::sqrt(dot(v_a, v_a))) * grad_concentration;
        const double length = math::sqrt(dot(shift, shift));
        if (length > shifting.max_shift) shift = (shifting.max_shift / length) * shift;
        for (int i = 0; i < Dim; ++i)
          for (int j = 0; j < Dim; ++j) dv[i] += grad_velocity[i][j] * shift[j];
      }
      set_row(P.shift, a, shift);
      set_row(P.shift_velocity, a, dv);
    }
  }
};

// Evaluates the rates of all owned particles; ghosts and the neighbour list
// must be up to date, and `sums` must hold RateComponents<Dim>::count(shifting)
// components for every owned particle.
template <int Dim, class ExecSpace>
void compute_pair_rates(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                        const NeighbourList<Dim, ExecSpace>& neighbours, const PairSums<ExecSpace>& sums,
                        const QuinticKernel<Dim>& kernel, const FluidProperties& fluid, const Vec<Dim>& body_force,
                        const ShiftingParameters& shifting = {}) {
  const auto policy = Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned);
  const bool shift = P.has_shifting && shifting.coefficient > 0;
  // Each combination is its own kernel: what a scene does not use is not compiled into its loop.
  static const std::string label_surfaces_shifting = "poresph::PairRates<surfaces,shifting>";
  static const std::string label_surfaces = "poresph::PairRates<surfaces>";
  static const std::string label_shifting = "poresph::PairRates<shifting>";
  static const std::string label_plain = "poresph::PairRates";
  if (P.has_surfaces && shift)
    Kokkos::parallel_for(label_surfaces_shifting, policy,
                         PairRates<Dim, ExecSpace, true, true>{P, neighbours, sums, kernel, fluid});
  else if (P.has_surfaces)
    Kokkos::parallel_for(label_surfaces, policy,
                         PairRates<Dim, ExecSpace, true, false>{P, neighbours, sums, kernel, fluid});
  else if (shift)
    Kokkos::parallel_for(label_shifting, policy,
                         PairRates<Dim, ExecSpace, false, true>{P, neighbours, sums, kernel, fluid});
  else
    Kokkos::parallel_for(label_plain, policy,
                         PairRates<Dim, ExecSpace, false, false>{P, neighbours, sums, kernel, fluid});
  static const std::string label_finish = "poresph::FinishRates";
  if (shift)
    Kokkos::parallel_for(label_finish, policy, FinishRates<Dim, ExecSpace, true>{P, sums, body_force, shifting});
  else
    Kokkos::parallel_for(label_finish, policy, FinishRates<Dim, ExecSpace, false>{P, sums, body_force, shifting});
}

}  // namespace poresph
