#pragma once
// Two fluids on fixed particles (the Phases sublist, Particles::phase): the
// viscous term of each pair with each particle's own phase's viscosity, in
// place of the one-fluid ViscousTerm, and the no-slip share of a boundary
// neighbour with the viscosity of the fluid particle it meets, in place of
// NoSlipTerm's (a wall takes on the viscosity of the fluid that touches
// it, so that a phase at a wall feels its own viscosity there). Between
// two fluid particles the harmonic mean of their dynamic viscosities
// (physics/PairTerms.hpp, harmonic_phase_viscous_weight): it keeps the
// shear stress continuous across a layer interface, and was measured the
// better of it and the arithmetic mean on layered Poiseuille flow
// (docs/method.md). Compiled only into the loops of scenes with phases
// (ReplacingPairTerms, physics/PairRates.hpp): a one-fluid scene's loop is
// as it was.
#include "physics/PairDriver.hpp"
#include "physics/PairTerms.hpp"
#include "physics/terms/NoSlipTerm.hpp"
#include "physics/terms/ViscousTerm.hpp"

namespace poresph {

// A particle's phase's kinematic viscosity, read per pair end.
template <class ExecSpace>
struct PhaseViscosities {
  Kokkos::View<int*, typename ExecSpace::memory_space> phase;
  double nu[kMaxPhases];
  template <int Dim>
  explicit PhaseViscosities(const PairTermInputs<Dim, ExecSpace>& in) : phase(in.particles.phase) {
    for (int p = 0; p < kMaxPhases; ++p) nu[p] = in.fluid.phase_kinematic_viscosity[p];
  }
  KOKKOS_FORCEINLINE_FUNCTION double of(int i) const { return nu[phase(i)]; }
};

// The pair's weight (its Shared) is 2 mu_ab / (rho_a rho_b) F; what an end
// adds with it (add_to_end) is ViscousTerm's.
template <int Dim, class ExecSpace>
struct PhaseViscousTerm : ViscousTerm<Dim, ExecSpace> {
  static constexpr const char* name = "phase_viscous";
  static constexpr bool optional = true;                   // named in the loop's label
  static constexpr TermMotion motion = TermMotion::Fixed;  // a phase is set on the lattice, once
  using Replaces = ViscousTerm<Dim, ExecSpace>;
  using Shared = typename ViscousTerm<Dim, ExecSpace>::Shared;
  PhaseViscosities<ExecSpace> viscosity;

  explicit PhaseViscousTerm(const PairTermInputs<Dim, ExecSpace>& in)
      : ViscousTerm<Dim, ExecSpace>(in), viscosity(in) {}
  static bool wanted(const PairTermInputs<Dim, ExecSpace>& in) { return in.particles.has_phase; }

  KOKKOS_FORCEINLINE_FUNCTION double weight(const PairEnd<Dim>& a, const PairEnd<Dim>& b, double F) const {
    return harmonic_phase_viscous_weight(viscosity.of(a.index), viscosity.of(b.index), a.inverse_density,
                                         b.inverse_density, F);
  }
  KOKKOS_FORCEINLINE_FUNCTION Shared shared(const PairEnd<Dim>& a, const PairEnd<Dim>& b, const Vec<Dim>&,
                                            const Vec<Dim>&, double F) const {
    // Only a pair of fluid particles takes it (add_to_end); a boundary end's phase means nothing.
    return {a.kind == kFluid && b.kind == kFluid ? weight(a, b, F) : 0.0};
  }
  KOKKOS_FORCEINLINE_FUNCTION void add_to_fluid_pair(const PairEnd<Dim>& a, const PairEnd<Dim>& b, const Vec<Dim>&,
                                                     const Vec<Dim>&, double F, FluidPairWeights& w) const {
    const double viscous = weight(a, b, F);
    w.v_a += b.m * viscous;
    w.v_b += -(a.m * viscous);
  }
};

// NoSlipTerm with the viscosity of the pair's fluid end: its shared weight
// nu_a (1/rho_a + 1/rho_B) F; everything else is NoSlipTerm's.
template <int Dim, class ExecSpace>
struct PhaseNoSlipTerm : NoSlipTerm<Dim, ExecSpace> {
  using Replaces = NoSlipTerm<Dim, ExecSpace>;
  using Shared = typename NoSlipTerm<Dim, ExecSpace>::Shared;
  static constexpr TermMotion motion = TermMotion::Fixed;
  PhaseViscosities<ExecSpace> viscosity;

  explicit PhaseNoSlipTerm(const PairTermInputs<Dim, ExecSpace>& in)
      : NoSlipTerm<Dim, ExecSpace>(in), viscosity(in) {}
  static bool wanted(const PairTermInputs<Dim, ExecSpace>& in) {
    return in.particles.has_phase && NoSlipTerm<Dim, ExecSpace>::wanted(in);
  }

  KOKKOS_FORCEINLINE_FUNCTION Shared shared(const PairEnd<Dim>& a, const PairEnd<Dim>& b, const Vec<Dim>&,
                                            const Vec<Dim>&, double F) const {
    if (a.kind == kFluid && b.kind == kFluid) return {0.0};  // NoSlipTerm adds nothing between fluid particles
    const double nu = viscosity.of(a.kind == kFluid ? a.index : b.index);
    return {viscous_weight(nu, a.inverse_density, b.inverse_density, F)};
  }
};

}  // namespace poresph
