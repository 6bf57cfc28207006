#pragma once
// The solid is impermeable: grains, an image's solid and a channel's walls.
// The boundary particles' pressure keeps fluid out, but a stagnant fluid
// particle that starts on a grain surface (a lattice point a hair outside it)
// feels almost no push and can drift a fraction of a per cent of dx inside,
// and a moving one can be carried through the wall's layers where the fluid
// next to the wall rarefies. After each step such a particle is put back on
// the surface and loses its velocity into the solid; the count and the depth
// are reported, so the correction is visible, not hidden.
#include <Kokkos_Core.hpp>

#include "core/Math.hpp"
#include "core/Particles.hpp"
#include "geometry/Solid.hpp"

namespace poresph {

struct GrainPenetration {
  long long particles = 0;  // fluid particles found inside a grain
  double max_depth = 0;     // deepest of them below the surface
};

// Moves a penetrating particle to just outside the surface along the normal
// and removes the inward normal velocity.
template <int Dim>
KOKKOS_INLINE_FUNCTION void push_out_of_grain(double* x, double* v, const double* normal, double depth,
                                              double clearance) {
  double inward = 0;
  for (int d = 0; d < Dim; ++d) {
    x[d] += (depth + clearance) * normal[d];
    inward += v[d] * normal[d];
  }
  if (inward < 0)
    for (int d = 0; d < Dim; ++d) v[d] -= inward * normal[d];
}

// Counts owned fluid particles inside the solid (grains or image); with
// `correct`, also pushes them out.
template <int Dim, class ExecSpace>
GrainPenetration fluid_in_grains(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                                 const SolidMap<Dim, typename ExecSpace::memory_space>& map, bool correct,
                                 double clearance) {
  GrainPenetration result;
  if (map.empty()) return result;
  const auto Q = P;
  static const std::string label_keep = "poresph::keep_fluid_outside_grains";
  static const std::string label_count = "poresph::count_fluid_inside_grains";
  Kokkos::parallel_reduce(
      correct ? label_keep : label_count,
      Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned),
      KOKKOS_LAMBDA(int i, long long& count, double& deepest) {
        if (Q.kind(i) != kFluid) return;
        double x[Dim], normal[Dim], depth;
        for (int d = 0; d < Dim; ++d) x[d] = Q.x(i, d);
        if (map.deepest(x, depth, normal) < 0) return;
        ++count;
        if (depth > deepest) deepest = depth;
        if (!correct) return;
        double v[Dim];
        for (int d = 0; d < Dim; ++d) v[d] = Q.v(i, d);
        push_out_of_grain<Dim>(x, v, normal, depth, clearance);
        for (int d = 0; d < Dim; ++d) Q.x(i, d) = x[d], Q.v(i, d) = v[d];
      },
      result.particles, Kokkos::Max<double>(result.max_depth));
  if (result.particles == 0) result.max_depth = 0;  // the Max reducer starts at the lowest double
  return result;
}

}  // namespace poresph
