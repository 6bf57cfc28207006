#pragma once
// Equation of state and density re-initialisation by summation.
#include <Kokkos_Core.hpp>

#include "core/NeighbourList.hpp"
#include "core/Kernel.hpp"
#include "core/Math.hpp"
#include "core/Particles.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

// p = c^2 rho, and the factors the pair loop needs: (p - p_ref)/rho^2 and 1/rho.
template <int Dim, class ExecSpace>
void update_pressure(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                     double sound_speed_sq, double reference_pressure) {
  const auto rho = P.rho, p = P.p, term = P.pressure_term, inverse = P.inverse_density;
  static const std::string label_update_pressure = "poresph::update_pressure";
  Kokkos::parallel_for(
      label_update_pressure, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned), KOKKOS_LAMBDA(int i) {
        p(i) = pressure_from_density(rho(i), sound_speed_sq);
        term(i) = pressure_term(p(i) - reference_pressure, rho(i));
        inverse(i) = 1.0 / rho(i);
      });
}

// rho_a = sum_b m_b W_ab (self included) for fluid particles. Boundary
// particles keep their continuity density: the solid beyond their 3h shell
// holds no particles, so a sum would be deficient there.
template <int Dim, class ExecSpace>
void resum_fluid_density(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                         const NeighbourList<Dim, ExecSpace>& neighbours, const QuinticKernel<Dim>& kernel) {
  const auto x = P.x, m = P.m, rho = P.rho;
  const auto kind = P.kind;
  const int owned = P.owned;
  // The sums start from the particle's own term (the list leaves it out)
  // and, with a half list, gather each pair from both ends.
  static const std::string label_self = "poresph::resum_fluid_density::self";
  Kokkos::parallel_for(
      label_self, Kokkos::RangePolicy<ExecSpace>(space, 0, owned), KOKKOS_LAMBDA(int a) {
        if (kind(a) == kFluid) rho(a) = m(a) * kernel.value(0.0);
      });
  static const std::string label_resum_fluid_density = "poresph::resum_fluid_density";
  Kokkos::parallel_for(
      label_resum_fluid_density, Kokkos::RangePolicy<ExecSpace>(space, 0, owned),
      KOKKOS_LAMBDA(int a) {
        const bool a_is_fluid = kind(a) == kFluid;
        const Vec<Dim> x_a = row<Dim>(x, a);
        double sum = 0.0;
        for (int k = neighbours.begin(a); k < neighbours.end(a); ++k) {
          const int b = neighbours.neighbour(k);
          const Vec<Dim> r_ab = x_a - row<Dim>(x, b);
          const double r_sq = dot(r_ab, r_ab);
          if (r_sq >= kernel.cutoff_sq) continue;
          const double w = kernel.value(math::sqrt(r_sq));
          sum += m(b) * w;
          if constexpr (NeighbourList<Dim, ExecSpace>::kHalf)
            if (b < owned && kind(b) == kFluid) rho(b) += m(a) * w;
        }
        if (a_is_fluid) rho(a) += sum;
      });
}

}  // namespace poresph
