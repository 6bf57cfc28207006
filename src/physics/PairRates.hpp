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
// a scene without walls or grains pays nothing for them.
template <int Dim, class ExecSpace, bool WithSurfaces, bool WithShifting>
struct PairRates {
  using MemorySpace = typename ExecSpace::memory_space;
  Particles<Dim, MemorySpace> P;
  NeighbourList<Dim, ExecSpace> neighbours;
  QuinticKernel<Dim> kernel;
  FluidProperties fluid;
  Vec<Dim> body_force;
  ShiftingParameters shifting;

  KOKKOS_INLINE_FUNCTION void operator()(int a) const {
    const Vec<Dim> x_a = row<Dim>(P.x, a), v_a = row<Dim>(P.v, a);
    const double inv_rho_a = P.inverse_density(a), P_a = P.pressure_term(a);
    const bool a_is_fluid = P.kind(a) == kFluid;
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
      const double m_b = P.m(b);
      const Vec<Dim> v_ab = v_a - row<Dim>(P.v, b);
      drho += continuity_rate(m_b, v_ab, r_ab, F_ab);
      if (!a_is_fluid) continue;  // boundary particles move as their surface prescribes
      if constexpr (WithShifting) {
        const double volume_F = m_b * P.inverse_density(b) * F_ab;  // (m_b/rho_b) grad W = volume_F r_ab
        grad_concentration += volume_F * r_ab;
        for (int i = 0; i < Dim; ++i)
          for (int j = 0; j < Dim; ++j) grad_velocity[i][j] -= volume_F * v_ab[i] * r_ab[j];
      }
      acceleration += pressure_acceleration(m_b, P_a, P.pressure_term(b), r_ab, F_ab);
      Vec<Dim> v_viscous = v_ab;
      if constexpr (WithSurfaces) {
        const int kind_b = P.kind(b);
        if (kind_b != kFluid) {
          const SurfaceDistances<Dim> s =
              surface_distances<Dim>(kind_b, row<Dim>(P.wall_vector, b), P.wall_scalar(b), r_ab);
          v_viscous = no_slip_factor(s, fluid.min_surface_distance) * v_ab;
        }
      }
      acceleration += viscous_acceleration(m_b, fluid.kinematic_viscosity, inv_rho_a, P.inverse_density(b), v_viscous, F_ab);
    }

    P.drhodt(a) = drho;
    if (a_is_fluid) acceleration += body_force;
    else acceleration = Vec<Dim>::zero();
    set_row(P.dvdt, a, acceleration);
    if constexpr (WithShifting) {
      Vec<Dim> shift = Vec<Dim>::zero(), dv = Vec<Dim>::zero();
      if (a_is_fluid) {
        shift = (-shifting.coefficient * shifting.h_dt * math::sqrt(dot(v_a, v_a))) * grad_concentration;
        const double length = math::sqrt(dot(shift, shift));
        if (length > shifting.max_shift) shift = (shifting.max_shift / length) * shift;
        for (int i = 0; i < Dim; ++i)
          for (int j = 0; j < Dim; ++j) dv[i] += grad_velocity[i][j] * shift[j];
      }
      set_row(P.shift, a, shift);
      set_row(P.shift_velocity, a, dv);
    }
  }
};

// Evaluates the rates of all owned particles; ghosts and the cell list must
// be up to date.
template <int Dim, class ExecSpace>
void compute_pair_rates(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                        const NeighbourList<Dim, ExecSpace>& neighbours, const QuinticKernel<Dim>& kernel,
                        const FluidProperties& fluid, const Vec<Dim>& body_force,
                        const ShiftingParameters& shifting = {}) {
  const auto policy = Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned);
  const bool shift = P.has_shifting && shifting.coefficient > 0;
  // Each combination is its own kernel: what a scene does not use is not compiled into its loop.
  static const std::string label_surfaces_shifting = "poresph::PairRates<surfaces,shifting>";
  static const std::string label_surfaces = "poresph::PairRates<surfaces>";
  static const std::string label_shifting = "poresph::PairRates<shifting>";
  static const std::string label_plain = "poresph::PairRates";
  if (P.has_surfaces && shift)
    Kokkos::parallel_for(label_surfaces_shifting, policy,
                         PairRates<Dim, ExecSpace, true, true>{P, neighbours, kernel, fluid, body_force, shifting});
  else if (P.has_surfaces)
    Kokkos::parallel_for(label_surfaces, policy,
                         PairRates<Dim, ExecSpace, true, false>{P, neighbours, kernel, fluid, body_force, shifting});
  else if (shift)
    Kokkos::parallel_for(label_shifting, policy,
                         PairRates<Dim, ExecSpace, false, true>{P, neighbours, kernel, fluid, body_force, shifting});
  else
    Kokkos::parallel_for(label_plain, policy,
                         PairRates<Dim, ExecSpace, false, false>{P, neighbours, kernel, fluid, body_force, shifting});
}

}  // namespace poresph
