#pragma once
// The fluid's force on the surfaces (PairLoopOptions::surface_reactions):
// with this term in the list, the driver gives a boundary particle's end of
// each pair with a fluid particle the reaction to what the fluid gains from
// it (PairDriver::add_reaction), so that m_B dv_B/dt is the fluid's force on
// it. It adds nothing of its own; a loop without it (the time loop of a
// scene whose surfaces hold still) has no reaction code at all.
#include "physics/PairDriver.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
struct SurfaceReactionTerm : PairTermBase {
  static constexpr const char* name = "surface_reactions";
  static constexpr bool reactions = true;
  explicit SurfaceReactionTerm(const PairTermInputs<Dim, ExecSpace>&) {}
  static bool wanted(const PairTermInputs<Dim, ExecSpace>& in) {
    return in.options.surface_reactions && in.particles.has_surfaces;
  }
  template <int Own, class Sums>
  KOKKOS_FORCEINLINE_FUNCTION void add_to_end(const PairEnd<Dim>&, const PairEnd<Dim>&, const EndGeometry<Dim>&,
                                              const SeenVelocity<Dim>&, const Shared&, Sums&, Vec<Dim>&) const {}
};

}  // namespace poresph
