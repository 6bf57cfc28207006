#pragma once
// Equation of state and density re-initialisation by summation.
#include <Kokkos_Core.hpp>

#include <stdexcept>
#include <string>

#include "core/NeighbourList.hpp"
#include "core/Kernel.hpp"
#include "core/Math.hpp"
#include "core/PairSums.hpp"
#include "core/Particles.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

// p = c^2 rho, and the factors the pair loop needs: (p - p_ref)/rho^2 and
// 1/rho, by which the loop turns masses into volumes. Fixed particles pass
// volume_density = rho0: a lattice point's volume is dx^N whatever the
// density there, which is then only the pressure's measure.
template <int Dim, class ExecSpace>
void update_pressure(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                     double sound_speed_sq, double reference_pressure, double volume_density = 0.0) {
  const auto rho = P.rho, p = P.p, term = P.pressure_term, inverse = P.inverse_density;
  const bool with_inverse = !P.fixed_positions;  // fixed particles hold none (1/rho0)
  static const std::string label_update_pressure = "poresph::update_pressure";
  Kokkos::parallel_for(
      label_update_pressure, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned), KOKKOS_LAMBDA(int i) {
        p(i) = pressure_from_density(rho(i), sound_speed_sq);
        term(i) = pressure_term(p(i) - reference_pressure, rho(i));
        if (with_inverse) inverse(i) = 1.0 / (volume_density > 0 ? volume_density : rho(i));
      });
}

// rho_a = sum_b m_b W_ab (self included) for fluid particles. Boundary
// particles keep their continuity density: the solid beyond their 3h shell
// holds no particles, so a sum would be deficient there. The half list's
// pairs add to both ends through `sums` (component 0), as in the pair loop.
template <int Dim, class ExecSpace>
void resum_fluid_density(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                         const NeighbourList<Dim, ExecSpace>& neighbours, const PairSums<Dim, ExecSpace>& sums,
                         const QuinticKernel<Dim>& kernel) {
  // Its sums are component 0 of every copy: none may be a particle's rate.
  if (sums.first_copy_in_rates()) throw std::logic_error("resum_fluid_density: the pair sums' first copy is the rates");
  const auto x = P.x, m = P.m, rho = P.rho;
  const auto kind = P.kind;
  const auto policy = Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned);
  static const std::string label_resum_fluid_density = "poresph::resum_fluid_density";
  Kokkos::parallel_for(
      label_resum_fluid_density, policy, KOKKOS_LAMBDA(int a) {
        const Vec<Dim> x_a = row<Dim>(x, a);
        const double m_a = m(a);
        const int copy = sums.acquire();
        double sum = 0.0;
        const int ghosts_begin = neighbours.ghosts_begin(a), end = neighbours.end(a);
        // Beyond 3h (the list's skin) the kernel is exactly zero: no test needed.
        for (int k = neighbours.begin(a); k < ghosts_begin; ++k) {
          const int b = neighbours.neighbour(k);
          const Vec<Dim> r_ab = x_a - row<Dim>(x, b);
          const double w = kernel.value(math::sqrt(dot(r_ab, r_ab)));
          sum += m(b) * w;
          sums.add(copy, b, 0, m_a * w);
        }
        for (int k = ghosts_begin; k < end; ++k) {
          const int b = neighbours.neighbour(k);
          const Vec<Dim> r_ab = x_a - row<Dim>(x, b);
          sum += m(b) * kernel.value(math::sqrt(dot(r_ab, r_ab)));
        }
        sums.add(copy, a, 0, sum);
        sums.release(copy);
      });
  static const std::string label_take = "poresph::resum_fluid_density::take";
  Kokkos::parallel_for(
      label_take, policy, KOKKOS_LAMBDA(int a) {
        const double neighbours_sum = sums.take(a, 0);  // taken for every particle: the copies return to zero
        if (kind(a) == kFluid) rho(a) = m(a) * kernel.value(0.0) + neighbours_sum;
      });
}

// The mass that particles [0, count) all have, owned and ghost, or 0 if
// they differ: a fixed lattice's are rho0 dx^N (PairLoopOptions::uniform_mass).
template <int Dim, class ExecSpace>
double common_mass(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P, int count) {
  if (count == 0) return 0.0;
  using Extremes = Kokkos::MinMax<double>;
  typename Extremes::value_type extremes;
  const auto m = P.m;
  static const std::string label = "poresph::common_mass";
  Kokkos::parallel_reduce(
      label, Kokkos::RangePolicy<ExecSpace>(space, 0, count),
      KOKKOS_LAMBDA(int i, typename Extremes::value_type& found) {
        found.min_val = m(i) < found.min_val ? m(i) : found.min_val;
        found.max_val = m(i) > found.max_val ? m(i) : found.max_val;
      },
      Extremes(extremes));
  const double lightest = extremes.min_val, heaviest = extremes.max_val;
  return lightest == heaviest && lightest > 0 ? lightest : 0.0;
}

}  // namespace poresph
