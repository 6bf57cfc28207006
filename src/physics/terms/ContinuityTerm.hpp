#pragma once
// The continuity equation, d rho_a/dt = sum_b m_b v_ab . grad_a W_ab: the
// density rate of fluid particles, and of boundary particles that integrate
// it (the paper; PairLoopOptions::wall_continuity).
#include "physics/PairDriver.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
struct ContinuityTerm : PairTermBase {
  static constexpr const char* name = "continuity";
  static constexpr bool optional = false;
  static constexpr bool at_boundary_ends = true;
  static constexpr bool adds_acceleration = false;

  struct Shared {
    double weight;  // F v_ab . r_ab, the same from either end
  };

  explicit ContinuityTerm(const PairTermInputs<Dim, ExecSpace>&) {}

  KOKKOS_FORCEINLINE_FUNCTION Shared shared(const PairEnd<Dim>&, const PairEnd<Dim>&, const Vec<Dim>& r,
                                            const Vec<Dim>& v, double F) const {
    return {continuity_weight(v, r, F)};
  }
  template <int Own, class Sums>
  KOKKOS_FORCEINLINE_FUNCTION void add_to_end(const PairEnd<Dim>&, const PairEnd<Dim>& other, const EndGeometry<Dim>&,
                                              const SeenVelocity<Dim>&, const Shared& pair, Sums& sum, Vec<Dim>&) const {
    sum.drho() += other.m * pair.weight;
  }
  KOKKOS_FORCEINLINE_FUNCTION void add_to_fluid_pair(const PairEnd<Dim>& a, const PairEnd<Dim>& b, const Vec<Dim>& r,
                                                     const Vec<Dim>& v, double F, FluidPairWeights& w) const {
    const double continuity = continuity_weight(v, r, F);
    w.drho_a += b.m * continuity;
    w.drho_b += a.m * continuity;
  }
};

}  // namespace poresph
