#pragma once
// Predictor-corrector step of the paper: advance to the mid-point with the
// old rates, evaluate the interparticle forces there, then advance the whole
// step from the start with the mid-point rates. Boundary particles move with
// their surface's prescribed velocity and keep it.
#include <Kokkos_Core.hpp>

#include "core/Math.hpp"
#include "core/Particles.hpp"
#include "diagnostics/Health.hpp"

namespace poresph {

// v after a time tau of dv/dt = a - kappa v with a and kappa constant:
// v e^{-kappa tau} + a (1 - e^{-kappa tau}) / kappa, exact however large
// kappa tau is (the drag of a wall a hair away), and v + a tau at kappa = 0.
KOKKOS_INLINE_FUNCTION double velocity_after(double v, double a, double kappa, double tau) {
  if (!(kappa > 0)) return v + a * tau;
  return v * math::exp(-kappa * tau) - a * math::expm1(-kappa * tau) / kappa;
}

// move = false: fixed particles, whose positions never change (Eulerian SPH).
// wall_drag: the particles carry a drag coefficient kappa apart from their
// acceleration (physics/terms/NoSlipTerm.hpp, FluidProperties::separate_wall_drag),
// integrated exactly over each stage.
template <int Dim, class ExecSpace>
void predict_to_midpoint(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                         double dt, bool move = true, bool wall_drag = false) {
  const auto Q = P;
  const double half = 0.5 * dt;
  const bool drag = wall_drag && P.has_surfaces;
  static const std::string label_predict_to_midpoint = "poresph::predict_to_midpoint";
  Kokkos::parallel_for(
      label_predict_to_midpoint, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned), KOKKOS_LAMBDA(int i) {
        const bool fluid = Q.kind(i) == kFluid;
        const double kappa = drag ? Q.wall_drag(i) : 0.0;
        for (int d = 0; d < Dim; ++d) {
          if (move) {  // fixed particles keep their x: nothing to start from
            Q.x_start(i, d) = Q.x(i, d);
            Q.x(i, d) += half * Q.v(i, d);
          }
          Q.v_start(i, d) = Q.v(i, d);
          if (fluid) Q.v(i, d) = velocity_after(Q.v(i, d), Q.dvdt(i, d), kappa, half);
        }
        Q.rho_start(i) = Q.rho(i);
        Q.rho(i) += half * Q.drhodt(i);
      });
}

// With `health`, the corrector also counts the particles that its step left
// unhealthy (diagnostics/Health.hpp, the per-step check) as it writes them:
// one pass over the particles less than checking them afterwards. Returns
// that count (0 without `health`).
template <int Dim, class ExecSpace>
long long correct_full_step(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                            double dt, bool move = true, bool wall_drag = false, const HealthLimits* health = nullptr) {
  const auto Q = P;
  const bool drag = wall_drag && P.has_surfaces;
  const bool check = health != nullptr;
  const HealthLimits limits = check ? *health : HealthLimits{};
  long long unhealthy = 0;
  static const std::string label_correct_full_step = "poresph::correct_full_step";
  Kokkos::parallel_reduce(
      label_correct_full_step, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned),
      KOKKOS_LAMBDA(int i, long long& count) {
        const bool fluid = Q.kind(i) == kFluid;
        const double kappa = drag ? Q.wall_drag(i) : 0.0;
        double x[Dim], v[Dim], a[Dim];
        for (int d = 0; d < Dim; ++d) {
          const double v_start = Q.v_start(i, d);
          a[d] = Q.dvdt(i, d);
          v[d] = fluid ? velocity_after(v_start, a[d], kappa, dt) : v_start;
          Q.v(i, d) = v[d];
          // Trapezoidal positions: second order, and exact for boundary particles.
          if (move) Q.x(i, d) = Q.x_start(i, d) + 0.5 * dt * (v_start + v[d]);
          x[d] = check && move ? Q.x(i, d) : 0.0;  // fixed particles' x never changes
        }
        const double drhodt = Q.drhodt(i);
        const double rho = Q.rho_start(i) + dt * drhodt;
        Q.rho(i) = rho;
        if (check) count += healthy<Dim>(x, v, a, rho, drhodt, fluid, limits) ? 0 : 1;
      },
      unhealthy);
  return unhealthy;
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
