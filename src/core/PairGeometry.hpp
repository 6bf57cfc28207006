#pragma once
// The geometry of a fixed arrangement's pairs: for each entry k of a pair
// list (the neighbour list, the wall-pressure list), the separation
// r = x_a - x_b and one function of |r| (F = (1/r) dW/dr for the pair loop,
// W for the wall pressure). Fixed particles never leave their lattice, so
// every separation is a lattice offset n dx (n an integer vector) of a short
// list, the same for every particle: the entries then hold a 2-byte stencil
// id into one table of the offsets' r and F, computed once from the kernel,
// instead of Dim + 1 doubles each (in 3D about 57 entries a particle, 1.8 kB
// of the 3.1 kB a particle took; docs/performance.md). Where some pair is not
// a lattice offset (particles pushed off the lattice, a periodic cell that is
// a whole number of spacings only to 1e-6), each entry keeps its own r and F
// as before: the per-pair cache is the fallback, and moving particles
// evaluate the geometry in the pair loop and have neither.
#include <Kokkos_Core.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/Math.hpp"
#include "core/Vec.hpp"

namespace poresph {

// Every lattice offset r = n * spacing (n an integer vector, n != 0) with
// |r| within a radius, in one fixed order (n_x varying fastest, as the
// lattice stores its points: a row's neighbours come in the order of their
// slots), with r and
// of_distance(|r|): computed on the host from the spacing and the kernel
// alone, so every process holds the same table to the bit, whatever its
// particles.
template <int Dim, class MemorySpace>
class LatticeStencil {
 public:
  using Id = std::uint16_t;
  // Ids must fit an Id; a larger stencil (a support of more than about 25
  // spacings in 3D) is left empty, and every pair then takes the per-pair cache.
  static constexpr int kMostOffsets = 65536;
  // How far, in spacings per axis, a separation may be from a lattice offset
  // and still count as one. Lattice coordinates are (i + 1/2) dx, correct to
  // a few units in the last place of the coordinate, so the separations of a
  // lattice with up to 10^4 points across are offsets to about 1e-12
  // spacings. Across the periodic seam they are off by what the cell side
  // misses a whole number of spacings by: a spacing given to ten digits
  // (0.1 / 120 as 0.0008333333333) leaves 4.8e-9 spacings at 120 points
  // across, which 1e-9 refused, so that such a cell lost its lattice rows
  // and its steady solve took ten times as long (docs/method.md). Particles
  // moved off the lattice on purpose are further than 1e-6.
  static constexpr double kTolerance = 1e-7;

  LatticeStencil() = default;

  // The offsets within `radius` (the pair list's reach: its entries are
  // closer) and a little beyond, for separations that round either side.
  template <class OfDistance>
  LatticeStencil(const std::array<double, Dim>& spacing, double radius, const OfDistance& of_distance) {
    long long dense = 1;
    for (int d = 0; d < Dim; ++d) {
      inverse_spacing_[d] = 1.0 / spacing[d];
      reach_[d] = static_cast<int>(std::floor(radius * (1 + 1e-6) / spacing[d]));
      dense *= 2 * reach_[d] + 1;
    }
    const double radius_sq = radius * radius * (1 + 4e-6);
    std::vector<int> id_of_dense(dense, -1);
    std::vector<std::array<double, Dim + 1>> rows;
    for (long long c = 0; c < dense; ++c) {
      // c = sum over d of (n_d + reach_d) times the sizes of the axes before d.
      std::array<double, Dim + 1> row{};
      double r_sq = 0;
      bool zero = true;
      for (int d = 0, rest = static_cast<int>(c); d < Dim; rest /= 2 * reach_[d] + 1, ++d) {
        const int n = rest % (2 * reach_[d] + 1) - reach_[d];
        row[d] = n * spacing[d];
        r_sq += row[d] * row[d];
        zero = zero && n == 0;
      }
      if (zero || r_sq > radius_sq) continue;
      row[Dim] = of_distance(std::sqrt(r_sq));
      id_of_dense[c] = static_cast<int>(rows.size());
      rows.push_back(row);
    }
    if (static_cast<long long>(rows.size()) > kMostOffsets) return;  // empty: no separation is found in it
    table_ = TableView("LatticeStencil::table", rows.size());
    lookup_ = Kokkos::View<int*, MemorySpace>("LatticeStencil::lookup", dense);
    auto table = Kokkos::create_mirror_view(table_);
    auto lookup = Kokkos::create_mirror_view(lookup_);
    for (std::size_t k = 0; k < rows.size(); ++k)
      for (int c = 0; c <= Dim; ++c) table(k, c) = rows[k][c];
    for (long long c = 0; c < dense; ++c) lookup(c) = id_of_dense[c];
    Kokkos::deep_copy(table_, table);
    Kokkos::deep_copy(lookup_, lookup);
  }

  int size() const { return static_cast<int>(table_.extent(0)); }
  KOKKOS_INLINE_FUNCTION double separation(int id, int d) const { return table_(id, d); }
  KOKKOS_INLINE_FUNCTION double of_distance(int id) const { return table_(id, Dim); }

  // The id of the offset r lies on (to kTolerance spacings per axis), or -1
  // where r is no offset of the table.
  KOKKOS_INLINE_FUNCTION int id_of(const Vec<Dim>& r) const {
    if (lookup_.extent(0) == 0) return -1;
    long long dense = 0;
    for (int d = Dim - 1; d >= 0; --d) {
      const double q = r[d] * inverse_spacing_[d];
      const double n = math::floor(q + 0.5);
      if (!(math::fabs(q - n) <= kTolerance) || !(math::fabs(n) <= reach_[d])) return -1;
      dense = dense * (2 * reach_[d] + 1) + (static_cast<int>(n) + reach_[d]);
    }
    return lookup_(dense);
  }

 private:
  using TableView = Kokkos::View<double* [Dim + 1], Kokkos::LayoutRight, MemorySpace>;
  TableView table_;
  Kokkos::View<int*, MemorySpace> lookup_;  // dense offset index -> id, or -1 beyond the radius
  Kokkos::Array<double, Dim> inverse_spacing_{};
  Kokkos::Array<int, Dim> reach_{};
};

// The geometry of a pair list's entries, by entry: from the stencil (ids),
// or from a per-entry cache (the fallback), or none (moving particles, which
// evaluate it in the pair loop).
template <int Dim, class ExecSpace>
class PairGeometry {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using Stencil = LatticeStencil<Dim, MemorySpace>;

  // For rows i < rows of a list in CSR form (entries [offsets(i),
  // offsets(i+1)) naming particles by indices(k)): each entry's stencil id.
  // Returns whether every entry is an offset of the stencil. The geometry is
  // not in use until use_stencil() (every process must agree first) or cache().
  template <class IndexView, class PositionView>
  bool find_stencil_ids(const ExecSpace& space, const std::string& label, const IndexView& offsets,
                        const IndexView& indices, const PositionView& x, int rows, long long entries,
                        const Stencil& stencil) {
    cache_ = CacheView();
    ids_ = IdView(Kokkos::view_alloc(Kokkos::WithoutInitializing, label + "::ids"), entries);
    const auto ids = ids_;
    int off_lattice = 0;
    Kokkos::parallel_reduce(
        label, Kokkos::RangePolicy<ExecSpace>(space, 0, rows),
        KOKKOS_LAMBDA(int i, int& off) {
          const Vec<Dim> xi = row<Dim>(x, i);
          for (int k = offsets(i); k < offsets(i + 1); ++k) {
            const int id = stencil.id_of(xi - row<Dim>(x, indices(k)));
            off += id < 0;
            ids(k) = static_cast<typename Stencil::Id>(id < 0 ? 0 : id);
          }
        },
        off_lattice);
    mode_ = Mode::None;
    return off_lattice == 0;
  }
  // The ids found are the geometry, read from `stencil` (the one they were found in).
  void use_stencil(const Stencil& stencil) {
    stencil_ = stencil;
    mode_ = Mode::Stencil;
  }

  // The fallback: each entry's separation r = x_i - x_indices(k) and
  // of_distance(|r|), Dim + 1 doubles an entry.
  template <class IndexView, class PositionView, class OfDistance>
  void cache(const ExecSpace& space, const std::string& label, const IndexView& offsets, const IndexView& indices,
             const PositionView& x, int rows, long long entries, const OfDistance& of_distance) {
    ids_ = IdView();
    if (static_cast<long long>(cache_.extent(0)) < entries) cache_ = CacheView(label + "::cache", entries);
    const auto geometry = cache_;
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space, 0, rows), KOKKOS_LAMBDA(int i) {
          const Vec<Dim> xi = row<Dim>(x, i);
          for (int k = offsets(i); k < offsets(i + 1); ++k) {
            const Vec<Dim> r = xi - row<Dim>(x, indices(k));
            for (int d = 0; d < Dim; ++d) geometry(k, d) = r[d];
            geometry(k, Dim) = of_distance(math::sqrt(dot(r, r)));
          }
        });
    space.fence();
    mode_ = Mode::Cache;
  }

  // Each entry's stencil id (after find_stencil_ids).
  const Kokkos::View<typename Stencil::Id*, MemorySpace>& ids() const { return ids_; }

  void clear() { mode_ = Mode::None; }
  bool has_geometry() const { return mode_ != Mode::None; }
  bool on_stencil() const { return mode_ == Mode::Stencil; }

  KOKKOS_INLINE_FUNCTION double separation(int k, int d) const {
    return mode_ == Mode::Stencil ? stencil_.separation(ids_(k), d) : cache_(k, d);
  }
  KOKKOS_INLINE_FUNCTION double of_distance(int k) const {
    return mode_ == Mode::Stencil ? stencil_.of_distance(ids_(k)) : cache_(k, Dim);
  }

 private:
  enum class Mode { None, Stencil, Cache };
  using IdView = Kokkos::View<typename Stencil::Id*, MemorySpace>;
  using CacheView = Kokkos::View<double* [Dim + 1], Kokkos::LayoutRight, MemorySpace>;
  Mode mode_ = Mode::None;
  IdView ids_;
  CacheView cache_;
  Stencil stencil_;
};

}  // namespace poresph
