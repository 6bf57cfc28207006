#pragma once
// Particle shifting (Lind et al. 2012) of moving particles: the pairs sum
// the concentration gradient grad C and the velocity gradient grad v; after
// the loop a fluid particle's shift is dr = -A h |v| dt grad C, capped at a
// fraction of dx, and its velocity follows by dv = (grad v) dr
// (physics/PredictorCorrector.hpp applies both).
#include "core/Math.hpp"
#include "physics/PairDriver.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
struct ShiftingTerm : PairTermBase {
  static constexpr const char* name = "shifting";
  static constexpr TermMotion motion = TermMotion::Moving;
  // grad C, then grad v row-major (d v_i / d x_j)
  static constexpr int components = Dim + Dim * Dim;
  static constexpr bool fluid_pair_weights = false;  // its gradients are no weights of r and v at both ends
  ShiftingParameters shifting;

  explicit ShiftingTerm(const PairTermInputs<Dim, ExecSpace>& in) : shifting(in.options.shifting) {}
  static bool wanted(const PairTermInputs<Dim, ExecSpace>& in) {
    return in.particles.has_shifting && in.options.shifting.coefficient > 0;
  }

  template <int Own, class Sums>
  KOKKOS_FORCEINLINE_FUNCTION void add_to_end(const PairEnd<Dim>&, const PairEnd<Dim>& other, const EndGeometry<Dim>& g,
                                              const SeenVelocity<Dim>&, const Shared&, Sums& sum, Vec<Dim>&) const {
    const double volume_F = volume_gradient_weight(other.m * other.inverse_density, g.F);
    for (int i = 0; i < Dim; ++i) {
      sum.value[Own + i] += volume_F * g.r[i];  // grad C
      for (int j = 0; j < Dim; ++j) sum.value[Own + Dim + i * Dim + j] -= volume_F * g.v[i] * g.r[j];  // grad v
    }
  }

  template <class Particles, class Totals>
  KOKKOS_FORCEINLINE_FUNCTION void finish(const Particles& Q, int a, bool a_is_fluid, const Totals& totals) const {
    Vec<Dim> grad_concentration;
    double grad_velocity[Dim][Dim];
    for (int i = 0; i < Dim; ++i) {
      grad_concentration[i] = totals.take(i);
      for (int j = 0; j < Dim; ++j) grad_velocity[i][j] = totals.take(Dim + i * Dim + j);
    }
    Vec<Dim> shift = Vec<Dim>::zero(), dv = Vec<Dim>::zero();
    if (a_is_fluid) {
      const Vec<Dim> v_a = row<Dim>(Q.v, a);
      shift = (-shifting.coefficient * shifting.h_dt * math::sqrt(dot(v_a, v_a))) * grad_concentration;
      const double length = math::sqrt(dot(shift, shift));
      if (length > shifting.max_shift) shift = (shifting.max_shift / length) * shift;
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) dv[i] += grad_velocity[i][j] * shift[j];
    }
    set_row(Q.shift, a, shift);
    set_row(Q.shift_velocity, a, dv);
  }
};

}  // namespace poresph
