#pragma once
// The fluid's force on the solid, surface by surface: on each grain its
// force and its torque about its centre, on the plane walls and on an
// image's solid their totals. Each boundary particle's force is the
// reaction to what the fluid gains from it in the pair loop
// (Simulation::surface_loads), so that the loads and the fluid's momentum
// change from its surfaces add to zero to round-off; at a steady state the
// loads hold up the body force on the fluid (body_force_on_fluid).
#include <Kokkos_Core.hpp>
#include <array>
#include <vector>

#include "core/Vec.hpp"

namespace poresph {

template <int Dim>
struct SurfaceLoads {
  using Force = std::array<double, Dim>;
  using Torque = std::array<double, spin_components<Dim>()>;  // about the axis out of the plane in 2D
  std::vector<Force> grain_force;  // by the scene's grain index
  std::vector<Torque> grain_torque;
  Force walls{}, image{};
  Force body_force_on_fluid{};  // the fluid's mass times the body force

  // Over every surface.
  Force total() const {
    Force sum{};
    for (int d = 0; d < Dim; ++d) {
      for (const Force &f : grain_force) sum[d] += f[d];
      sum[d] += walls[d] + image[d];
    }
    return sum;
  }
};

}  // namespace poresph
