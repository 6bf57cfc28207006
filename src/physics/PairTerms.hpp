#pragma once
// One pair's contributions to the rates of particle a (METHOD.md), with
// grad_a W_ab = r_ab F_ab and F_ab = (1/r) dW/dr. Each term is exactly
// antisymmetric in (a, b) up to the neighbour's mass, so that momentum is
// conserved to round-off when both particles evaluate the pair.
#include <Kokkos_Core.hpp>

#include "core/Vec.hpp"

namespace poresph {

// Continuity equation: d rho_a/dt += m_b v_ab . grad_a W_ab.
template <int Dim>
KOKKOS_INLINE_FUNCTION double continuity_rate(double m_b, const Vec<Dim>& v_ab, const Vec<Dim>& r_ab, double F_ab) {
  return m_b * F_ab * dot(v_ab, r_ab);
}

// Symmetric pressure term: -m_b (p_a/rho_a^2 + p_b/rho_b^2) grad_a W_ab.
template <int Dim>
KOKKOS_INLINE_FUNCTION Vec<Dim> pressure_acceleration(double m_b, double p_a, double rho_a, double p_b, double rho_b,
                                                      const Vec<Dim>& r_ab, double F_ab) {
  const double coefficient = -m_b * (p_a / (rho_a * rho_a) + p_b / (rho_b * rho_b)) * F_ab;
  return coefficient * r_ab;
}

// Morris et al. (1997) viscous term, m_b (mu_a + mu_b) v_ab / (rho_a rho_b) F_ab,
// with mu = rho nu for one fluid of kinematic viscosity nu.
template <int Dim>
KOKKOS_INLINE_FUNCTION Vec<Dim> viscous_acceleration(double m_b, double nu, double rho_a, double rho_b,
                                                     const Vec<Dim>& v_ab, double F_ab) {
  const double coefficient = m_b * nu * (rho_a + rho_b) / (rho_a * rho_b) * F_ab;
  return coefficient * v_ab;
}

// Weakly compressible equation of state of the paper: p = c^2 rho.
KOKKOS_INLINE_FUNCTION double pressure_from_density(double rho, double sound_speed_sq) { return sound_speed_sq * rho; }

}  // namespace poresph
