#pragma once
// No-slip surfaces through boundary particles (Morris et al. 1997,
// physics/NoSlip.hpp): a fluid particle sees a boundary neighbour move with
// the fluid's velocity relative to the wall continued linearly into the
// solid, v_aB = (1 + d_B/d_a)(v_a - u_w), in the viscous and convective
// terms; this term sets that velocity and adds the viscous share. With
// FluidProperties::separate_wall_drag (fixed particles) that share,
// -kappa (v_a - u_w), is split into kappa, summed as the particle's
// wall_drag and integrated exactly by the step (physics/PredictorCorrector.hpp),
// and the wall's kappa u_w, a rate like the others.
#include "physics/NoSlip.hpp"
#include "physics/PairDriver.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
struct NoSlipTerm : PairTermBase {
  static constexpr const char* name = "no_slip";
  static constexpr int components = 1;  // the wall drag kappa
  static constexpr bool surfaces = true;
  Particles<Dim, typename ExecSpace::memory_space> P;
  NoSlipFactors<Dim, ExecSpace> no_slip;  // per fluid-boundary list entry, when cached_no_slip
  bool cached_no_slip;
  double kinematic_viscosity, min_surface_distance;
  bool separate_wall_drag;

  explicit NoSlipTerm(const PairTermInputs<Dim, ExecSpace>& in)
      : P(in.particles),
        no_slip(in.no_slip),
        cached_no_slip(in.cached && in.no_slip.built()),
        kinematic_viscosity(in.fluid.kinematic_viscosity),
        min_surface_distance(in.fluid.min_surface_distance),
        separate_wall_drag(in.fluid.separate_wall_drag) {}
  static bool wanted(const PairTermInputs<Dim, ExecSpace>& in) { return in.particles.has_surfaces; }

  KOKKOS_FORCEINLINE_FUNCTION bool row_touches_surface(int a) const {
    return !cached_no_slip || no_slip.touches_surface(a);
  }
  // Where row a's fluid-boundary pairs begin in the cache (-1: no cache).
  KOKKOS_FORCEINLINE_FUNCTION int row_first_surface_pair(int a) const {
    return cached_no_slip ? no_slip.row_first(a) : -1;
  }

  // The factor 1 + d_B / d_a, from the cache of fixed particles (entry: the
  // pair's place among the cached fluid-boundary pairs) or computed.
  KOKKOS_FORCEINLINE_FUNCTION void see(const PairEnd<Dim>& self, const PairEnd<Dim>& other, const EndGeometry<Dim>& g,
                                       int entry, SeenVelocity<Dim>& seen) const {
    if (other.kind == kFluid) return;
    seen.factor = cached_no_slip && entry >= 0
                      ? no_slip.factor(entry)
                      : no_slip_factor_seen(P, self.index, other.index, other.kind, g.r, min_surface_distance);
    seen.v = seen.factor * g.v;
  }

  struct Shared {
    double viscous_weight;  // nu (1/rho_a + 1/rho_b) F, the same from either end
  };
  KOKKOS_FORCEINLINE_FUNCTION Shared shared(const PairEnd<Dim>& a, const PairEnd<Dim>& b, const Vec<Dim>&,
                                            const Vec<Dim>&, double F) const {
    return {viscous_weight(kinematic_viscosity, a.inverse_density, b.inverse_density, F)};
  }

  // The viscous term of a boundary neighbour, at the velocity seen.
  template <int Own, class Sums>
  KOKKOS_FORCEINLINE_FUNCTION void add_to_end(const PairEnd<Dim>&, const PairEnd<Dim>& other, const EndGeometry<Dim>&,
                                              const SeenVelocity<Dim>& seen, const Shared& pair, Sums& sum,
                                              Vec<Dim>& acceleration) const {
    if (other.kind == kFluid) return;
    if (separate_wall_drag) {
      // other.m viscous factor (v_self - v_other) = -kappa (v_self - v_other)
      const double kappa = -other.m * pair.viscous_weight * seen.factor;
      sum.value[Own] += kappa;  // the wall drag
      acceleration += kappa * other.v;
    } else {
      acceleration += (other.m * pair.viscous_weight) * seen.v;
    }
  }

  template <class Particles, class Totals>
  KOKKOS_FORCEINLINE_FUNCTION void finish(const Particles& Q, int a, bool a_is_fluid, const Totals& totals) const {
    const double drag = totals.take(0);  // taken always: the copies return to zero
    Q.wall_drag(a) = a_is_fluid ? drag : 0.0;
  }
};

}  // namespace poresph
