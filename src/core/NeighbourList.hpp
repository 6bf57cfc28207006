#pragma once
// Verlet neighbour list: for each owned particle, the particles (owned or
// ghost) within the support plus a skin, found through the cell list. Kept
// over many steps while no particle has moved more than half the skin, so
// the pair loop walks a short contiguous list instead of 3^Dim cells.
//
// It is a half list: a pair of owned particles is listed once (under the
// smaller index) and the pair loop adds to both, which halves the pair work;
// threads add into separate copies of the sums (core/PairSums.hpp). A
// ghost is listed by every owned particle near it: its owner evaluates the
// pair for its own particle. Each particle's owned neighbours come first and
// its ghosts after them, so the pair loop knows which pairs have a second
// end to update without a test per pair.
//
// Fixed particles on one lattice hold no list: their rows are masks over
// the lattice stencil (build_lattice_rows, core/LatticeRows.hpp).
#include <Kokkos_Core.hpp>

#include <string>

#include "core/CellList.hpp"
#include "core/LatticeRows.hpp"
#include "core/Math.hpp"
#include "core/PairGeometry.hpp"
#include "core/Vec.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
class NeighbourList {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using IndexView = Kokkos::View<int*, MemorySpace>;

  // room_to_grow: a quarter more entries than found, for the rebuilds of
  // moving particles; a list built once (fixed particles) holds what it has.
  template <class PositionView>
  void build(const ExecSpace& space, const CellList<Dim, ExecSpace>& cells, const PositionView& x, int owned,
             double radius, bool room_to_grow = true) {
    if (static_cast<int>(offsets_.extent(0)) < owned + 1) {
      offsets_ = IndexView("NeighbourList::offsets", owned + owned / 4 + 1);
      ghosts_begin_ = IndexView("NeighbourList::ghosts_begin", owned + owned / 4 + 1);
    }
    const auto offsets = offsets_, ghosts_begin = ghosts_begin_;
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
    if (static_cast<int>(indices_.extent(0)) < total)
      indices_ = IndexView("NeighbourList::indices", room_to_grow ? total + total / 4 : total);
    const auto indices = indices_;
    static const std::string label_fill = "poresph::NeighbourList::fill";
    Kokkos::parallel_for(
        label_fill, Kokkos::RangePolicy<ExecSpace>(space, 0, owned), KOKKOS_LAMBDA(int i) {
          const Vec<Dim> xi = row<Dim>(x, i);
          // Owned neighbours from the front, ghosts from the back; they meet.
          int front = offsets(i), back = offsets(i + 1);
          cells.for_each_candidate(xi, [&](int j) {
            const Vec<Dim> r = xi - row<Dim>(x, j);
            if (listed(i, j) && dot(r, r) < radius_sq) {
              if (j < owned) indices(front++) = j;
              else indices(--back) = j;
            }
          });
          ghosts_begin(i) = front;
        });
    space.fence();
    pairs_ = total;
    rows_ = owned;
    geometry_.clear();
    lattice_rows_.clear();
    // Neighbours per particle as a full list would have them: the half list
    // holds each pair of owned particles once.
    static const std::string label_owned_pairs = "poresph::NeighbourList::owned_pairs";
    long long owned_pairs = 0;
    Kokkos::parallel_reduce(
        label_owned_pairs, Kokkos::RangePolicy<ExecSpace>(space, 0, owned),
        KOKKOS_LAMBDA(int i, long long& n) { n += ghosts_begin(i) - offsets(i); }, owned_pairs);
    neighbours_per_particle_ = owned > 0 ? static_cast<double>(total + owned_pairs) / owned : 0.0;
  }

  // Whether owned particle i lists particle j (within range). Ghosts come
  // after the owned particles, so j > i lists every ghost.
  KOKKOS_INLINE_FUNCTION static bool listed(int i, int j) { return j > i; }

  // Neighbours of owned particle i are neighbour(k) for k in [begin(i), end(i)):
  // owned particles in [begin(i), ghosts_begin(i)), ghosts in [ghosts_begin(i), end(i)).
  // (A plain loop, not a callback: GCC does not inline a per-pair lambda.)
  KOKKOS_INLINE_FUNCTION int begin(int i) const { return offsets_(i); }
  KOKKOS_INLINE_FUNCTION int ghosts_begin(int i) const { return ghosts_begin_(i); }
  KOKKOS_INLINE_FUNCTION int end(int i) const { return offsets_(i + 1); }
  KOKKOS_INLINE_FUNCTION int neighbour(int k) const { return indices_(k); }

  // Fixed particles: the separation r_ab and F_ab = (1/r) dW/dr of every
  // entry, found once after the build, so that the pair loop streams them
  // instead of gathering positions and evaluating the kernel at each step:
  // from the lattice stencil where every entry is one of its offsets
  // (find_stencil_ids, then use_stencil once every process has found so),
  // else cached per entry (cache_geometry, core/PairGeometry.hpp).
  // The list must hold no entry beyond the kernel's support (no skin).
  template <class PositionView>
  bool find_stencil_ids(const ExecSpace& space, const PositionView& x, int owned,
                        const LatticeStencil<Dim, MemorySpace>& stencil) {
    static const std::string label = "poresph::NeighbourList::find_stencil_ids";
    return geometry_.find_stencil_ids(space, label, offsets_, indices_, x, owned, pairs_, stencil);
  }
  // Each row's owned neighbours, then its ghosts, are put in the stencil's
  // order: the order of rows kept as masks (build_lattice_rows), so that a
  // list and rows give the pair loop its pairs in the same order, and the
  // same sums to the bit.
  void use_stencil(const ExecSpace& space, const LatticeStencil<Dim, MemorySpace>& stencil) {
    geometry_.use_stencil(stencil);
    const auto offsets = offsets_, ghosts_begin = ghosts_begin_, indices = indices_;
    const auto ids = geometry_.ids();
    static const std::string label = "poresph::NeighbourList::sort_rows_by_stencil_id";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space, 0, rows_), KOKKOS_LAMBDA(int i) {
          const int parts[3] = {offsets(i), ghosts_begin(i), offsets(i + 1)};
          for (int part = 0; part < 2; ++part)
            for (int k = parts[part] + 1; k < parts[part + 1]; ++k) {  // insertion sort: rows are short
              const auto id = ids(k);
              const int index = indices(k);
              int m = k;
              for (; m > parts[part] && ids(m - 1) > id; --m) ids(m) = ids(m - 1), indices(m) = indices(m - 1);
              ids(m) = id, indices(m) = index;
            }
        });
    space.fence();
  }
  // Fixed particles on one lattice: the rows as masks over the stencil and
  // a map of the lattice's sites (core/LatticeRows.hpp), made from the cell
  // list without the list; slots: the owned particles and ghosts. Returns
  // whether every pair is an offset of the stencil (else nothing is held,
  // and build() makes the list).
  template <class PositionView>
  bool build_lattice_rows(const ExecSpace& space, const CellList<Dim, ExecSpace>& cells, const PositionView& x,
                          int owned, int slots, double radius, const LatticeStencil<Dim, MemorySpace>& stencil,
                          double spacing) {
    offsets_ = IndexView(), ghosts_begin_ = IndexView(), indices_ = IndexView();
    geometry_ = PairGeometry<Dim, ExecSpace>();
    pairs_ = 0, rows_ = 0, neighbours_per_particle_ = 0;
    if (!lattice_rows_.build(space, cells, x, owned, slots, radius, stencil, spacing)) return false;
    rows_ = owned;
    pairs_ = lattice_rows_.pairs(space, false);
    neighbours_per_particle_ = static_cast<double>(pairs_ + lattice_rows_.pairs(space, true)) / owned;
    return true;
  }
  // f(b, r) for each entry of owned particle a's row, b the neighbour and
  // r = x_a - x_b, in the pair loop's order; fixed particles (the list has
  // its geometry, or is rows).
  template <class F>
  KOKKOS_INLINE_FUNCTION void for_each_entry(int a, F&& f) const {
    if (lattice_rows_.built()) return lattice_rows_.for_each(a, f);
    for (int k = begin(a); k < end(a); ++k) {
      Vec<Dim> r;
      for (int d = 0; d < Dim; ++d) r[d] = separation(k, d);
      f(neighbour(k), r);
    }
  }
  bool on_lattice_rows() const { return lattice_rows_.built(); }
  const LatticeRows<Dim, ExecSpace>& lattice_rows() const { return lattice_rows_; }
  template <class PositionView, class Kernel>
  void cache_geometry(const ExecSpace& space, const PositionView& x, int owned, const Kernel& kernel) {
    static const std::string label = "poresph::NeighbourList::cache_geometry";
    geometry_.cache(space, label, offsets_, indices_, x, owned, pairs_,
                    KOKKOS_LAMBDA(double r) { return kernel.derivative_over_r(r); });
  }
  bool has_geometry() const { return geometry_.has_geometry() || lattice_rows_.built(); }
  bool on_stencil() const { return geometry_.on_stencil() || lattice_rows_.built(); }
  KOKKOS_INLINE_FUNCTION double separation(int k, int d) const { return geometry_.separation(k, d); }
  KOKKOS_INLINE_FUNCTION double derivative_over_r(int k) const { return geometry_.of_distance(k); }

  long long pairs() const { return pairs_; }  // entries of the list
  double neighbours_per_particle() const { return neighbours_per_particle_; }

 private:
  IndexView offsets_, ghosts_begin_, indices_;
  PairGeometry<Dim, ExecSpace> geometry_;
  LatticeRows<Dim, ExecSpace> lattice_rows_;
  int rows_ = 0;  // owned particles at the build
  long long pairs_ = 0;
  double neighbours_per_particle_ = 0;
};

}  // namespace poresph
