#pragma once
// The no-slip of a turning grain (moving particles, grains that move):
// what a fluid particle a sees of a boundary particle B is the fluid's
// velocity relative to the grain's rigid motion continued into the solid,
// plus the rigid motion itself,
//   v_aB = (1 + d_B/d_a)(v_a - u(x_a)) + u(x_a) - u(x_B),
// u(x_a) - u(x_B) = omega x r_aB, where NoSlipTerm, before it in the list,
// continues v_a - u(x_B) as for a wall that does not turn: this term takes
// (1 + d_B/d_a - 1) omega x r_aB off what that one set. Without it a grain
// turning with the fluid around it as one body would be seen to slip
// (test_rigid_grains, TurningWithTheFluidAsOneBodyTakesNoTorque). Compiled
// only into the loops of grains that move: every other scene's loop is as
// it was.
#include "core/Vec.hpp"
#include "physics/NoSlip.hpp"
#include "physics/PairDriver.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
struct TurningWallTerm : PairTermBase {
  static constexpr const char* name = "turning_wall";
  static constexpr TermMotion motion = TermMotion::Moving;
  Particles<Dim, typename ExecSpace::memory_space> P;
  NoSlipFactors<Dim, ExecSpace> no_slip;  // holds the grains' spins

  explicit TurningWallTerm(const PairTermInputs<Dim, ExecSpace>& in) : P(in.particles), no_slip(in.no_slip) {}
  static bool wanted(const PairTermInputs<Dim, ExecSpace>& in) {
    return in.particles.has_surfaces && in.no_slip.grains_turn();
  }

  KOKKOS_FORCEINLINE_FUNCTION void see(const PairEnd<Dim>&, const PairEnd<Dim>& other, const EndGeometry<Dim>& g, int,
                                       SeenVelocity<Dim>& seen) const {
    if (other.kind != kGrainBoundary) return;
    double turn[Dim];
    spin_cross<Dim>(no_slip.grain_spin(P.grain(other.index)), g.r.c, turn);
    for (int d = 0; d < Dim; ++d) seen.v[d] -= (seen.factor - 1.0) * turn[d];
  }

  template <int Own, class Sums>
  KOKKOS_FORCEINLINE_FUNCTION void add_to_end(const PairEnd<Dim>&, const PairEnd<Dim>&, const EndGeometry<Dim>&,
                                              const SeenVelocity<Dim>&, const Shared&, Sums&, Vec<Dim>&) const {}
};

}  // namespace poresph
