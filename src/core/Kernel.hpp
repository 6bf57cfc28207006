#pragma once
// Quintic spline kernel (Morris et al. 1997), support radius 3h.
//   W(r,h) = alpha_N f(r/h),  f(s) = (3-s)^5 - 6(2-s)^5 + 15(1-s)^5 with the
//   terms dropped beyond s = 1, 2, 3.
// alpha_N makes the integral of W over R^N equal 1; tests integrate it.
#include <Kokkos_Core.hpp>

#include "core/Math.hpp"

namespace poresph {

constexpr double kSupportRadiusInH = 3.0;

template <int Dim>
KOKKOS_INLINE_FUNCTION constexpr double quintic_normalisation(double h) {
  // 7/(478 pi) and 1/(120 pi): 2D and 3D normalisation; 1/120 in 1D.
  constexpr double pi = 3.14159265358979323846;
  if constexpr (Dim == 1) return 1.0 / (120.0 * h);
  else if constexpr (Dim == 2) return 7.0 / (478.0 * pi * h * h);
  else return 1.0 / (120.0 * pi * h * h * h);
}

// The terms are written with max(0, k - s) rather than branches on s: in
// the pair loop s is effectively random, and mispredicted branches cost more
// than the few extra multiplications. max(0, t) is computed as (t + |t|) / 2,
// which is exact (2t / 2, or 0) for the t here, because GCC 12 vectorises
// that and not `t > 0 ? t : 0`.
KOKKOS_INLINE_FUNCTION double positive_part(double t) { return 0.5 * (t + math::fabs(t)); }

// f(s) of the quintic spline.
KOKKOS_INLINE_FUNCTION double quintic_shape(double s) {
  const double t3 = positive_part(3.0 - s), t2 = positive_part(2.0 - s), t1 = positive_part(1.0 - s);
  const double q3 = t3 * t3, q2 = t2 * t2, q1 = t1 * t1;
  return q3 * q3 * t3 - 6.0 * q2 * q2 * t2 + 15.0 * q1 * q1 * t1;
}

// df/ds of the quintic spline (non-positive).
KOKKOS_INLINE_FUNCTION double quintic_shape_derivative(double s) {
  const double t3 = positive_part(3.0 - s), t2 = positive_part(2.0 - s), t1 = positive_part(1.0 - s);
  const double q3 = t3 * t3, q2 = t2 * t2, q1 = t1 * t1;
  return -5.0 * q3 * q3 + 30.0 * q2 * q2 - 75.0 * q1 * q1;
}

template <int Dim>
struct QuinticKernel {
  double h;
  double inv_h;
  double alpha;   // normalisation alpha_N(h)
  double cutoff;  // 3h
  double cutoff_sq;

  QuinticKernel() = default;
  explicit QuinticKernel(double smoothing_length)
      : h(smoothing_length),
        inv_h(1.0 / smoothing_length),
        alpha(quintic_normalisation<Dim>(smoothing_length)),
        cutoff(kSupportRadiusInH * smoothing_length),
        cutoff_sq(cutoff * cutoff) {}

  KOKKOS_INLINE_FUNCTION double value(double r) const { return alpha * quintic_shape(r * inv_h); }
  // dW/dr (non-positive).
  KOKKOS_INLINE_FUNCTION double derivative(double r) const {
    return alpha * inv_h * quintic_shape_derivative(r * inv_h);
  }
  // (1/r) dW/dr, the factor shared by grad W = r_vec (1/r) dW/dr and by
  // Morris's viscous term. Finite at r -> 0 is not needed: r > 0 for a != b.
  KOKKOS_INLINE_FUNCTION double derivative_over_r(double r) const { return derivative(r) / r; }
};

}  // namespace poresph
