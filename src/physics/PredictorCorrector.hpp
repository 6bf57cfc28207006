#pragma once
// Predictor-corrector step of the paper: advance to the mid-point with the
// old rates, evaluate the interparticle forces there, then advance the whole
// step from the start with the mid-point rates. Boundary particles move with
// their surface's prescribed velocity and keep it.
#include <Kokkos_Core.hpp>

#include "core/Particles.hpp"

namespace poresph {

// move = false: fixed particles, whose positions never change (Eulerian SPH).
template <int Dim, class ExecSpace>
void predict_to_midpoint(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                         double dt, bool move = true) {
  const auto Q = P;
  const double half = 0.5 * dt;
  static const std::string label_predict_to_midpoint = "poresph::predict_to_midpoint";
  Kokkos::parallel_for(
      label_predict_to_midpoint, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned), KOKKOS_LAMBDA(int i) {
        const bool fluid = Q.kind(i) == kFluid;
        for (int d = 0; d < Dim; ++d) {
          Q.x_start(i, d) = Q.x(i, d);
          Q.v_start(i, d) = Q.v(i, d);
          if (move) Q.x(i, d) += half * Q.v(i, d);
          if (fluid) Q.v(i, d) += half * Q.dvdt(i, d);
        }
        Q.rho_start(i) = Q.rho(i);
        Q.rho(i) += half * Q.drhodt(i);
      });
}

template <int Dim, class ExecSpace>
void correct_full_step(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                       double dt, bool move = true) {
  const auto Q = P;
  static const std::string label_correct_full_step = "poresph::correct_full_step";
  Kokkos::parallel_for(
      label_correct_full_step, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned), KOKKOS_LAMBDA(int i) {
        const bool fluid = Q.kind(i) == kFluid;
        for (int d = 0; d < Dim; ++d) {
          const double v_start = Q.v_start(i, d);
          const double v_end = fluid ? v_start + dt * Q.dvdt(i, d) : v_start;
          Q.v(i, d) = v_end;
          // Trapezoidal positions: second order, and exact for boundary particles.
          if (move) Q.x(i, d) = Q.x_start(i, d) + 0.5 * dt * (v_start + v_end);
        }
        Q.rho(i) = Q.rho_start(i) + dt * Q.drhodt(i);
      });
}

}  // namespace poresph

namespace poresph {

// Applies the particle-shifting displacement computed with the mid-point
// rates, and the matching velocity change, after the corrector.
template <int Dim, class ExecSpace>
void apply_shifting(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P) {
  const auto Q = P;
  static const std::string label_apply_shifting = "poresph::apply_shifting";
  Kokkos::parallel_for(
      label_apply_shifting, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned), KOKKOS_LAMBDA(int i) {
        for (int d = 0; d < Dim; ++d) {
          Q.x(i, d) += Q.shift(i, d);
          Q.v(i, d) += Q.shift_velocity(i, d);
        }
      });
}

}  // namespace poresph
