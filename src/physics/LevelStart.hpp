#pragma once
// A finer level of the resolution ladder starts from a coarser level's flow
// (app/Simulation.hpp, warm_start): the fluid's velocity and its pressure
// above rest, interpolated at the finer particles (GridInterpolation.hpp),
// and, where the coarser level kept its own start, continued by what that
// level changed of it (docs/method.md, "The resolution ladder").
#include <Kokkos_Core.hpp>

#include <string>

#include "core/Particles.hpp"

namespace poresph {

// What a finer level takes of one interpolated value: `now` (this level's
// end) plus `extrapolation` times its change from `start` (the start this
// level was given), all times `scale` (0.5: the same flow at half the force).
KOKKOS_INLINE_FUNCTION double continued_value(double now, double start, double extrapolation, double scale) {
  return scale * (now + extrapolation * (now - start));
}

// How a finer level takes the values.
struct LevelStartRule {
  double scale = 1;          // of what is taken
  double extrapolation = 0;  // 0: the interpolation alone
  double sound_speed_sq;     // the finer level's: its density from the pressure taken
  double density;            // rho0
};

// Sets the owned fluid particles of F from `values` (per particle: velocity
// (Dim), pressure above rest), continued by `start_values` (the same of the
// coarser level's own start; unread with extrapolation 0). The pressure
// carries over, not the density, whose sound speed differs between levels.
// If F keeps a level start, it keeps the plain part (scaled).
template <int Dim, class ExecSpace>
void take_level_start(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& F,
                      const Kokkos::View<double**, typename ExecSpace::memory_space>& values,
                      const Kokkos::View<double**, typename ExecSpace::memory_space>& start_values,
                      const LevelStartRule& rule) {
  const bool keep = F.has_level_start, continue_change = rule.extrapolation != 0;
  const auto v = F.v, rho = F.rho, v_start = F.v_level_start, p_start = F.p_level_start;
  const auto kind = F.kind;
  static const std::string label = "poresph::take_level_start";
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(space, 0, F.owned), KOKKOS_LAMBDA(int i) {
        if (kind(i) != kFluid) return;
        if (keep) {
          for (int d = 0; d < Dim; ++d) v_start(i, d) = rule.scale * values(i, d);
          p_start(i) = rule.sound_speed_sq * rule.density + rule.scale * values(i, Dim);
        }
        double taken[Dim + 1];
        for (int c = 0; c <= Dim; ++c) {
          const double now = values(i, c);  // no start read without a change to continue: it may be empty
          taken[c] = continued_value(now, continue_change ? start_values(i, c) : now, rule.extrapolation, rule.scale);
        }
        for (int d = 0; d < Dim; ++d) v(i, d) = taken[d];
        rho(i) = rule.density + taken[Dim] / rule.sound_speed_sq;
      });
}

}  // namespace poresph
