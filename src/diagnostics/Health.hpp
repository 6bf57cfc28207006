#pragma once
// Is the state after a step still a solution? A NaN or Inf in a field, a
// fluid density beyond the allowed variation, or a particle that outruns the
// time step's CFL limits (moves more than h/4 in a step, or accelerates
// faster than dt <= 0.25 sqrt(h/|a|) allows) means it is not; the run stops
// naming the particle rather than writing numbers that mean nothing.
#include <Kokkos_Core.hpp>

#include "core/Math.hpp"
#include "core/Particles.hpp"

namespace poresph {

enum HealthCause { kNonFinite = 0, kDensityVariation = 1, kSpeedLimit = 2, kAccelerationLimit = 3 };
constexpr int kHealthCauses = 4;
constexpr const char* kHealthCauseNames[kHealthCauses] = {
    "a field is NaN or Inf", "the density variation exceeds Checks/Density Variation Limit",
    "the particle moves more than h/4 in a step (CFL limit)",
    "the acceleration exceeds the time step's limit dt <= 0.25 sqrt(h/|a|)"};

struct HealthLimits {
  double reference_density;
  double density_variation;
  double speed;         // h / (4 dt)
  double acceleration;  // h / (16 dt^2)
};

// Particles found with each cause (a particle counts once, for its first cause).
struct HealthCounts {
  long long count[kHealthCauses];
  KOKKOS_INLINE_FUNCTION HealthCounts() {
    for (int c = 0; c < kHealthCauses; ++c) count[c] = 0;
  }
  KOKKOS_INLINE_FUNCTION HealthCounts& operator+=(const HealthCounts& other) {
    for (int c = 0; c < kHealthCauses; ++c) count[c] += other.count[c];
    return *this;
  }
  // Kokkos 3's OpenMP backend joins partial results through volatile references.
  KOKKOS_INLINE_FUNCTION void operator+=(const volatile HealthCounts& other) volatile {
    for (int c = 0; c < kHealthCauses; ++c) count[c] += other.count[c];
  }
  long long total() const {
    long long n = 0;
    for (int c = 0; c < kHealthCauses; ++c) n += count[c];
    return n;
  }
};

KOKKOS_INLINE_FUNCTION bool is_finite(double value) { return value - value == 0.0; }  // false for NaN and Inf

// The first cause that applies to one particle, or -1.
template <int Dim>
KOKKOS_INLINE_FUNCTION int health_problem(const double* x, const double* v, const double* a, double rho,
                                          double drhodt, bool fluid, const HealthLimits& limits) {
  bool finite = is_finite(rho) && is_finite(drhodt);
  double speed_sq = 0, accel_sq = 0;
  for (int d = 0; d < Dim; ++d) {
    finite = finite && is_finite(x[d]) && is_finite(v[d]) && is_finite(a[d]);
    speed_sq += v[d] * v[d];
    accel_sq += a[d] * a[d];
  }
  if (!finite) return kNonFinite;
  if (!fluid) return -1;  // boundary particles move as prescribed
  if (math::fabs(rho / limits.reference_density - 1.0) > limits.density_variation) return kDensityVariation;
  if (speed_sq > limits.speed * limits.speed) return kSpeedLimit;
  if (accel_sq > limits.acceleration * limits.acceleration) return kAccelerationLimit;
  return -1;
}

// health_problem(...) < 0 without a branch, for the corrector to check the
// particles as it writes them (physics/PredictorCorrector.hpp). Any NaN or
// Inf makes the sum of the differences v - v NaN.
template <int Dim>
KOKKOS_INLINE_FUNCTION bool healthy(const double* x, const double* v, const double* a, double rho, double drhodt,
                                    bool fluid, const HealthLimits& limits) {
  double differences = (rho - rho) + (drhodt - drhodt);
  double speed_sq = 0, accel_sq = 0;
  for (int d = 0; d < Dim; ++d) {
    differences += (x[d] - x[d]) + (v[d] - v[d]) + (a[d] - a[d]);
    speed_sq += v[d] * v[d];
    accel_sq += a[d] * a[d];
  }
  const bool within = (math::fabs(rho / limits.reference_density - 1.0) <= limits.density_variation) &
                      (speed_sq <= limits.speed * limits.speed) &
                      (accel_sq <= limits.acceleration * limits.acceleration);
  return (differences == 0.0) & (within | !fluid);
}

template <int Dim, class Fields>
KOKKOS_INLINE_FUNCTION int health_problem_of(const Fields& P, int i, const HealthLimits& limits) {
  double x[Dim], v[Dim], a[Dim];
  for (int d = 0; d < Dim; ++d) x[d] = P.x(i, d), v[d] = P.v(i, d), a[d] = P.dvdt(i, d);
  return health_problem<Dim>(x, v, a, P.rho(i), P.drhodt(i), P.kind(i) == kFluid, limits);
}

}  // namespace poresph

namespace Kokkos {
template <>
struct reduction_identity<poresph::HealthCounts> {
  KOKKOS_FORCEINLINE_FUNCTION static poresph::HealthCounts sum() { return poresph::HealthCounts(); }
};
}  // namespace Kokkos

namespace poresph {

// Counts the owned particles with each problem.
template <int Dim, class ExecSpace>
HealthCounts count_health_problems(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                                   const HealthLimits& limits) {
  HealthCounts counts;
  const auto Q = P;
  static const std::string label_count_health_problems = "poresph::count_health_problems";
  Kokkos::parallel_reduce(
      label_count_health_problems, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned),
      KOKKOS_LAMBDA(int i, HealthCounts& sum) {
        const int cause = health_problem_of<Dim>(Q, i, limits);
        if (cause >= 0) ++sum.count[cause];
      },
      Kokkos::Sum<HealthCounts>(counts));
  return counts;
}

// The owned particle with the smallest id that has `cause` (-1 if none).
template <int Dim, class ExecSpace>
int first_particle_with(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                        const HealthLimits& limits, int cause) {
  const auto Q = P;
  long long smallest_id = 0;
  static const std::string label_first_particle_with = "poresph::first_particle_with";
  Kokkos::parallel_reduce(
      label_first_particle_with, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned),
      KOKKOS_LAMBDA(int i, long long& best) {
        if (health_problem_of<Dim>(Q, i, limits) == cause && Q.id(i) < best) best = Q.id(i);
      },
      Kokkos::Min<long long>(smallest_id));
  int index = -1;
  static const std::string label_index_of_id = "poresph::index_of_id";
  Kokkos::parallel_reduce(
      label_index_of_id, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned),
      KOKKOS_LAMBDA(int i, int& found) {
        if (Q.id(i) == smallest_id && found < i) found = i;
      },
      Kokkos::Max<int>(index));
  return index >= 0 ? index : -1;
}

}  // namespace poresph
