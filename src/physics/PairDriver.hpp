#pragma once
// The one pair-interaction loop, over a list of pair terms fixed at compile
// time: for every owned particle, a single pass over its neighbours adds
// every term of every pair. The neighbour list is a half list: a pair of
// owned particles is evaluated once and adds to both, into the calling
// thread's copy of the sums (core/PairSums.hpp), so threads never race.
//
// The driver owns what every term shares: the chunked, vectorised kernel
// evaluation, the half list and its ghost rows, the cached geometry of fixed
// particles, the sums and their scatter to the second end. A term
// (physics/terms/, registered in physics/PairRates.hpp) says only what one
// pair adds, through the KOKKOS_INLINE_FUNCTION functions of
// physics/PairTerms.hpp; PairTermConcept below lists what it provides. A
// scene's loop is compiled with the terms it uses and no others.
#include <Kokkos_Core.hpp>

#include <string>
#include <type_traits>

#include "core/Kernel.hpp"
#include "core/Math.hpp"
#include "core/NeighbourList.hpp"
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
  // Two fluids (Particles::phase): each phase's kinematic viscosity, which
  // the phases' terms take instead of kinematic_viscosity
  // (physics/terms/PhaseViscousTerm.hpp).
  double phase_kinematic_viscosity[kMaxPhases] = {};
};

// What a scene adds to the terms every pair has.
struct PairLoopOptions {
  ShiftingParameters shifting{};  // moving particles: towards uniform spacing
  bool convection = false;        // fixed particles: the convective term
  // Boundary particles integrate the continuity equation (the paper);
  // false when their pressure is extrapolated from the fluid instead
  // (physics/WallPressure.hpp), and their density is no state of its own.
  bool wall_continuity = true;
  // Fixed particles of one mass (the caller checks after each list build):
  // every neighbour's m, taken as a constant instead of read per pair; and
  // fixed particles, whose volumes use rho0: every 1/rho is 1/rho0 (they
  // hold no inverse_density). 0: read them.
  double uniform_mass = 0;
  double uniform_inverse_density = 0;
  // A boundary particle's end of each pair with a fluid particle takes the
  // reaction to what the fluid gains from it (physics/terms/
  // SurfaceReactionTerm.hpp): the fluid's force on the surfaces, m times
  // the boundary particle's acceleration sum. On in the time loop of a
  // scene whose grains move (physics/RigidGrains.hpp); otherwise only in
  // Simulation::surface_loads.
  bool surface_reactions = false;
  // With the reactions: whether fluid particles' ends take their terms too.
  // false: only the boundary ends (their reactions), and the fluid's sums
  // are left as they are: the forces on the surfaces of
  // compute_surface_forces, which must not disturb the rates when they are
  // the sums' first copy (core/PairSums.hpp).
  bool fluid_ends = true;
};

// Which particles a term applies to: a list holding a term for fixed
// particles and one for moving particles is never compiled.
enum class TermMotion { Any, Fixed, Moving };

// Everything a term is made from (each takes what it needs).
template <int Dim, class ExecSpace>
struct PairTermInputs {
  const Particles<Dim, typename ExecSpace::memory_space>& particles;
  const FluidProperties& fluid;
  const PairLoopOptions& options;
  const NoSlipFactors<Dim, ExecSpace>& no_slip;
  bool cached;  // the list carries each pair's separation and F (fixed particles)
};

// What the pair loop reads of one particle.
template <int Dim>
struct PairEnd {
  Vec<Dim> x, v;
  double m, inverse_density, pressure_term;
  int kind, index;
};

// What one end of a listed pair (a, b) sees of it, beyond the two ends:
// r and v from self to its neighbour (x_self - x_other, v_self - v_other),
// F = (1/r) dW/dr, and the sign that turns what a term formed once for the
// pair from a's side (its shared()) into self's: +1 at a, -1 at b.
// Aggregates that the pair loop passes around stay this small, and hold no
// references: so the compiler keeps them in registers and sees the kinds of
// rows without boundary particles as the constants they are (a larger one
// changed how it contracted the sums into fused multiply-adds).
template <int Dim>
struct EndGeometry {
  Vec<Dim> r, v;
  double F, sign;
};

// The neighbour's velocity relative to self as self sees it: for a boundary
// neighbour, the fluid's relative to the wall continued linearly into the
// solid (physics/terms/NoSlipTerm.hpp), factor times v; otherwise v.
template <int Dim>
struct SeenVelocity {
  double factor;
  Vec<Dim> v;
};

// Both ends of a pair of fluid particles at once: each end's acceleration is
// a weight of r_ab and a weight of v_ab, which the terms add to, so that the
// pair's terms are formed once instead of once per end with their signs
// turned (the general path, which no-slip and shifting need). The weights
// and density rates start at -0.0, which any addition leaves exactly as its
// other operand.
struct FluidPairWeights {
  double r_a = -0.0, r_b = -0.0;
  double v_a = -0.0, v_b = -0.0;
  double drho_a = -0.0, drho_b = -0.0;
};

// One particle's rates from its neighbours: d rho/dt, dv/dt, then each
// term's own components (wall drag, shifting gradients) in the list's order.
template <int Dim, int Count>
struct PairRateSums {
  static constexpr int density = 0;
  static constexpr int acceleration_begin = 1;
  static constexpr int terms_begin = 1 + Dim;  // the first term's own components
  static constexpr int count = Count;
  double value[count] = {};
  KOKKOS_FORCEINLINE_FUNCTION double& drho() { return value[density]; }
  KOKKOS_FORCEINLINE_FUNCTION double& acceleration(int d) { return value[acceleration_begin + d]; }
};

// A term's own components of particle a after the loop, taken from the
// threads' copies (which are left zero).
template <int Dim, class ExecSpace>
struct TermTotals {
  const PairSums<Dim, ExecSpace>& sums;
  int particle, offset;
  KOKKOS_FORCEINLINE_FUNCTION double take(int i) const { return sums.take(particle, offset + i); }
};

// What a term need not say when it has nothing to add: each term derives
// from this and overrides what it does (physics/terms/ holds examples).
struct PairTermBase {
  // What the term forms once per pair for both ends (shared()).
  struct Shared {};
  static constexpr bool optional = true;               // false: every scene has it
  static constexpr TermMotion motion = TermMotion::Any;
  static constexpr int components = 0;                 // sums of its own beyond d rho/dt and dv/dt
  static constexpr bool at_boundary_ends = false;      // adds to boundary particles too (before they leave)
  static constexpr bool fluid_pair_weights = true;     // a pair of fluid particles is weights of r and v
  static constexpr bool surfaces = false;              // brings boundary particles (row_touches_surface)
  static constexpr bool reactions = false;             // boundary ends take reactions (SurfaceReactionTerm)
  // What the term touches of the shared sums and the ends (true unless it
  // says otherwise): a loop whose terms add no density rate, no
  // acceleration, or read no velocity leaves those out (the steady solver's
  // loops of the pressure term alone and of continuity alone).
  static constexpr bool adds_density = true;
  static constexpr bool adds_acceleration = true;
  static constexpr bool reads_velocity = true;
  template <class Inputs>
  static bool wanted(const Inputs&) { return true; }
  template <int Dim>
  KOKKOS_FORCEINLINE_FUNCTION Shared shared(const PairEnd<Dim>&, const PairEnd<Dim>&, const Vec<Dim>&,
                                            const Vec<Dim>&, double) const {
    return {};
  }
  template <int Dim>
  KOKKOS_FORCEINLINE_FUNCTION void see(const PairEnd<Dim>&, const PairEnd<Dim>&, const EndGeometry<Dim>&, int,
                                       SeenVelocity<Dim>&) const {}
  template <int Dim>
  KOKKOS_FORCEINLINE_FUNCTION void add_to_fluid_pair(const PairEnd<Dim>&, const PairEnd<Dim>&, const Vec<Dim>&,
                                                     const Vec<Dim>&, double, FluidPairWeights&) const {}
  template <class Particles, class Totals>
  KOKKOS_FORCEINLINE_FUNCTION void finish(const Particles&, int, bool, const Totals&) const {}
};

template <class... Terms>
struct PairTermList {};

namespace pair_detail {

// One term's part of a pair's shared values.
template <class Term>
struct SharedOf {
  typename Term::Shared value;
};
template <class... Terms>
struct PairShared : SharedOf<Terms>... {};

// The offset of Term's own components: after d rho/dt, dv/dt and those of the terms before it.
template <int Dim, class Term, class... Terms>
struct OffsetOf;
template <int Dim, class Term, class First, class... Rest>
struct OffsetOf<Dim, Term, First, Rest...> {
  static constexpr int value =
      std::is_same_v<Term, First> ? 1 + Dim : First::components + OffsetOf<Dim, Term, Rest...>::value;
};
template <int Dim, class Term>
struct OffsetOf<Dim, Term> {
  static constexpr int value = 1 + Dim;
};

template <class... Terms>
constexpr bool motions_agree() {
  const bool fixed = ((Terms::motion == TermMotion::Fixed) || ...);
  const bool moving = ((Terms::motion == TermMotion::Moving) || ...);
  return !(fixed && moving);
}

}  // namespace pair_detail

// What the driver asks of a term, checked where a term list is compiled.
template <int Dim, class ExecSpace, class Term>
struct PairTermConcept {
  static_assert(std::is_base_of_v<PairTermBase, Term>, "a pair term derives from PairTermBase");
  static_assert(std::is_same_v<std::remove_cv_t<decltype(Term::name)>, const char*>,
                "a pair term names itself (the loop's label)");
  static_assert(std::is_constructible_v<Term, const PairTermInputs<Dim, ExecSpace>&>,
                "a pair term is made from PairTermInputs");
  static_assert(Term::components >= 0, "a pair term's own sums are counted");
  static_assert(std::is_copy_constructible_v<Term>, "a pair term is copied into the kernel");
  static constexpr bool value = true;
};

// The pair loop over Terms. Surfaces (the no-slip term is among them):
// boundary particles exist; rows of the list without one still take the
// loop compiled without them. The per-pair helpers are force-inlined:
// GCC 12 left such helpers as calls, which spilled the sums to memory at
// every pair (27 % of the step).
template <int Dim, class ExecSpace, class... Terms>
struct PairDriver : Terms... {
  static_assert((PairTermConcept<Dim, ExecSpace, Terms>::value && ...));
  static_assert(pair_detail::motions_agree<Terms...>(), "a term list mixes fixed-particle and moving-particle terms");
  static constexpr bool WithSurfaces = (Terms::surfaces || ...);
  // Boundary ends take the reactions to what the fluid gains from them
  // (physics/terms/SurfaceReactionTerm.hpp, add_reaction).
  static constexpr bool WithReactions = (Terms::reactions || ...);
  // All terms are weights of r and v for a pair of fluid particles: both its ends at once.
  static constexpr bool FluidPairsAsWeights = (Terms::fluid_pair_weights && ...);
  // Sums no term adds to are not added (they would add -0.0 or +0.0 to sums
  // that start at +0.0, which changes no bit), velocities no term reads not
  // loaded (they stay zero).
  static constexpr bool AddsDensity = (Terms::adds_density || ...);
  static constexpr bool AddsAcceleration = (Terms::adds_acceleration || ...);
  static constexpr bool ReadsVelocity = (Terms::reads_velocity || ...);
  using MemorySpace = typename ExecSpace::memory_space;
  using Sums = PairRateSums<Dim, 1 + Dim + (Terms::components + ... + 0)>;
  template <class Term>
  static constexpr int offset_of = pair_detail::OffsetOf<Dim, Term, Terms...>::value;
  // List entries per chunk of the pair loop: enough that the vectorised
  // phase runs full vectors, few enough that a chunk stays in L1.
  static constexpr int kPairChunk = 32;

  Particles<Dim, MemorySpace> P;
  NeighbourList<Dim, ExecSpace> neighbours;
  PairSums<Dim, ExecSpace> sums;
  QuinticKernel<Dim> kernel;
  bool cached;  // the list carries each pair's separation and F (fixed particles)
  bool lattice_rows;  // its rows are masks over the stencil (core/LatticeRows.hpp)
  // Whether a boundary particle takes anything from its pairs: the
  // continuity of its density (PairLoopOptions::wall_continuity). Otherwise
  // its end of every pair is left out, its terms would be thrown away, and a
  // pair of two boundary particles (a wall's or a grain's inside, about a
  // tenth of a channel's pairs) is skipped. Also with the reactions,
  // which boundary ends take (add_reaction).
  bool boundary_pairs = true;
  double uniform_mass = 0, uniform_inverse_density = 0;  // PairLoopOptions
  bool fluid_ends = true;                                 // PairLoopOptions (with the reactions only)

  PairDriver(const PairTermInputs<Dim, ExecSpace>& in, const NeighbourList<Dim, ExecSpace>& list,
             const PairSums<Dim, ExecSpace>& pair_sums, const QuinticKernel<Dim>& W)
      : Terms(in)...,
        P(in.particles),
        neighbours(list),
        sums(pair_sums),
        kernel(W),
        cached(in.cached),
        lattice_rows(list.on_lattice_rows()),
        boundary_pairs(in.options.wall_continuity || WithReactions),
        uniform_mass(in.options.uniform_mass),
        uniform_inverse_density(in.options.uniform_inverse_density),
        fluid_ends(in.options.fluid_ends) {}

  // "poresph::PairRates<no_slip,convection>": what profiles show.
  static std::string label() {
    std::string extras;
    ((extras += (Terms::optional ? (extras.empty() ? "" : ",") + std::string(Terms::name) : std::string())), ...);
    return "poresph::PairRates" + (extras.empty() ? std::string() : "<" + extras + ">");
  }

  // Surfaces = false: a row of the list without boundary particles, whose
  // kinds need not be read.
  template <bool Surfaces = WithSurfaces>
  KOKKOS_FORCEINLINE_FUNCTION PairEnd<Dim> end_of(int i) const {
    int kind = kFluid;
    if constexpr (Surfaces) kind = P.kind(i);
    // Constants where they are (PairLoopOptions): arrays fewer to gather from.
    PairEnd<Dim> end{{},
                     {},
                     uniform_mass > 0 ? uniform_mass : P.m(i),
                     uniform_inverse_density > 0 ? uniform_inverse_density : P.inverse_density(i),
                     P.pressure_term(i),
                     kind,
                     i};
    for (int d = 0; d < Dim; ++d) {
      end.x.c[d] = P.x(i, d);
      if constexpr (ReadsVelocity) end.v.c[d] = P.v(i, d);
    }
    return end;
  }

  // Whether an end of this kind takes its terms: every end, but with the
  // reactions and without fluid_ends only boundary particles'.
  KOKKOS_FORCEINLINE_FUNCTION bool takes_end(int kind) const {
    return !WithReactions || fluid_ends || kind != kFluid;
  }

  // Whether component c of the sums is one some term adds to.
  KOKKOS_FORCEINLINE_FUNCTION static constexpr bool added(int c) {
    if (c == Sums::density) return AddsDensity;
    if (c < Sums::terms_begin) return AddsAcceleration;
    return true;
  }
  // Particle i's sums of this pair loop into copy `copy` of the shared ones.
  KOKKOS_FORCEINLINE_FUNCTION void add_sums(int copy, int i, const Sums& sum) const {
    for (int c = 0; c < Sums::count; ++c)
      if (added(c)) sums.add(copy, i, c, sum.value[c]);
  }

  // Adds to `sum` what `self` gains from `other`: the terms that act on
  // boundary particles (their density), and for a fluid particle the others,
  // whose accelerations are summed in the list's order (from -0.0, which the
  // first addition leaves exactly as the term's) before they join the sums.
  // entry: the pair's place among the cached fluid-boundary pairs of fixed
  // particles (NoSlipFactors), else -1.
  using Shared = pair_detail::PairShared<Terms...>;
  template <class Term, bool AtBoundaryEnds>
  KOKKOS_FORCEINLINE_FUNCTION void add_term(Sums& sum, Vec<Dim>& acceleration, const PairEnd<Dim>& self,
                                            const PairEnd<Dim>& other, const EndGeometry<Dim>& g,
                                            const SeenVelocity<Dim>& seen, const Shared& shared) const {
    if constexpr (Term::at_boundary_ends == AtBoundaryEnds)
      static_cast<const Term&>(*this).template add_to_end<offset_of<Term>>(
          self, other, g, seen, static_cast<const pair_detail::SharedOf<Term>&>(shared).value, sum, acceleration);
  }
  KOKKOS_FORCEINLINE_FUNCTION void add(Sums& sum, const PairEnd<Dim>& self, const PairEnd<Dim>& other,
                                       const EndGeometry<Dim>& g, int entry, const Shared& shared) const {
    Vec<Dim> acceleration;
    for (int d = 0; d < Dim; ++d) acceleration[d] = -0.0;
    SeenVelocity<Dim> seen{1.0, g.v};
    (add_term<Terms, true>(sum, acceleration, self, other, g, seen, shared), ...);
    if (WithSurfaces && self.kind != kFluid) {  // boundary particles move as their surface prescribes
      if constexpr (WithReactions)
        if (other.kind == kFluid) add_reaction(sum, self, other, g, entry, shared);
      return;
    }
    (static_cast<const Terms&>(*this).see(self, other, g, entry, seen), ...);
    (add_term<Terms, false>(sum, acceleration, self, other, g, seen, shared), ...);
    for (int d = 0; d < Dim; ++d) sum.acceleration(d) += acceleration[d];
  }
  // With the reactions: boundary particle `self` takes into its
  // acceleration minus what fluid particle `fluid` gains from it, over the
  // mass ratio, so that m_self a_self = -m_fluid a_fluid and the pair
  // conserves momentum. The gain is formed by the fluid's own end, add()
  // (the same terms, the same no-slip factor), with the whole viscous pull:
  // a wall drag kept apart (FluidProperties::separate_wall_drag) must be off.
  // Not force-inlined: it calls add(), which calls it.
  KOKKOS_INLINE_FUNCTION void add_reaction(Sums& sum, const PairEnd<Dim>& self, const PairEnd<Dim>& fluid,
                                           const EndGeometry<Dim>& g, int entry, const Shared& shared) const {
    Sums gained;
    add(gained, fluid, self, EndGeometry<Dim>{-1.0 * g.r, -1.0 * g.v, g.F, -g.sign}, entry, shared);
    const double ratio = -fluid.m / self.m;
    for (int d = 0; d < Dim; ++d) sum.acceleration(d) += ratio * gained.acceleration(d);
  }

  // Whether row a of the list has a boundary particle (a or a neighbour), as
  // the terms that bring them know it; rows without take the loop compiled
  // without surfaces.
  template <class Term>
  KOKKOS_FORCEINLINE_FUNCTION bool touches_surface(int a) const {
    if constexpr (Term::surfaces) return static_cast<const Term&>(*this).row_touches_surface(a);
    (void)a;
    return false;
  }

  // Where row a's fluid-boundary pairs begin in the per-pair caches of the
  // terms that bring surfaces (-1: none cached). The cached loop counts
  // them from there, in the list's order.
  template <class Term>
  KOKKOS_FORCEINLINE_FUNCTION int first_surface_pair(int a) const {
    if constexpr (Term::surfaces) return static_cast<const Term&>(*this).row_first_surface_pair(a);
    (void)a;
    return -1;
  }

  // One pair (a, b) at separation r with F = (1/r) dW/dr: added to a and,
  // with BothEnds (b owned), to b's copy of the sums; entry as in add().
  template <bool BothEnds, bool Surfaces>
  KOKKOS_FORCEINLINE_FUNCTION void add_pair(const PairEnd<Dim>& end_a, Sums& sum_a, int copy, int b,
                                            const Vec<Dim>& r, double F, int entry) const {
    const PairEnd<Dim> end_b = end_of<Surfaces>(b);
    // Which ends need the pair's terms: a boundary particle only with
    // boundary_pairs (a ghost end never: its owner adds the pair to it).
    // (boundary_pairs is set with the reactions: a boundary end then takes its reaction.)
    const bool a_takes = (!Surfaces || boundary_pairs || end_a.kind == kFluid) && takes_end(end_a.kind);
    const bool b_takes = BothEnds && (!Surfaces || boundary_pairs || end_b.kind == kFluid) && takes_end(end_b.kind);
    if (!a_takes && !b_takes) return;
    if constexpr (BothEnds && FluidPairsAsWeights) {
      if (!Surfaces || (end_a.kind == kFluid && end_b.kind == kFluid)) {
        Sums sum_b;
        const Vec<Dim> v = end_a.v - end_b.v;
        FluidPairWeights w;
        (static_cast<const Terms&>(*this).add_to_fluid_pair(end_a, end_b, r, v, F, w), ...);
        if constexpr (AddsDensity) {
          sum_a.drho() += w.drho_a;
          sum_b.drho() += w.drho_b;
        }
        if constexpr (AddsAcceleration)
          for (int d = 0; d < Dim; ++d) {
            sum_a.acceleration(d) += w.r_a * r[d] + w.v_a * v[d];
            sum_b.acceleration(d) += w.r_b * r[d] + w.v_b * v[d];
          }
        // The density and acceleration: a pair of fluid particles adds to no term's own sums.
        for (int c = Sums::density; c < Sums::terms_begin; ++c)
          if (added(c)) sums.add(copy, b, c, sum_b.value[c]);
        return;
      }
    }
    const Vec<Dim> v = end_a.v - end_b.v;
    const Shared shared{pair_detail::SharedOf<Terms>{static_cast<const Terms&>(*this).shared(end_a, end_b, r, v, F)}...};
    if (a_takes) add(sum_a, end_a, end_b, EndGeometry<Dim>{r, v, F, 1.0}, entry, shared);
    if (b_takes) {
      Sums sum_b;
      add(sum_b, end_b, end_a, EndGeometry<Dim>{-1.0 * r, -1.0 * v, F, -1.0}, entry, shared);
      add_sums(copy, b, sum_b);
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
  // the list: no gather of positions, no kernel evaluation.
  // surface_pair: the next fluid-boundary pair's place in the per-pair
  // caches (-1: none), counted on.
  template <bool BothEnds, bool Surfaces>
  KOKKOS_FORCEINLINE_FUNCTION void add_cached_pairs(const PairEnd<Dim>& end_a, Sums& sum_a, int copy, int first,
                                                    int last, int& surface_pair) const {
    for (int k = first; k < last; ++k) {
      Vec<Dim> r;
      for (int d = 0; d < Dim; ++d) r[d] = neighbours.separation(k, d);
      const int b = neighbours.neighbour(k);
      int entry = -1;
      if constexpr (Surfaces)
        if (surface_pair >= 0 && fluid_boundary_pair(end_a.kind, P.kind(b))) entry = surface_pair++;
      add_pair<BothEnds, Surfaces>(end_a, sum_a, copy, b, r, neighbours.derivative_over_r(k), entry);
    }
  }

  // The same for a row said by masks over the stencil (core/LatticeRows.hpp):
  // the owned neighbours' mask with BothEnds, else the ghosts', in the
  // stencil's order, as the sorted list had them.
  template <bool BothEnds, bool Surfaces>
  KOKKOS_FORCEINLINE_FUNCTION void add_lattice_pairs(const PairEnd<Dim>& end_a, Sums& sum_a, int copy,
                                                     int& surface_pair) const {
    constexpr int kBits = LatticeRows<Dim, ExecSpace>::kBits;
    const auto& rows = neighbours.lattice_rows();
    const int a = end_a.index, site = rows.site(a), words = rows.words();
    for (int w = 0; w < words; ++w) {
      auto bits = rows.template bits<BothEnds>(a, w);
      if (bits == 0) continue;
      // The next pair's neighbour is looked up before this pair's terms, so
      // that the map's load (a list's index is a stream) is under way while they run.
      int next_id = w * kBits + lowest_bit(bits);
      int next_b = rows.neighbour_of_site(site, next_id);
      while (true) {
        const int id = next_id, b = next_b;
        bits &= bits - 1;
        if (bits != 0) {
          next_id = w * kBits + lowest_bit(bits);
          next_b = rows.neighbour_of_site(site, next_id);
        }
        Vec<Dim> r;
        for (int d = 0; d < Dim; ++d) r[d] = rows.separation(id, d);
        int entry = -1;
        if constexpr (Surfaces)
          if (surface_pair >= 0 && fluid_boundary_pair(end_a.kind, P.kind(b))) entry = surface_pair++;
        add_pair<BothEnds, Surfaces>(end_a, sum_a, copy, b, r, rows.of_distance(id), entry);
        if (bits == 0) break;
      }
    }
  }

  KOKKOS_INLINE_FUNCTION void operator()(int a) const {
    if constexpr (WithSurfaces)  // most rows of a scene with surfaces have no boundary particle
      if (!(touches_surface<Terms>(a) || ...)) return rates_of<false>(a);
    rates_of<WithSurfaces>(a);
  }

  template <bool Surfaces>
  KOKKOS_FORCEINLINE_FUNCTION void rates_of(int a) const {
    const PairEnd<Dim> end_a = end_of<Surfaces>(a);
    Sums sum_a;
    const int copy = sums.acquire();
    if (cached) {
      int surface_pair = -1;
      if constexpr (Surfaces) ((surface_pair = first_surface_pair<Terms>(a) >= 0 ? first_surface_pair<Terms>(a) : surface_pair), ...);
      if (lattice_rows) {
        add_lattice_pairs<true, Surfaces>(end_a, sum_a, copy, surface_pair);
        add_lattice_pairs<false, Surfaces>(end_a, sum_a, copy, surface_pair);
      } else {
        const int ghosts_begin = neighbours.ghosts_begin(a);
        add_cached_pairs<true, Surfaces>(end_a, sum_a, copy, neighbours.begin(a), ghosts_begin, surface_pair);
        add_cached_pairs<false, Surfaces>(end_a, sum_a, copy, ghosts_begin, neighbours.end(a), surface_pair);
      }
    } else {
      const int ghosts_begin = neighbours.ghosts_begin(a);
      add_pairs<true, Surfaces>(end_a, sum_a, copy, neighbours.begin(a), ghosts_begin);  // owned neighbours
      add_pairs<false, Surfaces>(end_a, sum_a, copy, ghosts_begin, neighbours.end(a));   // ghosts
    }
    if (takes_end(end_a.kind)) add_sums(copy, a, sum_a);
    sums.release(copy);
  }
};

// After the pair loop: the sums into the particles' rates, the body force on
// fluid particles, none on boundary particles, and what each term makes of
// its own sums (the wall drag, the particle-shifting displacement).
template <int Dim, class ExecSpace, class... Terms>
struct FinishPairRates : Terms... {
  using Sums = PairRateSums<Dim, 1 + Dim + (Terms::components + ... + 0)>;
  template <class Term>
  static constexpr int offset_of = pair_detail::OffsetOf<Dim, Term, Terms...>::value;
  Particles<Dim, typename ExecSpace::memory_space> P;
  PairSums<Dim, ExecSpace> sums;
  Vec<Dim> body_force;
  bool wall_continuity;
  // A boundary particle's dv/dt is its reaction sum (PairDriver::add_reaction).
  static constexpr bool WithReactions = (Terms::reactions || ...);

  FinishPairRates(const PairTermInputs<Dim, ExecSpace>& in, const PairSums<Dim, ExecSpace>& pair_sums,
                  const Vec<Dim>& force)
      : Terms(in)...,
        P(in.particles),
        sums(pair_sums),
        body_force(force),
        wall_continuity(in.options.wall_continuity) {}

  KOKKOS_INLINE_FUNCTION void operator()(int a) const {
    const bool a_is_fluid = P.kind(a) == kFluid;
    const double drhodt = sums.take(a, Sums::density);
    P.drhodt(a) = a_is_fluid || wall_continuity ? drhodt : 0.0;
    for (int d = 0; d < Dim; ++d) {
      const double pairs = sums.take(a, Sums::acceleration_begin + d);
      P.dvdt(a, d) = a_is_fluid ? pairs + body_force[d] : WithReactions ? pairs : 0.0;
    }
    (static_cast<const Terms&>(*this).finish(P, a, a_is_fluid, TermTotals<Dim, ExecSpace>{sums, a, offset_of<Terms>}), ...);
  }
};

}  // namespace poresph
