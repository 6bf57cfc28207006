#pragma once
// The sum of term(i) over [0, n) as a labelled Kokkos reduction over blocks
// of kBlockSummands, each block summed in kSumLanes running sums (lane k
// takes the summands k, k + kSumLanes, ...), which the compiler keeps in
// one vector register.
//
// Why not a reduction over i: each summand is then added to one running
// sum, a chain of dependent additions the compiler may not reorder, and
// with the Serial backend that sum lives in memory (a store and a load a
// summand). The Krylov solvers' inner products took 10 % of a steady solve
// that way (docs/steady_solver.md, "Sums in lanes"). Blocked, the result is
// the same sum in another order: it differs from the plain one in the last
// bits, and is the same on every run (a block's order is fixed).
//
// A term must be arithmetic, without a branch: Debian's GCC 12.2 at -O3
// with AVX2 vectorises a conditional term (c ? x : 0.0) in these lanes
// into wrong sums (docs/building.md); a product, as in the inner products,
// comes out right (test BlockedSumIsTheSumAtEveryLength).
#include <Kokkos_Core.hpp>

#include <string>

namespace poresph {

constexpr int kSumLanes = 8;
constexpr int kBlockSummands = 8 * kSumLanes;

template <class ExecSpace, class Term>
double blocked_sum(const ExecSpace& space, const std::string& label, long long n, const Term& term) {
  const long long blocks = (n + kBlockSummands - 1) / kBlockSummands;
  double total = 0;
  Kokkos::parallel_reduce(
      label, Kokkos::RangePolicy<ExecSpace>(space, 0, blocks),
      KOKKOS_LAMBDA(long long block, double& sum) {
        const long long first = block * kBlockSummands;
        double lane[kSumLanes] = {};
        if (first + kBlockSummands <= n) {
          for (int j = 0; j < kBlockSummands; j += kSumLanes)
            for (int k = 0; k < kSumLanes; ++k) lane[k] += term(first + j + k);
        } else {
          for (long long i = first; i < n; ++i) lane[(i - first) % kSumLanes] += term(i);
        }
        double block_sum = 0;
        for (int k = 0; k < kSumLanes; ++k) block_sum += lane[k];
        sum += block_sum;
      },
      total);
  return total;
}

}  // namespace poresph
