#pragma once
// The pair terms PoreSPH has, and the pair loop a scene runs: the driver
// (physics/PairDriver.hpp) compiled with the core terms and the optional
// terms the scene asks for, each combination its own kernel, so that a
// scene pays only for what it uses.
//
// A new term is one file in physics/terms/ and one entry in
// CorePairTerms, OptionalPairTerms or ReplacingPairTerms below (docs/code.md).
#include <Kokkos_Core.hpp>

#include <stdexcept>
#include <string>
#include <type_traits>

#include "core/Kernel.hpp"
#include "core/NeighbourList.hpp"
#include "core/PairSums.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"
#include "physics/NoSlip.hpp"
#include "physics/PairDriver.hpp"
#include "physics/terms/ContinuityTerm.hpp"
#include "physics/terms/ConvectionTerm.hpp"
#include "physics/terms/NoSlipTerm.hpp"
#include "physics/terms/PhaseViscousTerm.hpp"
#include "physics/terms/PressureTerm.hpp"
#include "physics/terms/ShiftingTerm.hpp"
#include "physics/terms/SurfaceReactionTerm.hpp"
#include "physics/terms/TurningWallTerm.hpp"
#include "physics/terms/ViscousTerm.hpp"

namespace poresph {

// Terms of every pair of every scene, in the order their accelerations are summed.
template <int Dim, class ExecSpace>
using CorePairTerms =
    PairTermList<ContinuityTerm<Dim, ExecSpace>, PressureTerm<Dim, ExecSpace>, ViscousTerm<Dim, ExecSpace>>;

// Terms a scene may ask for (each says when, through wanted()), after the
// core ones in this order. Every combination whose terms agree on the
// particles' motion is compiled.
template <int Dim, class ExecSpace>
using OptionalPairTerms =
    PairTermList<NoSlipTerm<Dim, ExecSpace>, TurningWallTerm<Dim, ExecSpace>, ConvectionTerm<Dim, ExecSpace>,
                 ShiftingTerm<Dim, ExecSpace>, SurfaceReactionTerm<Dim, ExecSpace>>;

// Terms that take the place of another of the lists above (Replaces) where
// a scene wants them: in the list's order, each only where all before it
// replace too, so that a chain (two fluids' viscosity, then their walls')
// adds one set of kernels per replacement, not one per subset of them.
// Elsewhere no kernel changes.
template <int Dim, class ExecSpace>
using ReplacingPairTerms = PairTermList<PhaseViscousTerm<Dim, ExecSpace>, PhaseNoSlipTerm<Dim, ExecSpace>>;

// Terms whose accelerations depend on the fluid's velocities: with the
// scene's replacements and those it wants of the optional ones, the
// velocity block of the steady solver (the change of dv/dt for a change of
// the velocities), a pair loop without continuity and the pressure term,
// which add no velocity-dependent acceleration. A new term that adds one
// belongs here too (SteadySolverTest.ProductsOfOneTermAreTheJacobiansBlocks
// compares the block with the whole rates' products).
template <int Dim, class ExecSpace>
using VelocityCorePairTerms = PairTermList<ViscousTerm<Dim, ExecSpace>>;
template <int Dim, class ExecSpace>
using VelocityOptionalPairTerms = PairTermList<NoSlipTerm<Dim, ExecSpace>, ConvectionTerm<Dim, ExecSpace>>;

namespace pair_detail {

// List with New in the place of New::Replaces (unchanged if not there).
template <class List, class New>
struct Replaced;
template <class... Terms, class New>
struct Replaced<PairTermList<Terms...>, New> {
  using type =
      PairTermList<std::conditional_t<std::is_same_v<Terms, typename New::Replaces>, New, Terms>...>;
};

// Calls f(PairTermList<chosen...>{}) with the terms of Chosen and those of
// Optional that the inputs want; a wanted term whose motion disagrees with
// the ones chosen is an error of the caller's options.
template <class Chosen, class Optional>
struct ChooseTerms;
template <class... Chosen>
struct ChooseTerms<PairTermList<Chosen...>, PairTermList<>> {
  template <class Inputs, class F>
  static void run(const Inputs&, F&& f) {
    f(PairTermList<Chosen...>{});
  }
};
template <class... Chosen, class Next, class... Rest>
struct ChooseTerms<PairTermList<Chosen...>, PairTermList<Next, Rest...>> {
  template <class Inputs, class F>
  static void run(const Inputs& in, F&& f) {
    if (Next::wanted(in)) {
      if constexpr (motions_agree<Chosen..., Next>())
        return ChooseTerms<PairTermList<Chosen..., Next>, PairTermList<Rest...>>::run(in, f);
      else
        throw std::logic_error(std::string("pair term ") + Next::name +
                               " applies to particles that move otherwise than those of the terms chosen before it");
    }
    ChooseTerms<PairTermList<Chosen...>, PairTermList<Rest...>>::run(in, f);
  }
};

// ChooseTerms over Core and Optional with the replacements of Replacing
// that the inputs want made, up to the first one they do not.
template <class Core, class Optional, class Replacing>
struct ChooseReplacements;
template <class Core, class Optional>
struct ChooseReplacements<Core, Optional, PairTermList<>> {
  template <class Inputs, class F>
  static void run(const Inputs& in, F&& f) {
    ChooseTerms<Core, Optional>::run(in, f);
  }
};
template <class Core, class Optional, class Next, class... Rest>
struct ChooseReplacements<Core, Optional, PairTermList<Next, Rest...>> {
  template <class Inputs, class F>
  static void run(const Inputs& in, F&& f) {
    if (!Next::wanted(in)) return ChooseTerms<Core, Optional>::run(in, f);
    ChooseReplacements<typename Replaced<Core, Next>::type, typename Replaced<Optional, Next>::type,
                       PairTermList<Rest...>>::run(in, f);
  }
};

template <int Dim, class ExecSpace, class... Terms>
constexpr int sums_of(PairTermList<Terms...>) {
  return PairDriver<Dim, ExecSpace, Terms...>::Sums::count;
}

template <int Dim, class ExecSpace, class F>
void with_scene_terms(const PairTermInputs<Dim, ExecSpace>& in, F&& f) {
  ChooseReplacements<CorePairTerms<Dim, ExecSpace>, OptionalPairTerms<Dim, ExecSpace>,
                     ReplacingPairTerms<Dim, ExecSpace>>::run(in, f);
}

}  // namespace pair_detail

// How many sums per particle the scene's pair loop needs (the size of its PairSums).
template <int Dim, class ExecSpace>
int pair_sum_components(const Particles<Dim, typename ExecSpace::memory_space>& P, const PairLoopOptions& options) {
  const FluidProperties fluid{};
  const NoSlipFactors<Dim, ExecSpace> no_slip;
  int components = 0;
  pair_detail::with_scene_terms<Dim, ExecSpace>(
      {P, fluid, options, no_slip, false}, [&](auto terms) { components = pair_detail::sums_of<Dim, ExecSpace>(terms); });
  return components;
}

// The pair loop of one list of terms, and its finish.
template <int Dim, class ExecSpace, class... Terms>
void run_pair_loop(const Kokkos::RangePolicy<ExecSpace>& policy, const PairTermInputs<Dim, ExecSpace>& inputs,
                   const NeighbourList<Dim, ExecSpace>& neighbours, const PairSums<Dim, ExecSpace>& sums,
                   const QuinticKernel<Dim>& kernel, PairTermList<Terms...>) {
  using Driver = PairDriver<Dim, ExecSpace, Terms...>;
  static const std::string label = Driver::label();
  Kokkos::parallel_for(label, policy, Driver(inputs, neighbours, sums, kernel));
}
template <int Dim, class ExecSpace, class... Terms>
void run_pair_finish(const Kokkos::RangePolicy<ExecSpace>& policy, const PairTermInputs<Dim, ExecSpace>& inputs,
                     const PairSums<Dim, ExecSpace>& sums, const Vec<Dim>& body_force, PairTermList<Terms...>) {
  static const std::string label = "poresph::FinishRates";
  Kokkos::parallel_for(label, policy, FinishPairRates<Dim, ExecSpace, Terms...>(inputs, sums, body_force));
}

// The pair loop: the sums of every pair term over the neighbours of all
// owned particles, into `sums`, which must hold pair_sum_components(P,
// options) components for every owned particle; ghosts and the neighbour
// list must be up to date. With the sums' first copy in the rates, those
// rates are zeroed first (the finish writes them).
template <int Dim, class ExecSpace>
void sum_pair_rates(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                    const NeighbourList<Dim, ExecSpace>& neighbours, const PairSums<Dim, ExecSpace>& sums,
                    const QuinticKernel<Dim>& kernel, const FluidProperties& fluid, const PairLoopOptions& options,
                    const NoSlipFactors<Dim, ExecSpace>& no_slip) {
  const auto policy = Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned);
  const PairTermInputs<Dim, ExecSpace> inputs{P, fluid, options, no_slip, neighbours.has_geometry()};
  const auto into = sums.with_rates(P);
  pair_detail::with_scene_terms<Dim, ExecSpace>(inputs, [&](auto terms) {
    into.clear_rates(space, P.owned, pair_detail::sums_of<Dim, ExecSpace>(terms));
    run_pair_loop(policy, inputs, neighbours, into, kernel, terms);
  });
}

// After sum_pair_rates with the same arguments: the particles' rates from
// the sums (which are left zero), the body force, each term's own finish.
template <int Dim, class ExecSpace>
void finish_pair_rates(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                       const NeighbourList<Dim, ExecSpace>& neighbours, const PairSums<Dim, ExecSpace>& sums,
                       const FluidProperties& fluid, const Vec<Dim>& body_force, const PairLoopOptions& options,
                       const NoSlipFactors<Dim, ExecSpace>& no_slip) {
  const auto policy = Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned);
  const PairTermInputs<Dim, ExecSpace> inputs{P, fluid, options, no_slip, neighbours.has_geometry()};
  const auto from = sums.with_rates(P);
  pair_detail::with_scene_terms<Dim, ExecSpace>(
      inputs, [&](auto terms) { run_pair_finish(policy, inputs, from, body_force, terms); });
}

// The rates of one list of terms only, not the scene's: the steady
// solver's preconditioner products (solver/SteadySolver.hpp) take the
// pressure gradient or the continuity alone, a pair loop a fraction of the
// scene's. The list holds no term that brings surfaces: every row takes the
// loop without them, and a boundary particle is an end like a fluid one,
// which the pressure and continuity terms of a fluid particle do not tell
// apart; the rows of boundary particles are then not their rates.
template <int Dim, class ExecSpace, class... Terms>
void compute_pair_rates_of(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                           const NeighbourList<Dim, ExecSpace>& neighbours, const PairSums<Dim, ExecSpace>& sums,
                           const QuinticKernel<Dim>& kernel, const FluidProperties& fluid, const Vec<Dim>& body_force,
                           const PairLoopOptions& options, const NoSlipFactors<Dim, ExecSpace>& no_slip,
                           PairTermList<Terms...> terms) {
  static_assert(!(Terms::surfaces || ...), "a partial pair loop treats boundary particles as fluid ones");
  const auto policy = Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned);
  const PairTermInputs<Dim, ExecSpace> inputs{P, fluid, options, no_slip, neighbours.has_geometry()};
  const auto into = sums.with_rates(P);
  into.clear_rates(space, P.owned, pair_detail::sums_of<Dim, ExecSpace>(terms));
  run_pair_loop(policy, inputs, neighbours, into, kernel, terms);
  run_pair_finish(policy, inputs, into, body_force, terms);
}

// The rates of the velocity block's terms alone (VelocityCorePairTerms and
// those of VelocityOptionalPairTerms the scene wants, with its
// replacements): the accelerations and wall drags of fluid particles. Their
// d rho/dt, and the rows of boundary particles, are not the state's.
template <int Dim, class ExecSpace>
void compute_velocity_rates(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                            const NeighbourList<Dim, ExecSpace>& neighbours, const PairSums<Dim, ExecSpace>& sums,
                            const QuinticKernel<Dim>& kernel, const FluidProperties& fluid, const Vec<Dim>& body_force,
                            const PairLoopOptions& options, const NoSlipFactors<Dim, ExecSpace>& no_slip) {
  const auto policy = Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned);
  const PairTermInputs<Dim, ExecSpace> inputs{P, fluid, options, no_slip, neighbours.has_geometry()};
  const auto into = sums.with_rates(P);
  pair_detail::ChooseReplacements<VelocityCorePairTerms<Dim, ExecSpace>, VelocityOptionalPairTerms<Dim, ExecSpace>,
                                  ReplacingPairTerms<Dim, ExecSpace>>::run(inputs, [&](auto terms) {
    into.clear_rates(space, P.owned, pair_detail::sums_of<Dim, ExecSpace>(terms));
    run_pair_loop(policy, inputs, neighbours, into, kernel, terms);
    run_pair_finish(policy, inputs, into, body_force, terms);
  });
}

// The fluid's force on each owned boundary particle a: on_force(a, F)
// inside the kernel, F its force (a Vec<Dim>). The pair loop with
// PairLoopOptions::surface_reactions (the term physics/terms/
// SurfaceReactionTerm.hpp), whose boundary ends then hold the reactions to
// what the fluid gains from them (PairDriver::add_reaction), times their
// mass: the same terms as the rates of sum_pair_rates with the same
// arguments, so that the fluid's momentum change from its surfaces and the
// surfaces' force add to zero to round-off. No array a particle: the
// caller sums what it needs. Only the boundary ends take their pairs
// (PairLoopOptions::fluid_ends): the fluid particles' rates are left as
// they were, also where they are the sums' first copy, whose boundary
// particles' part must then be zero, as a finish without wall continuity
// or reactions leaves it (app/Simulation.cpp); the sums are left zero.
template <int Dim, class ExecSpace, class OnForce>
void compute_surface_forces(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                            const NeighbourList<Dim, ExecSpace>& neighbours, const PairSums<Dim, ExecSpace>& sums,
                            const QuinticKernel<Dim>& kernel, const FluidProperties& fluid,
                            const PairLoopOptions& options, const NoSlipFactors<Dim, ExecSpace>& no_slip,
                            const OnForce& on_force) {
  FluidProperties whole_drag = fluid;
  whole_drag.separate_wall_drag = false;  // the reaction takes the whole viscous pull
  PairLoopOptions reactions = options;
  reactions.surface_reactions = true;
  reactions.fluid_ends = false;
  const auto policy = Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned);
  const PairTermInputs<Dim, ExecSpace> inputs{P, whole_drag, reactions, no_slip, neighbours.has_geometry()};
  pair_detail::with_scene_terms<Dim, ExecSpace>(inputs, [&](auto terms) {
    const auto totals = sums.with_rates(P);
    run_pair_loop(policy, inputs, neighbours, totals, kernel, terms);
    constexpr int count = pair_detail::sums_of<Dim, ExecSpace>(decltype(terms){});
    using Sums = PairRateSums<Dim, 1>;
    const auto Q = P;
    static const std::string label = "poresph::surface_forces";
    Kokkos::parallel_for(
        label, policy, KOKKOS_LAMBDA(int a) {
          if (Q.kind(a) == kFluid) return;  // added nothing (fluid_ends)
          Vec<Dim> F;
          for (int c = 0; c < count; ++c) {
            const double total = totals.take(a, c);  // taken always: the copies return to zero
            const int d = c - Sums::acceleration_begin;
            if (d >= 0 && d < Dim) F[d] = Q.m(a) * total;
          }
          on_force(a, F);
        });
  });
}

// Both: the rates of all owned particles.
template <int Dim, class ExecSpace>
void compute_pair_rates(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                        const NeighbourList<Dim, ExecSpace>& neighbours, const PairSums<Dim, ExecSpace>& sums,
                        const QuinticKernel<Dim>& kernel, const FluidProperties& fluid, const Vec<Dim>& body_force,
                        const PairLoopOptions& options = {}, const NoSlipFactors<Dim, ExecSpace>& no_slip = {}) {
  sum_pair_rates(space, P, neighbours, sums, kernel, fluid, options, no_slip);
  finish_pair_rates(space, P, neighbours, sums, fluid, body_force, options, no_slip);
}

}  // namespace poresph
