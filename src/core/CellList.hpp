#pragma once
// Cell list for the neighbour search: a regular grid of cells no smaller than
// the kernel support (3h) over a box that already contains every particle a
// search can reach (owned particles plus ghosts). Periodicity is not handled
// here: periodic images arrive as ghost particles from the halo layer, so the
// search is the same on one process and on many.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/Math.hpp"
#include "core/Vec.hpp"

namespace poresph {

template <int Dim>
struct CellGrid {
  double lo[Dim];
  double inv_cell_size[Dim];
  int count[Dim];

  KOKKOS_INLINE_FUNCTION int coordinate(double x, int d) const {
    int c = static_cast<int>(math::floor((x - lo[d]) * inv_cell_size[d]));
    return c < 0 ? 0 : (c >= count[d] ? count[d] - 1 : c);
  }
  KOKKOS_INLINE_FUNCTION int flat(const int (&c)[Dim]) const {
    int k = c[Dim - 1];
    for (int d = Dim - 2; d >= 0; --d) k = k * count[d] + c[d];
    return k;
  }
  int cells() const {
    int n = 1;
    for (int d = 0; d < Dim; ++d) n *= count[d];
    return n;
  }
};

template <int Dim, class ExecSpace>
class CellList {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using IndexView = Kokkos::View<int*, MemorySpace>;

  // Bins particles [0, n) of positions x into cells of side >= min_cell_size
  // covering [lo, hi]. Particles outside the box go to the nearest edge cell.
  template <class PositionView>
  void build(const ExecSpace& space, const PositionView& x, int n, const Vec<Dim>& lo, const Vec<Dim>& hi,
             double min_cell_size) {
    for (int d = 0; d < Dim; ++d) {
      const double extent = hi[d] - lo[d];
      if (!(extent > 0.0)) throw std::invalid_argument("CellList: empty box");
      grid_.lo[d] = lo[d];
      grid_.count[d] = std::max(1, static_cast<int>(std::floor(extent / min_cell_size)));
      grid_.inv_cell_size[d] = grid_.count[d] / extent;
    }
    const int ncells = grid_.cells();
    if (static_cast<int>(cell_start_.extent(0)) < ncells + 1) {
      cell_start_ = IndexView("CellList::cell_start", ncells + 1);
      fill_ = IndexView("CellList::fill", ncells);
    }
    if (static_cast<int>(sorted_.extent(0)) < n) {
      sorted_ = IndexView("CellList::sorted", n + n / 4);
      cell_of_ = IndexView("CellList::cell_of", n + n / 4);
    }
    // A kernel, not deep_copy(view, 0): Kokkos 3.4 builds a label string for that fill at every call.
    {
      static const std::string label_clear = "poresph::CellList::clear";
      const auto start = cell_start_;
      const auto fill = fill_;
      Kokkos::parallel_for(
          label_clear, Kokkos::RangePolicy<ExecSpace>(space, 0, ncells + 1), KOKKOS_LAMBDA(int k) {
            start(k) = 0;
            if (k < ncells) fill(k) = 0;
          });
    }

    const auto grid = grid_;
    const auto cell_of = cell_of_;
    const auto start = cell_start_;
    const auto sorted = sorted_;
    static const std::string label_bin = "poresph::CellList::bin";
    Kokkos::parallel_for(
        label_bin, Kokkos::RangePolicy<ExecSpace>(space, 0, n), KOKKOS_LAMBDA(int i) {
          int c[Dim];
          for (int d = 0; d < Dim; ++d) c[d] = grid.coordinate(x(i, d), d);
          const int k = grid.flat(c);
          cell_of(i) = k;
          Kokkos::atomic_increment(&start(k + 1));
        });
    static const std::string label_offsets = "poresph::CellList::offsets";
    Kokkos::parallel_scan(
        label_offsets, Kokkos::RangePolicy<ExecSpace>(space, 0, ncells + 1),
        KOKKOS_LAMBDA(int k, int& running, bool final) {
          running += start(k);
          if (final) start(k) = running;
        });
    // start(k) now holds the end of cell k-1, i.e. the beginning of cell k.
    const auto fill = fill_;
    static const std::string label_fill = "poresph::CellList::fill";
    Kokkos::parallel_for(
        label_fill, Kokkos::RangePolicy<ExecSpace>(space, 0, n), KOKKOS_LAMBDA(int i) {
          const int k = cell_of(i);
          sorted(start(k) + Kokkos::atomic_fetch_add(&fill(k), 1)) = i;
        });
    // Threads fill a cell in any order; sorting each cell by index makes the
    // neighbour order, and so every floating-point sum, independent of the backend.
    static const std::string label_order = "poresph::CellList::order";
    Kokkos::parallel_for(
        label_order, Kokkos::RangePolicy<ExecSpace>(space, 0, ncells), KOKKOS_LAMBDA(int k) {
          for (int a = start(k) + 1; a < start(k + 1); ++a) {
            const int key = sorted(a);
            int b = a - 1;
            while (b >= start(k) && sorted(b) > key) {
              sorted(b + 1) = sorted(b);
              --b;
            }
            sorted(b + 1) = key;
          }
        });
    space.fence();
  }

  // Calls f(j) for every particle j in the cells around position xi
  // (3 x 3 in 2D, 3 x 3 x 3 in 3D); f filters by distance.
  template <class F>
  KOKKOS_INLINE_FUNCTION void for_each_candidate(const Vec<Dim>& xi, F&& f) const {
    int centre[Dim], lo[Dim], hi[Dim];
    for (int d = 0; d < Dim; ++d) {
      centre[d] = grid_.coordinate(xi[d], d);
      lo[d] = centre[d] > 0 ? centre[d] - 1 : 0;
      hi[d] = centre[d] + 1 < grid_.count[d] ? centre[d] + 1 : grid_.count[d] - 1;
    }
    int c[Dim];
    if constexpr (Dim == 2) {
      for (c[1] = lo[1]; c[1] <= hi[1]; ++c[1])
        for (c[0] = lo[0]; c[0] <= hi[0]; ++c[0]) visit_cell(grid_.flat(c), f);
    } else {
      for (c[2] = lo[2]; c[2] <= hi[2]; ++c[2])
        for (c[1] = lo[1]; c[1] <= hi[1]; ++c[1])
          for (c[0] = lo[0]; c[0] <= hi[0]; ++c[0]) visit_cell(grid_.flat(c), f);
    }
  }

  const CellGrid<Dim>& grid() const { return grid_; }

 private:
  template <class F>
  KOKKOS_INLINE_FUNCTION void visit_cell(int k, F& f) const {
    const int end = cell_start_(k + 1);
    for (int a = cell_start_(k); a < end; ++a) f(sorted_(a));
  }

  CellGrid<Dim> grid_{};
  IndexView cell_start_, sorted_, cell_of_, fill_;
};

}  // namespace poresph
