#pragma once
// The symmetric pressure term, -sum_b m_b (p_a/rho_a^2 + p_b/rho_b^2) grad_a W_ab.
#include "physics/PairDriver.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
struct PressureTerm : PairTermBase {
  static constexpr const char* name = "pressure";
  static constexpr bool optional = false;
  static constexpr bool adds_density = false;
  static constexpr bool reads_velocity = false;

  struct Shared {
    Vec<Dim> acceleration;  // per unit neighbour mass, as a sees it; b sees minus it
  };

  explicit PressureTerm(const PairTermInputs<Dim, ExecSpace>&) {}

  KOKKOS_FORCEINLINE_FUNCTION Shared shared(const PairEnd<Dim>& a, const PairEnd<Dim>& b, const Vec<Dim>& r,
                                            const Vec<Dim>&, double F) const {
    return {pressure_acceleration(1.0, a.pressure_term, b.pressure_term, r, F)};
  }
  template <int Own, class Sums>
  KOKKOS_FORCEINLINE_FUNCTION void add_to_end(const PairEnd<Dim>&, const PairEnd<Dim>& other,
                                              const EndGeometry<Dim>& g, const SeenVelocity<Dim>&, const Shared& pair,
                                              Sums&, Vec<Dim>& acceleration) const {
    acceleration += (other.m * g.sign) * pair.acceleration;
  }
  KOKKOS_FORCEINLINE_FUNCTION void add_to_fluid_pair(const PairEnd<Dim>& a, const PairEnd<Dim>& b, const Vec<Dim>&,
                                                     const Vec<Dim>&, double F, FluidPairWeights& w) const {
    const double pressure = pressure_weight(a.pressure_term, b.pressure_term, F);
    w.r_a += b.m * pressure;
    w.r_b += -(a.m * pressure);
  }
};

}  // namespace poresph
