#pragma once
// The one pair-interaction loop: for every owned particle, a single pass over
// its neighbours gives the continuity density rate, the pressure term and the
// Morris viscous term together. Each particle writes only its own rates (a
// full neighbour search, every pair seen from both sides), so threads never
// race and no scatter-add is needed.
#include <Kokkos_Core.hpp>

#include "core/CellList.hpp"
#include "core/Kernel.hpp"
#include "core/Math.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"
#include "physics/NoSlip.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

struct FluidProperties {
  double kinematic_viscosity;
  double min_surface_distance;  // lower bound of d_a in the no-slip extrapolation
  // Subtracted from p = c^2 rho in the momentum equation. A uniform pressure
  // has no gradient, but through the SPH gradient of a sheared lattice it
  // exerts spurious shear stresses proportional to itself
  // (docs/validation.md); c^2 rho0 removes them, 0 is the paper's form.
  double reference_pressure;
};

// WithSurfaces = false compiles the loop without any boundary-particle code:
// a scene without walls or grains pays nothing for them.
template <int Dim, class ExecSpace, bool WithSurfaces>
struct PairRates {
  using MemorySpace = typename ExecSpace::memory_space;
  Particles<Dim, MemorySpace> P;
  CellList<Dim, ExecSpace> cells;
  QuinticKernel<Dim> kernel;
  FluidProperties fluid;
  Vec<Dim> body_force;

  KOKKOS_INLINE_FUNCTION void operator()(int a) const {
    const Vec<Dim> x_a = row<Dim>(P.x, a), v_a = row<Dim>(P.v, a);
    const double rho_a = P.rho(a), p_a = P.p(a) - fluid.reference_pressure;
    const bool a_is_fluid = P.kind(a) == kFluid;
    double drho = 0.0;
    Vec<Dim> acceleration = Vec<Dim>::zero();

    cells.for_each_candidate(x_a, [&](int b) {
      const Vec<Dim> r_ab = x_a - row<Dim>(P.x, b);
      const double r_sq = dot(r_ab, r_ab);
      if (r_sq >= kernel.cutoff_sq || b == a) return;
      const double F_ab = kernel.derivative_over_r(math::sqrt(r_sq));
      const double m_b = P.m(b), rho_b = P.rho(b);
      const Vec<Dim> v_ab = v_a - row<Dim>(P.v, b);
      drho += continuity_rate(m_b, v_ab, r_ab, F_ab);
      if (!a_is_fluid) return;  // boundary particles move as their surface prescribes
      acceleration += pressure_acceleration(m_b, p_a, rho_a, P.p(b) - fluid.reference_pressure, rho_b, r_ab, F_ab);
      Vec<Dim> v_viscous = v_ab;
      if constexpr (WithSurfaces) {
        const int kind_b = P.kind(b);
        if (kind_b != kFluid) {
          const SurfaceDistances<Dim> s =
              surface_distances<Dim>(kind_b, row<Dim>(P.wall_vector, b), P.wall_scalar(b), r_ab);
          v_viscous = no_slip_factor(s, fluid.min_surface_distance) * v_ab;
        }
      }
      acceleration += viscous_acceleration(m_b, fluid.kinematic_viscosity, rho_a, rho_b, v_viscous, F_ab);
    });

    P.drhodt(a) = drho;
    if (a_is_fluid) acceleration += body_force;
    else acceleration = Vec<Dim>::zero();
    set_row(P.dvdt, a, acceleration);
  }
};

// Evaluates the rates of all owned particles; ghosts and the cell list must
// be up to date.
template <int Dim, class ExecSpace>
void compute_pair_rates(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                        const CellList<Dim, ExecSpace>& cells, const QuinticKernel<Dim>& kernel,
                        const FluidProperties& fluid, const Vec<Dim>& body_force) {
  const auto policy = Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned);
  if (P.has_surfaces)
    Kokkos::parallel_for("poresph::PairRates<surfaces>", policy,
                         PairRates<Dim, ExecSpace, true>{P, cells, kernel, fluid, body_force});
  else
    Kokkos::parallel_for("poresph::PairRates", policy,
                         PairRates<Dim, ExecSpace, false>{P, cells, kernel, fluid, body_force});
}

}  // namespace poresph
