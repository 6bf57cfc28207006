#pragma once
// One pair's contributions to the rates of particle a (METHOD.md), with
// grad_a W_ab = r_ab F_ab and F_ab = (1/r) dW/dr. Each term is exactly
// antisymmetric in (a, b) up to the neighbour's mass, so that momentum is
// conserved to round-off when both particles evaluate the pair. Force-inlined,
// as what the pair loop calls must be (core/Vec.hpp).
#include <Kokkos_Core.hpp>

#include "core/Vec.hpp"

namespace poresph {

// The pair loop (physics/PairDriver.hpp) forms each term per unit mass of
// the neighbour (the "weight" functions below) once for both ends of a pair
// and multiplies by the neighbour's mass at each end; the *_rate and
// *_acceleration functions are those weights times m_b, as the loop rounds
// them.

// Continuity per unit neighbour mass: v_ab . grad_a W_ab = F_ab v_ab . r_ab,
// the same from either end.
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION double continuity_weight(const Vec<Dim>& v_ab, const Vec<Dim>& r_ab, double F_ab) {
  return F_ab * dot(v_ab, r_ab);
}

// Continuity equation: d rho_a/dt += m_b v_ab . grad_a W_ab.
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION double continuity_rate(double m_b, const Vec<Dim>& v_ab, const Vec<Dim>& r_ab, double F_ab) {
  return m_b * continuity_weight(v_ab, r_ab, F_ab);
}

// p / rho^2, the per-particle factor of the symmetric pressure term.
KOKKOS_FORCEINLINE_FUNCTION double pressure_term(double p, double rho) { return p / (rho * rho); }

// d/dp of pressure_term(p - p_ref, rho) with the density following the
// pressure, rho = p / c^2: 1 / rho^2 - 2 (p - p_ref) / (rho^3 c^2).
KOKKOS_FORCEINLINE_FUNCTION double pressure_term_slope(double relative_p, double rho, double sound_speed_sq) {
  return (1.0 - 2.0 * relative_p / (rho * sound_speed_sq)) / (rho * rho);
}

// The pressure term per unit neighbour mass, as a weight of r_ab:
// -(P_a + P_b) F_ab with P = p / rho^2 (b sees the same weight of r_ba).
KOKKOS_FORCEINLINE_FUNCTION double pressure_weight(double P_a, double P_b, double F_ab) { return -(P_a + P_b) * F_ab; }

// Symmetric pressure term: -m_b (p_a/rho_a^2 + p_b/rho_b^2) grad_a W_ab,
// given the pressure terms P = p / rho^2 of both particles.
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION Vec<Dim> pressure_acceleration(double m_b, double P_a, double P_b, const Vec<Dim>& r_ab,
                                                      double F_ab) {
  return (m_b * pressure_weight(P_a, P_b, F_ab)) * r_ab;
}

// The viscous term per unit neighbour mass, as a weight of v_ab:
// nu (1/rho_a + 1/rho_b) F_ab, the same from either end.
KOKKOS_FORCEINLINE_FUNCTION double viscous_weight(double nu, double inv_rho_a, double inv_rho_b, double F_ab) {
  return nu * (inv_rho_a + inv_rho_b) * F_ab;
}

// Morris et al. (1997) viscous term, m_b (mu_a + mu_b) v_ab / (rho_a rho_b) F_ab,
// with mu = rho nu for one fluid of kinematic viscosity nu, written as
// m_b nu (1/rho_a + 1/rho_b) v_ab F_ab from the inverse densities. Next to a
// surface v_ab is the velocity seen through the no-slip extrapolation
// (physics/NoSlip.hpp).
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION Vec<Dim> viscous_acceleration(double m_b, double nu, double inv_rho_a, double inv_rho_b,
                                                     const Vec<Dim>& v_ab, double F_ab) {
  return (m_b * viscous_weight(nu, inv_rho_a, inv_rho_b, F_ab)) * v_ab;
}

// Two fluids: Morris's term m_b 2 mu_ab v_ab F_ab / (rho_a rho_b), with
// mu = rho nu of each particle's own phase and mu_ab a mean of mu_a and
// mu_b, per unit neighbour mass (physics/terms/PhaseViscousTerm.hpp).
// The harmonic mean, 2 mu_ab = 4 mu_a mu_b / (mu_a + mu_b), keeps the shear
// stress continuous across an interface between layers (the flux through a
// pair in series, as in a finite-volume face; the arithmetic mean,
// nu_a / rho_b + nu_b / rho_a, was measured 18 times farther off on the
// layered channel: docs/method.md); of one fluid (nu_a = nu_b, rho_a =
// rho_b) it is the one-fluid weight:
//   2 mu_ab / (rho_a rho_b) = 4 nu_a nu_b / (rho_a nu_a + rho_b nu_b).
KOKKOS_FORCEINLINE_FUNCTION double harmonic_phase_viscous_weight(double nu_a, double nu_b, double inv_rho_a,
                                                                 double inv_rho_b, double F_ab) {
  return 4.0 * nu_a * nu_b * inv_rho_a * inv_rho_b / (nu_a * inv_rho_b + nu_b * inv_rho_a) * F_ab;
}

// Convective acceleration -(v_a . grad) v at a, one neighbour's share, in
// the difference form -V_b (v_b - v_a) (v_a . grad_a W_ab) with V_b the
// neighbour's volume: zero for a uniform flow, and exact for a linear one
// wherever the support is full (sum_b V_b r_ab (x) grad_a W_ab = -I).
// As a weight of v_ab: V_b F_ab (v_a . r_ab); b's weight of v_ab (not v_ba)
// is V_a F_ab (v_b . r_ab).
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION double convective_weight(double V_b, const Vec<Dim>& v_a, const Vec<Dim>& r_ab, double F_ab) {
  return V_b * F_ab * dot(v_a, r_ab);
}
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION Vec<Dim> convective_acceleration(double V_b, const Vec<Dim>& v_a, const Vec<Dim>& v_ab,
                                                        const Vec<Dim>& r_ab, double F_ab) {
  return convective_weight(V_b, v_a, r_ab, F_ab) * v_ab;
}

// Particle shifting (Lind et al. 2012), one neighbour's share of the
// concentration gradient grad C_a = sum_b V_b grad_a W_ab, and of the
// velocity gradient (grad v)_ij = -sum_b V_b v_ab,i (grad_a W_ab)_j: both
// are V_b F_ab times r_ab, the weight given here.
KOKKOS_FORCEINLINE_FUNCTION double volume_gradient_weight(double V_b, double F_ab) { return V_b * F_ab; }

// Surface tension by the continuum surface force (Morris 2000; Adami, Hu &
// Adams 2010), one neighbour's share of each sum (physics/SurfaceTension.hpp).
// The colour gradient n_a = sum_b V_b (c_b - c_a) grad_a W_ab: on a full
// lattice it is the very operator the symmetric pressure term applies to
// p (sum_b V_b grad_a W_ab = 0 there), so that a force sigma kappa n with
// kappa uniform is balanced by a pressure sigma kappa c exactly.
template <int Dim>
KOKKOS_INLINE_FUNCTION Vec<Dim> colour_gradient_share(double V_b, double c_a, double c_b, const Vec<Dim>& r_ab,
                                                      double F_ab) {
  return (V_b * (c_b - c_a) * F_ab) * r_ab;
}
// The divergence of the unit normal, sum_b V_b (nhat_b - nhat_a) . grad_a W_ab,
// over the neighbours b whose normal passes Morris's filter; kappa_a is
// minus it over the same neighbours' Shepard sum sum_b V_b W_ab (self
// included), which makes up for the neighbours left out (Morris 2000).
template <int Dim>
KOKKOS_INLINE_FUNCTION double normal_divergence_share(double V_b, const Vec<Dim>& nhat_a, const Vec<Dim>& nhat_b,
                                                      const Vec<Dim>& r_ab, double F_ab) {
  return V_b * F_ab * dot(nhat_b - nhat_a, r_ab);
}
KOKKOS_INLINE_FUNCTION double curvature_from_sums(double divergence, double shepard) { return -divergence / shepard; }
// The acceleration of the force per volume sigma kappa n on a fluid of density rho.
template <int Dim>
KOKKOS_INLINE_FUNCTION Vec<Dim> surface_tension_acceleration(double sigma, double kappa, const Vec<Dim>& n,
                                                             double rho) {
  return (sigma * kappa / rho) * n;
}

// Weakly compressible equation of state of the paper: p = c^2 rho.
KOKKOS_FORCEINLINE_FUNCTION double pressure_from_density(double rho, double sound_speed_sq) { return sound_speed_sq * rho; }

}  // namespace poresph
