#pragma once
// The convective acceleration -(v_a . grad) v of fixed particles, whose
// velocity is that of the flow through their point (Eulerian SPH,
// docs/method.md): -sum_b V_b (v_b - v_a)(v_a . grad_a W_ab). A boundary
// neighbour's velocity continues the flow linearly into the solid (the
// velocity seen through the no-slip term).
#include "physics/PairDriver.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
struct ConvectionTerm : PairTermBase {
  static constexpr const char* name = "convection";
  static constexpr TermMotion motion = TermMotion::Fixed;

  explicit ConvectionTerm(const PairTermInputs<Dim, ExecSpace>&) {}
  static bool wanted(const PairTermInputs<Dim, ExecSpace>& in) { return in.options.convection; }

  template <int Own, class Sums>
  KOKKOS_FORCEINLINE_FUNCTION void add_to_end(const PairEnd<Dim>& self, const PairEnd<Dim>& other,
                                              const EndGeometry<Dim>& g, const SeenVelocity<Dim>& seen, const Shared&,
                                              Sums&, Vec<Dim>& acceleration) const {
    acceleration += convective_acceleration(other.m * other.inverse_density, self.v, seen.v, g.r, g.F);
  }
  // a's weight of v_ab is V_b F (v_a . r_ab), b's V_a F (v_b . r_ab).
  KOKKOS_FORCEINLINE_FUNCTION void add_to_fluid_pair(const PairEnd<Dim>& a, const PairEnd<Dim>& b, const Vec<Dim>& r,
                                                     const Vec<Dim>&, double F, FluidPairWeights& w) const {
    w.v_a += convective_weight(b.m * b.inverse_density, a.v, r, F);
    w.v_b += convective_weight(a.m * a.inverse_density, b.v, r, F);
  }
};

}  // namespace poresph
