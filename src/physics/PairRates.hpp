#pragma once
// The one pair-interaction loop: for every owned particle, a single pass over
// its neighbours gives the continuity density rate, the pressure term and the
// Morris viscous term together. The neighbour list is a half list: a pair of
// owned particles is evaluated once and adds to both, into the calling
// thread's copy of the sums (core/PairSums.hpp), so threads never race.
#include <Kokkos_Core.hpp>

#include <string>
#include <type_traits>

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
  // The viscous pull of boundary neighbours, kappa (v_a - u_w), split into
  // kappa (the particle's wall_drag, integrated exactly by the step) and the
  // wall's kappa u_w (a rate like the others). With it d_a needs no bound of
  // sqrt(3)/4 dx against a stiff kappa: fixed particles use it.
  bool separate_wall_drag = false;
};

// What a scene adds to the three terms every pair has.
struct PairLoopOptions {
  ShiftingParameters shifting{};  // moving particles: towards uniform spacing
  bool convection = false;        // fixed particles: the convective term
  // Boundary particles integrate the continuity equation (the paper);
  // false when their pressure is extrapolated from the fluid instead
  // (physics/WallPressure.hpp), and their density is no state of its own.
  bool wall_continuity = true;
  // Fixed particles of one mass whose volumes use rho0 (the caller checks
  // after each list build): every neighbour's m and 1/rho are these, taken
  // as constants instead of read per pair. 0: read them.
  double uniform_mass = 0;
  double uniform_inverse_density = 0;
};

// What the pair loop adds beyond the continuity, pressure and viscous terms:
// the particle-shifting gradients (moving particles) or the convective term
// (fixed particles, whose velocity is that of the flow through their point).
enum class PairExtra { None, Shifting, Convection };

// Where each rate sits among a particle's pair sums: d rho/dt, dv/dt, and
// with particle shifting grad C and grad v (row-major, d v_i / d x_j), or
// without it the wall drag (FluidProperties::separate_wall_drag).
template <int Dim>
struct RateComponents {
  static constexpr int density = 0;
  static constexpr int acceleration = 1;
  static constexpr int wall_drag = 1 + Dim;
  static constexpr int grad_concentration = 1 + Dim;
  static constexpr int grad_velocity = 1 + 2 * Dim;
  static constexpr int count(bool shifting) { return shifting ? 1 + 2 * Dim + Dim * Dim : 2 + Dim; }
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

// One particle's rates from its neighbours, laid out as RateComponents says.
template <int Dim, bool WithShifting>
struct PairRateSums {
  using Components = RateComponents<Dim>;
  static constexpr int count = Components::count(WithShifting);
  double value[count] = {};
  KOKKOS_FORCEINLINE_FUNCTION double& drho() { return value[Components::density]; }
  KOKKOS_FORCEINLINE_FUNCTION double& acceleration(int d) { return value[Components::acceleration + d]; }
  KOKKOS_FORCEINLINE_FUNCTION double& wall_drag() { return value[Components::wall_drag]; }
  KOKKOS_FORCEINLINE_FUNCTION double& grad_concentration(int d) { return value[Components::grad_concentration + d]; }
  KOKKOS_FORCEINLINE_FUNCTION double& grad_velocity(int i, int j) {
    return value[Components::grad_velocity + i * Dim + j];
  }
};

// The per-pair helpers are force-inlined: GCC 12 left add() as a call,
// which spilled the sums to memory at every pair (27 % of the step).
// WithSurfaces = false compiles the loop without any boundary-particle code:
// a scene without walls or grains pays nothing for them. The sums are
// finished (body force, particle shifting) after the loop by FinishRates.
template <int Dim, class ExecSpace, bool WithSurfaces, PairExtra Extra>
struct PairRates {
  static constexpr bool WithShifting = Extra == PairExtra::Shifting;
  static constexpr bool WithConvection = Extra == PairExtra::Convection;
  using MemorySpace = typename ExecSpace::memory_space;
  using Components = RateComponents<Dim>;
  using Sums = PairRateSums<Dim, WithShifting>;
  // List entries per chunk of the pair loop: enough that the vectorised
  // phase runs full vectors, few enough that a chunk stays in L1.
  static constexpr int kPairChunk = 32;
  Particles<Dim, MemorySpace> P;
  NeighbourList<Dim, ExecSpace> neighbours;
  PairSums<ExecSpace> sums;
  QuinticKernel<Dim> kernel;
  FluidProperties fluid;
  bool cached;  // the list carries each pair's separation and F (fixed particles)
  // Whether a boundary particle takes anything from its pairs: the
  // continuity of its density (PairLoopOptions::wall_continuity). Otherwise
  // its end of every pair is left out, its terms would be thrown away, and a
  // pair of two boundary particles (a wall's or a grain's inside, about a
  // tenth of a channel's pairs) is skipped.
  bool boundary_pairs = true;
  NoSlipFactors<Dim, ExecSpace> no_slip;  // per list entry, when cached_no_slip
  bool cached_no_slip = false;
  double uniform_mass = 0, uniform_inverse_density = 0;  // PairLoopOptions

  // "poresph::PairRates<surfaces,convection>": what profiles show.
  static std::string label() {
    std::string extras = WithSurfaces ? "surfaces" : "";
    const char* extra = WithShifting ? "shifting" : WithConvection ? "convection" : "";
    if (*extra) extras += (extras.empty() ? "" : ",") + std::string(extra);
    return "poresph::PairRates" + (extras.empty() ? std::string() : "<" + extras + ">");
  }

  // Surfaces = false: a row of the list without boundary particles, whose
  // kinds need not be read.
  template <bool Surfaces = WithSurfaces>
  KOKKOS_FORCEINLINE_FUNCTION PairEnd<Dim> end_of(int i) const {
    int kind = kFluid;
    if constexpr (Surfaces) kind = P.kind(i);
    const bool uniform = uniform_mass > 0;  // two arrays fewer to gather from
    return {row<Dim>(P.x, i), row<Dim>(P.v, i), uniform ? uniform_mass : P.m(i),
            uniform ? uniform_inverse_density : P.inverse_density(i), P.pressure_term(i), kind, i};
  }

  // r = x_a - x_b and F = (1/r) dW/dr, as the first phases computed them.
  KOKKOS_FORCEINLINE_FUNCTION SharedPairTerms<Dim> shared_terms(const PairEnd<Dim>& a, const PairEnd<Dim>& b,
                                                                const Vec<Dim>& r, double F) const {
    SharedPairTerms<Dim> t;
    t.r = r;
    t.v = a.v - b.v;
    t.F = F;
    t.continuity = continuity_rate(1.0, t.v, t.r, t.F);
    t.pressure = pressure_acceleration(1.0, a.pressure_term, b.pressure_term, t.r, t.F);
    t.viscous = fluid.kinematic_viscosity * (a.inverse_density + b.inverse_density) * t.F;
    return t;
  }

  // The no-slip factor 1 + d_B / d_a of a boundary particle `other` seen at
  // separation r (physics/NoSlip.hpp), read from the cache for list entry
  // `entry` (-1: computed); 1 for a fluid particle.
  KOKKOS_FORCEINLINE_FUNCTION double viscous_factor(const PairEnd<Dim>& self, const PairEnd<Dim>& other,
                                                    const Vec<Dim>& r, int entry) const {
    if constexpr (WithSurfaces) {
      if (other.kind != kFluid)
        return entry >= 0 ? no_slip.factor(entry)
                          : no_slip_factor_seen(P, self.index, other.index, other.kind, r, fluid.min_surface_distance);
    }
    (void)self, (void)other, (void)r, (void)entry;
    return 1.0;
  }

  // Adds to `sum` what `self` gains from `other`; sign = +1 when self is the
  // pair's a, -1 when it is b (r and v change sign, the continuity does not);
  // entry: the pair's list entry where its no-slip factor is cached, or -1.
  KOKKOS_FORCEINLINE_FUNCTION void add(Sums& sum, const PairEnd<Dim>& self, const PairEnd<Dim>& other,
                                       const SharedPairTerms<Dim>& t, double sign, int entry) const {
    sum.drho() += other.m * t.continuity;
    if (WithSurfaces && self.kind != kFluid) return;  // boundary particles move as their surface prescribes
    const Vec<Dim> r = sign * t.r, v = sign * t.v;
    // v as self sees it: for a boundary neighbour, the fluid velocity
    // relative to the wall's continued linearly into the solid.
    const double factor = viscous_factor(self, other, r, entry);
    const Vec<Dim> v_seen = factor * v;
    Vec<Dim> acceleration = (other.m * sign) * t.pressure;
    if (WithSurfaces && !WithShifting && fluid.separate_wall_drag && other.kind != kFluid) {
      // other.m t.viscous factor (v_self - v_other) = -kappa_ab (v_self - v_other)
      const double kappa = -other.m * t.viscous * factor;
      sum.wall_drag() += kappa;
      acceleration += kappa * other.v;
    } else {
      acceleration += (other.m * t.viscous) * v_seen;
    }
    if constexpr (WithConvection)  // a boundary neighbour's velocity continues the flow linearly into the solid
      acceleration += convective_acceleration(other.m * other.inverse_density, self.v, v_seen, r, t.F);
    for (int d = 0; d < Dim; ++d) sum.acceleration(d) += acceleration[d];
    if constexpr (WithShifting) {
      const double volume_F = other.m * other.inverse_density * t.F;  // (m/rho) grad W = volume_F r
      for (int i = 0; i < Dim; ++i) {
        sum.grad_concentration(i) += volume_F * r[i];
        for (int j = 0; j < Dim; ++j) sum.grad_velocity(i, j) -= volume_F * v[i] * r[j];
      }
    }
  }

  // Both ends of a pair of fluid particles at once: each end's acceleration
  // is a weight of r and a weight of v_ab, so the terms are formed once for
  // the pair instead of once per end with their signs turned (the general
  // add(), which no-slip and shifting need). The same rates, rounded
  // differently.
  KOKKOS_FORCEINLINE_FUNCTION void add_fluid_pair(Sums& sum_a, Sums& sum_b, const PairEnd<Dim>& a,
                                                  const PairEnd<Dim>& b, const Vec<Dim>& r, double F) const {
    const Vec<Dim> v = a.v - b.v;
    const double continuity = F * dot(v, r);
    const double pressure = -(a.pressure_term + b.pressure_term) * F;
    const double viscous = fluid.kinematic_viscosity * (a.inverse_density + b.inverse_density) * F;
    double v_weight_a = b.m * viscous, v_weight_b = -(a.m * viscous);
    if constexpr (WithConvection) {  // -V_b F (v_a . r) (v_b - v_a) at a, the mirror at b
      v_weight_a += b.m * b.inverse_density * F * dot(a.v, r);
      v_weight_b += a.m * a.inverse_density * F * dot(b.v, r);
    }
    const double r_weight_a = b.m * pressure, r_weight_b = -(a.m * pressure);
    sum_a.drho() += b.m * continuity;
    sum_b.drho() += a.m * continuity;
    for (int d = 0; d < Dim; ++d) {
      sum_a.acceleration(d) += r_weight_a * r[d] + v_weight_a * v[d];
      sum_b.acceleration(d) += r_weight_b * r[d] + v_weight_b * v[d];
    }
  }

  // One pair (a, b) at separation r with F = (1/r) dW/dr: added to a and,
  // with BothEnds (b owned), to b's copy of the sums; entry as in add().
  template <bool BothEnds, bool Surfaces>
  KOKKOS_FORCEINLINE_FUNCTION void add_pair(const PairEnd<Dim>& end_a, Sums& sum_a, int copy, int b,
                                            const Vec<Dim>& r, double F, int entry) const {
    const PairEnd<Dim> end_b = end_of<Surfaces>(b);
    // Which ends need the pair's terms: a boundary particle only without
    // boundary_pairs, where its rates are thrown away (a ghost end never:
    // its owner adds the pair to it).
    const bool a_takes = !Surfaces || boundary_pairs || end_a.kind == kFluid;
    const bool b_takes = BothEnds && (!Surfaces || boundary_pairs || end_b.kind == kFluid);
    if (!a_takes && !b_takes) return;
    if constexpr (BothEnds && !WithShifting) {
      if (!Surfaces || (end_a.kind == kFluid && end_b.kind == kFluid)) {
        Sums sum_b;
        add_fluid_pair(sum_a, sum_b, end_a, end_b, r, F);
        // The density and acceleration: a pair of fluid particles adds no wall drag.
        for (int c = Components::density; c < Components::acceleration + Dim; ++c)
          sums.add(copy, b, c, sum_b.value[c]);
        return;
      }
    }
    const SharedPairTerms<Dim> t = shared_terms(end_a, end_b, r, F);
    if (a_takes) add(sum_a, end_a, end_b, t, 1.0, entry);
    if (b_takes) {
      Sums sum_b;
      add(sum_b, end_b, end_a, t, -1.0, entry);
      for (int c = 0; c < Sums::count; ++c) sums.add(copy, b, c, sum_b.value[c]);
    }
  }

  // Pairs of particle a with its list entries [first, last), in chunks of
  // kPairChunk entries and three phases per chunk:
  //  1. separations, and the entries within the support kept by a
  //     branch-free compaction (the list holds the skin too, and which
  //     entries fall in it is random: a branch on it mispredicts);
  //  2. F = (1/r) dW/dr of the kept pairs, a loop without branches or
  //     dependencies between pairs that the compiler vectorises (as scalar
  //     code, the latency of its sqrt and division was a quarter of the step);
  //  3. the terms of each kept pair (add_pair).
  template <bool BothEnds, bool Surfaces>
  KOKKOS_FORCEINLINE_FUNCTION void add_pairs(const PairEnd<Dim>& end_a, Sums& sum_a, int copy, int first,
                                             int last) const {
    for (int chunk_begin = first; chunk_begin < last; chunk_begin += kPairChunk) {
      const int chunk_end = chunk_begin + kPairChunk < last ? chunk_begin + kPairChunk : last;
      int b_of[kPairChunk];
      double r_of[Dim][kPairChunk];
      double F_of[kPairChunk];  // |r|^2 in phase 1, (1/r) dW/dr from phase 2
      int kept = 0;
      for (int k = chunk_begin; k < chunk_end; ++k) {
        const int b = neighbours.neighbour(k);
        double r_sq = 0.0;
        for (int d = 0; d < Dim; ++d) {
          const double r = end_a.x[d] - P.x(b, d);
          r_of[d][kept] = r;
          r_sq += r * r;
        }
        b_of[kept] = b;
        F_of[kept] = r_sq;
        kept += r_sq < kernel.cutoff_sq;
      }
      for (int j = 0; j < kept; ++j) F_of[j] = kernel.derivative_over_r(math::sqrt(F_of[j]));
      for (int j = 0; j < kept; ++j) {
        Vec<Dim> r;
        for (int d = 0; d < Dim; ++d) r[d] = r_of[d][j];
        add_pair<BothEnds, Surfaces>(end_a, sum_a, copy, b_of[j], r, F_of[j], -1);
      }
    }
  }

  // The same with the separations and F of a fixed arrangement, cached in
  // the list, and the no-slip factors if they are cached too: no gather of
  // positions, no kernel evaluation, no surface distances.
  template <bool BothEnds, bool Surfaces>
  KOKKOS_FORCEINLINE_FUNCTION void add_cached_pairs(const PairEnd<Dim>& end_a, Sums& sum_a, int copy, int first,
                                                    int last) const {
    for (int k = first; k < last; ++k) {
      Vec<Dim> r;
      for (int d = 0; d < Dim; ++d) r[d] = neighbours.separation(k, d);
      add_pair<BothEnds, Surfaces>(end_a, sum_a, copy, neighbours.neighbour(k), r, neighbours.derivative_over_r(k),
                                   cached_no_slip ? k : -1);
    }
  }

  KOKKOS_INLINE_FUNCTION void operator()(int a) const {
    if constexpr (WithSurfaces)  // most rows of a scene with surfaces have no boundary particle
      if (cached_no_slip && !no_slip.touches_surface(a)) return rates_of<false>(a);
    rates_of<WithSurfaces>(a);
  }

  template <bool Surfaces>
  KOKKOS_FORCEINLINE_FUNCTION void rates_of(int a) const {
    const PairEnd<Dim> end_a = end_of<Surfaces>(a);
    Sums sum_a;
    const int copy = sums.acquire();
    const int ghosts_begin = neighbours.ghosts_begin(a);
    if (cached) {
      add_cached_pairs<true, Surfaces>(end_a, sum_a, copy, neighbours.begin(a), ghosts_begin);
      add_cached_pairs<false, Surfaces>(end_a, sum_a, copy, ghosts_begin, neighbours.end(a));
    } else {
      add_pairs<true, Surfaces>(end_a, sum_a, copy, neighbours.begin(a), ghosts_begin);  // owned neighbours
      add_pairs<false, Surfaces>(end_a, sum_a, copy, ghosts_begin, neighbours.end(a));   // ghosts
    }
    for (int c = 0; c < Sums::count; ++c) sums.add(copy, a, c, sum_a.value[c]);
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
  bool wall_continuity;

  KOKKOS_INLINE_FUNCTION void operator()(int a) const {
    const bool a_is_fluid = P.kind(a) == kFluid;
    const double drhodt = sums.take(a, Components::density);
    P.drhodt(a) = a_is_fluid || wall_continuity ? drhodt : 0.0;
    if constexpr (!WithShifting) {
      const double drag = sums.take(a, Components::wall_drag);  // taken always: the copies return to zero
      if (P.has_surfaces) P.wall_drag(a) = a_is_fluid ? drag : 0.0;
    }
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
                        const PairLoopOptions& options = {}, const NoSlipFactors<Dim, ExecSpace>& no_slip = {}) {
  const auto policy = Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned);
  const ShiftingParameters& shifting = options.shifting;
  const bool shift = P.has_shifting && shifting.coefficient > 0;
  const PairExtra extra = shift ? PairExtra::Shifting : options.convection ? PairExtra::Convection : PairExtra::None;
  // Each combination is its own kernel: what a scene does not use is not compiled into its loop.
  auto run = [&](auto surfaces, auto chosen) {
    using Rates = PairRates<Dim, ExecSpace, decltype(surfaces)::value, decltype(chosen)::value>;
    static const std::string label = Rates::label();
    const bool cached = neighbours.has_geometry();
    Kokkos::parallel_for(label, policy,
                         Rates{P, neighbours, sums, kernel, fluid, cached, options.wall_continuity, no_slip,
                               cached && no_slip.built(), options.uniform_mass, options.uniform_inverse_density});
  };
  using Surfaces = std::true_type;
  using NoSurfaces = std::false_type;
  using Shifting = std::integral_constant<PairExtra, PairExtra::Shifting>;
  using Convection = std::integral_constant<PairExtra, PairExtra::Convection>;
  using Plain = std::integral_constant<PairExtra, PairExtra::None>;
  if (P.has_surfaces) {
    if (extra == PairExtra::Shifting) run(Surfaces{}, Shifting{});
    else if (extra == PairExtra::Convection) run(Surfaces{}, Convection{});
    else run(Surfaces{}, Plain{});
  } else {
    if (extra == PairExtra::Shifting) run(NoSurfaces{}, Shifting{});
    else if (extra == PairExtra::Convection) run(NoSurfaces{}, Convection{});
    else run(NoSurfaces{}, Plain{});
  }
  static const std::string label_finish = "poresph::FinishRates";
  const bool walls = options.wall_continuity;
  if (shift)
    Kokkos::parallel_for(label_finish, policy, FinishRates<Dim, ExecSpace, true>{P, sums, body_force, shifting, walls});
  else
    Kokkos::parallel_for(label_finish, policy,
                         FinishRates<Dim, ExecSpace, false>{P, sums, body_force, shifting, walls});
}

}  // namespace poresph
