#pragma once
// The Morris et al. (1997) viscous term between fluid particles; a boundary
// neighbour's share is the no-slip term's (physics/terms/NoSlipTerm.hpp).
#include "physics/PairDriver.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
struct ViscousTerm : PairTermBase {
  static constexpr const char* name = "viscous";
  static constexpr bool optional = false;
  double kinematic_viscosity;

  struct Shared {
    double weight;  // nu (1/rho_a + 1/rho_b) F, the same from either end
  };

  explicit ViscousTerm(const PairTermInputs<Dim, ExecSpace>& in) : kinematic_viscosity(in.fluid.kinematic_viscosity) {}

  KOKKOS_FORCEINLINE_FUNCTION Shared shared(const PairEnd<Dim>& a, const PairEnd<Dim>& b, const Vec<Dim>&,
                                            const Vec<Dim>&, double F) const {
    return {viscous_weight(kinematic_viscosity, a.inverse_density, b.inverse_density, F)};
  }
  // viscous_acceleration with the pair's weight formed once.
  template <int Own, class Sums>
  KOKKOS_FORCEINLINE_FUNCTION void add_to_end(const PairEnd<Dim>&, const PairEnd<Dim>& other, const EndGeometry<Dim>&,
                                              const SeenVelocity<Dim>& seen, const Shared& pair, Sums&,
                                              Vec<Dim>& acceleration) const {
    if (other.kind != kFluid) return;
    acceleration += (other.m * pair.weight) * seen.v;
  }
  KOKKOS_FORCEINLINE_FUNCTION void add_to_fluid_pair(const PairEnd<Dim>& a, const PairEnd<Dim>& b, const Vec<Dim>&,
                                                     const Vec<Dim>&, double F, FluidPairWeights& w) const {
    const double viscous = viscous_weight(kinematic_viscosity, a.inverse_density, b.inverse_density, F);
    w.v_a += b.m * viscous;
    w.v_b += -(a.m * viscous);
  }
};

}  // namespace poresph
