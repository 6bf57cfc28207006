#pragma once
// Verlet neighbour list: for each owned particle, the particles (owned or
// ghost) within the support plus a skin, found through the cell list. Kept
// over many steps while no particle has moved more than half the skin, so
// the pair loop walks a short contiguous list instead of 3^Dim cells.
//
// On the Serial backend the list is a half list: a pair of owned particles
// is listed once (under the smaller index) and the pair loop updates both,
// which halves the pair work; nothing runs concurrently, so the writes to
// the neighbour cannot race. Threaded backends list every neighbour of each
// particle, which then writes only its own rates (no atomics, no scatter).
// Ghosts are listed in full either way: a ghost's owner evaluates the pair
// for its own particle.
#include <Kokkos_Core.hpp>

#include <type_traits>

#include "core/CellList.hpp"
#include "core/Vec.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
class NeighbourList {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using IndexView = Kokkos::View<int*, MemorySpace>;
  static constexpr bool kHalf = std::is_same_v<ExecSpace, Kokkos::Serial>;

  template <class PositionView>
  void build(const ExecSpace& space, const CellList<Dim, ExecSpace>& cells, const PositionView& x, int owned,
             double radius) {
    if (static_cast<int>(offsets_.extent(0)) < owned + 1) offsets_ = IndexView("NeighbourList::offsets", owned + owned / 4 + 1);
    const auto offsets = offsets_;
    const double radius_sq = radius * radius;
    static const std::string label_count = "poresph::NeighbourList::count";
    Kokkos::parallel_for(
        label_count, Kokkos::RangePolicy<ExecSpace>(space, 0, owned), KOKKOS_LAMBDA(int i) {
          const Vec<Dim> xi = row<Dim>(x, i);
          int n = 0;
          cells.for_each_candidate(xi, [&](int j) {
            const Vec<Dim> r = xi - row<Dim>(x, j);
            n += (listed(i, j) && dot(r, r) < radius_sq);
          });
          offsets(i + 1) = n;
        });
    int total = 0;
    static const std::string label_offsets = "poresph::NeighbourList::offsets";
    Kokkos::parallel_scan(
        label_offsets, Kokkos::RangePolicy<ExecSpace>(space, 0, owned + 1),
        KOKKOS_LAMBDA(int i, int& running, bool final) {
          const int n = i == 0 ? 0 : offsets(i);
          running += n;
          if (final) offsets(i) = running;
        },
        total);
    if (static_cast<int>(indices_.extent(0)) < total) indices_ = IndexView("NeighbourList::indices", total + total / 4);
    const auto indices = indices_;
    static const std::string label_fill = "poresph::NeighbourList::fill";
    Kokkos::parallel_for(
        label_fill, Kokkos::RangePolicy<ExecSpace>(space, 0, owned), KOKKOS_LAMBDA(int i) {
          const Vec<Dim> xi = row<Dim>(x, i);
          int k = offsets(i);
          cells.for_each_candidate(xi, [&](int j) {
            const Vec<Dim> r = xi - row<Dim>(x, j);
            if (listed(i, j) && dot(r, r) < radius_sq) indices(k++) = j;
          });
        });
    space.fence();
    pairs_ = total;
    // Neighbours per particle as a full list would have them: a half list
    // holds each pair of owned particles once.
    long long neighbours = total;
    if constexpr (kHalf) {
      static const std::string label_owned_pairs = "poresph::NeighbourList::owned_pairs";
      long long owned_pairs = 0;
      const auto indices_view = indices_;
      Kokkos::parallel_reduce(
          label_owned_pairs, Kokkos::RangePolicy<ExecSpace>(space, 0, total),
          KOKKOS_LAMBDA(int k, long long& n) { n += indices_view(k) < owned; }, owned_pairs);
      neighbours += owned_pairs;
    }
    neighbours_per_particle_ = owned > 0 ? static_cast<double>(neighbours) / owned : 0.0;
  }

  // Whether owned particle i lists particle j (within range). Ghosts come
  // after the owned particles, so j > i lists every ghost.
  KOKKOS_INLINE_FUNCTION static bool listed(int i, int j) {
    if constexpr (kHalf) return j > i;
    else return j != i;
  }

  // Neighbours of owned particle i are neighbour(k) for k in [begin(i), end(i)).
  // (A plain loop, not a callback: GCC does not inline a per-pair lambda.)
  KOKKOS_INLINE_FUNCTION int begin(int i) const { return offsets_(i); }
  KOKKOS_INLINE_FUNCTION int end(int i) const { return offsets_(i + 1); }
  KOKKOS_INLINE_FUNCTION int neighbour(int k) const { return indices_(k); }

  long long pairs() const { return pairs_; }  // entries of the list
  double neighbours_per_particle() const { return neighbours_per_particle_; }

 private:
  IndexView offsets_, indices_;
  long long pairs_ = 0;
  double neighbours_per_particle_ = 0;
};

}  // namespace poresph
