#pragma once
// The one pair-interaction loop: for every owned particle, a single pass over
// its neighbours gives the continuity density rate, the pressure term and the
// Morris viscous term together. Each particle writes only its own rates (a
// full neighbour search, every pair seen from both sides), so threads never
// race and no scatter-add is needed.
#include <Kokkos_Core.hpp>

#include "core/NeighbourList.hpp"
#include "core/Kernel.hpp"
#include "core/Math.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"
#include "physics/NoSlip.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

// Particle shifting (Lind et al. 2012): each step a fluid particle moves by
// dr = -A h |v| dt grad C, C = sum_b (m_b/rho_b) W_ab its concentration,
// capped at a fraction of dx, and its velocity follows by v += (grad v) dr.
struct ShiftingParameters {
  double coefficient = 0;  // A; 0 = off
  double h_dt = 0;         // h * dt
  double max_shift = 0;    // cap on |dr|
};

struct FluidProperties {
  double kinematic_viscosity;
  double min_surface_distance;  // lower bound of d_a in the no-slip extrapolation
};

// WithSurfaces = false compiles the loop without any boundary-particle code:
// a scene without walls or grains pays nothing for them. With a half
// neighbour list (Serial: core/NeighbourList.hpp) each listed pair is
// evaluated once and adds to both particles; with a full list each particle
// adds to itself only. The rates are sums: zeroed before the loop, finished
// (body force, particle shifting) after it by FinishRates.
template <int Dim, class ExecSpace, bool WithSurfaces, bool WithShifting>
struct PairRates {
  using MemorySpace = typename ExecSpace::memory_space;
  static constexpr bool kHalf = NeighbourList<Dim, ExecSpace>::kHalf;
  Particles<Dim, MemorySpace> P;
  NeighbourList<Dim, ExecSpace> neighbours;
  QuinticKernel<Dim> kernel;
  FluidProperties fluid;

  // The viscous velocity difference fluid particle a sees for neighbour b:
  // v_ab itself, or for a boundary particle its no-slip extrapolation.
  KOKKOS_INLINE_FUNCTION Vec<Dim> viscous_velocity(int b, int kind_b, const Vec<Dim>& v_ab,
                                                   const Vec<Dim>& r_ab) const {
    if constexpr (WithSurfaces) {
      if (kind_b != kFluid) {
        const SurfaceDistances<Dim> s =
            surface_distances<Dim>(kind_b, row<Dim>(P.wall_vector, b), P.wall_scalar(b), r_ab);
        return no_slip_factor(s, fluid.min_surface_distance) * v_ab;
      }
    }
    (void)b, (void)kind_b, (void)r_ab;
    return v_ab;
  }

  KOKKOS_INLINE_FUNCTION void operator()(int a) const {
    const Vec<Dim> x_a = row<Dim>(P.x, a), v_a = row<Dim>(P.v, a);
    const double inv_rho_a = P.inverse_density(a), P_a = P.pressure_term(a), m_a = P.m(a);
    const int kind_a = P.kind(a);
    const bool a_is_fluid = kind_a == kFluid;
    double drho = 0.0;
    Vec<Dim> acceleration = Vec<Dim>::zero();
    Vec<Dim> grad_concentration = Vec<Dim>::zero();
    double grad_velocity[Dim][Dim] = {};  // d v_i / d x_j

    const int end = neighbours.end(a);
    for (int k = neighbours.begin(a); k < end; ++k) {
      const int b = neighbours.neighbour(k);
      const Vec<Dim> r_ab = x_a - row<Dim>(P.x, b);
      const double r_sq = dot(r_ab, r_ab);
      if (r_sq >= kernel.cutoff_sq) continue;  // the list holds the skin too
      const double F_ab = kernel.derivative_over_r(math::sqrt(r_sq));
      const double m_b = P.m(b), inv_rho_b = P.inverse_density(b);
      const Vec<Dim> v_ab = v_a - row<Dim>(P.v, b);
      // Per unit mass of the other particle, so that each side scales by it.
      const double continuity = continuity_rate(1.0, v_ab, r_ab, F_ab);
      const Vec<Dim> pressure = pressure_acceleration(1.0, P_a, P.pressure_term(b), r_ab, F_ab);
      const double viscous_factor = fluid.kinematic_viscosity * (inv_rho_a + inv_rho_b) * F_ab;
      int kind_b = kFluid;
      if constexpr (WithSurfaces) kind_b = P.kind(b);
      else (void)kind_a;

      drho += m_b * continuity;
      if (a_is_fluid) {  // boundary particles move as their surface prescribes
        acceleration += m_b * (pressure + viscous_factor * viscous_velocity(b, kind_b, v_ab, r_ab));
        if constexpr (WithShifting) {
          const double volume_F = m_b * inv_rho_b * F_ab;  // (m_b/rho_b) grad W = volume_F r_ab
          grad_concentration += volume_F * r_ab;
          for (int i = 0; i < Dim; ++i)
            for (int j = 0; j < Dim; ++j) grad_velocity[i][j] -= volume_F * v_ab[i] * r_ab[j];
        }
      }
      if constexpr (kHalf) {
        if (b >= P.owned) continue;  // a ghost: its owner evaluates the pair for it
        // The same pair seen from b: r_ba = -r_ab, v_ba = -v_ab.
        P.drhodt(b) += m_a * continuity;
        if (kind_b != kFluid) continue;
        const Vec<Dim> v_viscous_b = viscous_velocity(a, kind_a, -1.0 * v_ab, -1.0 * r_ab);
        const Vec<Dim> acceleration_b = m_a * (viscous_factor * v_viscous_b - pressure);
        for (int d = 0; d < Dim; ++d) P.dvdt(b, d) += acceleration_b[d];
        if constexpr (WithShifting) {
          const double volume_F = m_a * inv_rho_a * F_ab;
          for (int i = 0; i < Dim; ++i) {
            P.grad_concentration(b, i) -= volume_F * r_ab[i];
            for (int j = 0; j < Dim; ++j) P.grad_velocity(b, i * Dim + j) -= volume_F * v_ab[i] * r_ab[j];
          }
        }
      }
    }

    P.drhodt(a) += drho;
    for (int d = 0; d < Dim; ++d) P.dvdt(a, d) += acceleration[d];
    if constexpr (WithShifting) {
      for (int i = 0; i < Dim; ++i) {
        P.grad_concentration(a, i) += grad_concentration[i];
        for (int j = 0; j < Dim; ++j) P.grad_velocity(a, i * Dim + j) += grad_velocity[i][j];
      }
    }
  }
};

// After the pair loop: the body force on fluid particles, none on boundary
// particles, and the particle-shifting displacement from the summed gradients.
template <int Dim, class MemorySpace, bool WithShifting>
struct FinishRates {
  Particles<Dim, MemorySpace> P;
  Vec<Dim> body_force;
  ShiftingParameters shifting;

  KOKKOS_INLINE_FUNCTION void operator()(int a) const {
    const bool a_is_fluid = P.kind(a) == kFluid;
    for (int d = 0; d < Dim; ++d) P.dvdt(a, d) = a_is_fluid ? P.dvdt(a, d) + body_force[d] : 0.0;
    if constexpr (WithShifting) {
      Vec<Dim> shift = Vec<Dim>::zero(), dv = Vec<Dim>::zero();
      if (a_is_fluid) {
        const Vec<Dim> v_a = row<Dim>(P.v, a), grad_concentration = row<Dim>(P.grad_concentration, a);
        shift = (-shifting.coefficient * shifting.h_dt * math::sqrt(dot(v_a, v_a))) * grad_concentration;
        const double length = math::sqrt(dot(shift, shift));
        if (length > shifting.max_shift) shift = (shifting.max_shift / length) * shift;
        for (int i = 0; i < Dim; ++i)
          for (int j = 0; j < Dim; ++j) dv[i] += P.grad_velocity(a, i * Dim + j) * shift[j];
      }
      set_row(P.shift, a, shift);
      set_row(P.shift_velocity, a, dv);
    }
  }
};

// Evaluates the rates of all owned particles; ghosts and the neighbour list
// must be up to date.
template <int Dim, class ExecSpace>
void compute_pair_rates(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                        const NeighbourList<Dim, ExecSpace>& neighbours, const QuinticKernel<Dim>& kernel,
                        const FluidProperties& fluid, const Vec<Dim>& body_force,
                        const ShiftingParameters& shifting = {}) {
  using MemorySpace = typename ExecSpace::memory_space;
  const auto policy = Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned);
  const bool shift = P.has_shifting && shifting.coefficient > 0;
  const auto Q = P;
  static const std::string label_zero = "poresph::zero_rates";
  Kokkos::parallel_for(
      label_zero, policy, KOKKOS_LAMBDA(int a) {
        Q.drhodt(a) = 0.0;
        for (int d = 0; d < Dim; ++d) Q.dvdt(a, d) = 0.0;
        if (shift)
          for (int i = 0; i < Dim; ++i) {
            Q.grad_concentration(a, i) = 0.0;
            for (int j = 0; j < Dim; ++j) Q.grad_velocity(a, i * Dim + j) = 0.0;
          }
      });
  // Each combination is its own kernel: what a scene does not use is not compiled into its loop.
  static const std::string label_surfaces_shifting = "poresph::PairRates<surfaces,shifting>";
  static const std::string label_surfaces = "poresph::PairRates<surfaces>";
  static const std::string label_shifting = "poresph::PairRates<shifting>";
  static const std::string label_plain = "poresph::PairRates";
  if (P.has_surfaces && shift)
    Kokkos::parallel_for(label_surfaces_shifting, policy, PairRates<Dim, ExecSpace, true, true>{P, neighbours, kernel, fluid});
  else if (P.has_surfaces)
    Kokkos::parallel_for(label_surfaces, policy, PairRates<Dim, ExecSpace, true, false>{P, neighbours, kernel, fluid});
  else if (shift)
    Kokkos::parallel_for(label_shifting, policy, PairRates<Dim, ExecSpace, false, true>{P, neighbours, kernel, fluid});
  else
    Kokkos::parallel_for(label_plain, policy, PairRates<Dim, ExecSpace, false, false>{P, neighbours, kernel, fluid});
  static const std::string label_finish = "poresph::FinishRates";
  if (shift)
    Kokkos::parallel_for(label_finish, policy, FinishRates<Dim, MemorySpace, true>{P, body_force, shifting});
  else
    Kokkos::parallel_for(label_finish, policy, FinishRates<Dim, MemorySpace, false>{P, body_force, shifting});
}

}  // namespace poresph
