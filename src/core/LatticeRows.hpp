#pragma once
// Fixed particles on one lattice hold their neighbour rows without a list.
// Where every pair is an offset of the lattice stencil (core/PairGeometry.hpp),
// row a of the half list is said by two bit masks over the stencil's ids,
// one for its owned neighbours and one for its ghosts, and the neighbour at
// offset id is found through a map from lattice sites to slots:
// slot_of_site(site(a) + step(id)). That takes the list's 6 bytes an entry
// (the index and the stencil id, about 310 bytes a particle in 3D) down to
// the masks (32 bytes a particle at h = dx in 3D), the site (4) and the map
// (4 bytes a site of the process's box and halo), and the list is never
// made. The rows are visited in the stencil's order: the order of a list
// whose rows are sorted by stencil id (NeighbourList::use_stencil), whose
// sums are then the same to the bit.
#include <Kokkos_Core.hpp>

#include <cstdint>
#include <string>

#include "core/Math.hpp"
#include "core/PairGeometry.hpp"
#include "core/Vec.hpp"

namespace poresph {

// The index of the lowest set bit of a nonzero word.
KOKKOS_FORCEINLINE_FUNCTION int lowest_bit(std::uint64_t word) { return __builtin_ctzll(word); }

template <int Dim, class ExecSpace>
class LatticeRows {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using Word = std::uint64_t;
  using Stencil = LatticeStencil<Dim, MemorySpace>;
  static constexpr int kBits = 64;
  // A map of more sites than this many per slot (particles scattered over a
  // large box) costs more than 128 bytes a particle, about half a list's in
  // 2D: the list is kept. A sparse image stays below it down to porosities
  // of a few per cent (the boundary layers around its pores are particles too).
  static constexpr long long kMostSitesPerSlot = 32;

  // The rows of the owned particles [0, owned) over the slots [0, slots)
  // (owned and ghosts) that the cell list holds, within `radius`: the half
  // list's pairs (NeighbourList::listed), made as masks without the list.
  // Returns false, and holds nothing, where some pair within the radius is
  // not an offset of the stencil, or the map does not give it back (two
  // particles on one site, a box too sparse or too large to map).
  template <class Cells, class PositionView>
  bool build(const ExecSpace& space, const Cells& cells, const PositionView& x, int owned, int slots, double radius,
             const Stencil& stencil, double spacing) {
    clear();
    if (owned == 0 || stencil.size() == 0) return false;
    const double inverse_spacing = 1.0 / spacing;
    // The box of the slots' lattice coordinates.
    Kokkos::Array<double, Dim> lowest;
    long long sites = 1;
    Kokkos::Array<long long, Dim> stride;
    for (int d = 0; d < Dim; ++d) {
      static const std::string label_box = "poresph::LatticeRows::box";
      double lo = 0, hi = 0;
      Kokkos::parallel_reduce(
          label_box, Kokkos::RangePolicy<ExecSpace>(space, 0, slots),
          KOKKOS_LAMBDA(int j, double& m) { m = x(j, d) < m ? x(j, d) : m; }, Kokkos::Min<double>(lo));
      Kokkos::parallel_reduce(
          label_box, Kokkos::RangePolicy<ExecSpace>(space, 0, slots),
          KOKKOS_LAMBDA(int j, double& m) { m = x(j, d) > m ? x(j, d) : m; }, Kokkos::Max<double>(hi));
      lowest[d] = lo;
      stride[d] = sites;
      const double extent = (hi - lo) * inverse_spacing;
      if (!(extent < 1e9)) return false;
      extent_[d] = static_cast<int>(extent + 0.5) + 1;
      sites *= extent_[d];
      if (sites > kMostSitesPerSlot * slots + 1024 || sites >= (1LL << 31)) return false;
    }
    words_ = (stencil.size() + kBits - 1) / kBits;
    stencil_ = stencil;
    spacing_ = spacing;
    site_ = Kokkos::View<int*, MemorySpace>(Kokkos::view_alloc(Kokkos::WithoutInitializing, "LatticeRows::site"),
                                            owned);
    slot_of_site_ = Kokkos::View<int*, MemorySpace>("LatticeRows::slot_of_site", sites);
    bits_ = BitsView("LatticeRows::bits", owned, 2 * words_);
    step_ = Kokkos::View<int*, MemorySpace>("LatticeRows::step", stencil.size());
    const auto site = site_, slot_of_site = slot_of_site_, step = step_;
    const auto bits = bits_;
    const int words = words_;
    const auto site_of = KOKKOS_LAMBDA(int j) {
      long long s = 0;
      for (int d = 0; d < Dim; ++d)
        s += static_cast<long long>(math::floor((x(j, d) - lowest[d]) * inverse_spacing + 0.5)) * stride[d];
      return static_cast<int>(s);
    };
    static const std::string label_steps = "poresph::LatticeRows::steps";
    Kokkos::parallel_for(
        label_steps, Kokkos::RangePolicy<ExecSpace>(space, 0, stencil.size()), KOKKOS_LAMBDA(int id) {
          long long s = 0;
          for (int d = 0; d < Dim; ++d)
            s += static_cast<long long>(math::floor(stencil.separation(id, d) * inverse_spacing + 0.5)) * stride[d];
          step(id) = static_cast<int>(-s);  // the separation is x_a - x_b: the neighbour lies at minus it
        });
    static const std::string label_map = "poresph::LatticeRows::map";
    Kokkos::parallel_for(
        label_map, Kokkos::RangePolicy<ExecSpace>(space, 0, slots), KOKKOS_LAMBDA(int j) {
          const int s = site_of(j);
          slot_of_site(s) = j + 1;  // 0: no slot
          if (j < owned) site(j) = s;
        });
    // The masks, and whether they hold every pair: a pair off the stencil,
    // an offset taken twice, or a neighbour the map does not give back
    // cannot be said this way.
    static const std::string label_masks = "poresph::LatticeRows::masks";
    const double radius_sq = radius * radius;
    int wrong = 0;
    Kokkos::parallel_reduce(
        label_masks, Kokkos::RangePolicy<ExecSpace>(space, 0, owned),
        KOKKOS_LAMBDA(int a, int& bad) {
          const Vec<Dim> xa = row<Dim>(x, a);
          cells.for_each_candidate(xa, [&](int j) {
            const Vec<Dim> r = xa - row<Dim>(x, j);
            if (!(j > a && dot(r, r) < radius_sq)) return;  // NeighbourList::listed
            const int id = stencil.id_of(r);
            if (id < 0) {
              ++bad;
              return;
            }
            const int column = (j < owned ? 0 : words) + id / kBits;
            const Word bit = Word(1) << (id % kBits);
            bad += (bits(a, column) & bit) != 0;
            bits(a, column) |= bit;
            bad += slot_of_site(site(a) + step(id)) != j + 1;
          });
        },
        wrong);
    space.fence();
    if (wrong != 0) {
      clear();
      return false;
    }
    return true;
  }

  // The pairs the rows hold, and those with both ends owned.
  long long pairs(const ExecSpace& space, bool owned_only) const {
    const auto bits = bits_;
    const int words = words_;
    long long count = 0;
    static const std::string label = "poresph::LatticeRows::pairs";
    Kokkos::parallel_reduce(
        label, Kokkos::RangePolicy<ExecSpace>(space, 0, static_cast<int>(bits.extent(0))),
        KOKKOS_LAMBDA(int a, long long& n) {
          for (int c = 0; c < (owned_only ? words : 2 * words); ++c) n += __builtin_popcountll(bits(a, c));
        },
        count);
    return count;
  }

  // f(b, r) for row a's neighbours b at r = x_a - x_b: owned ones, then
  // ghosts, each in the stencil's order (the pair loop's order).
  template <class F>
  KOKKOS_INLINE_FUNCTION void for_each(int a, F&& f) const {
    for (int c = 0; c < 2 * words_; ++c)
      for (Word word = bits_(a, c); word != 0; word &= word - 1) {
        const int id = (c % words_) * kBits + lowest_bit(word);
        Vec<Dim> r;
        for (int d = 0; d < Dim; ++d) r[d] = separation(id, d);
        f(neighbour(a, id), r);
      }
  }

  void clear() {
    site_ = {};
    slot_of_site_ = {};
    bits_ = {};
    step_ = {};
    words_ = 0;
  }
  bool built() const { return words_ > 0; }

  KOKKOS_INLINE_FUNCTION int words() const { return words_; }
  // Row a's owned neighbours (Owned) or ghosts, ids [kBits w, kBits (w + 1)).
  template <bool Owned>
  KOKKOS_FORCEINLINE_FUNCTION Word bits(int a, int w) const {
    return bits_(a, Owned ? w : words_ + w);
  }
  // The slot of row a's neighbour at stencil offset id (a bit of its masks).
  KOKKOS_FORCEINLINE_FUNCTION int neighbour(int a, int id) const { return neighbour_of_site(site_(a), id); }
  KOKKOS_FORCEINLINE_FUNCTION int site(int a) const { return site_(a); }
  KOKKOS_FORCEINLINE_FUNCTION int neighbour_of_site(int site, int id) const {
    return slot_of_site_(site + step_(id)) - 1;
  }
  // The sites of the map (the box of the slots' lattice points), the slot at
  // a site (-1: none), and the site difference of stencil offset id (a
  // neighbour lies at site(a) + step(id)).
  int sites() const { return static_cast<int>(slot_of_site_.extent(0)); }
  // The map's box: sites along axis d (axis 0 the fastest), and the spacing.
  int extent(int d) const { return extent_[d]; }
  double spacing() const { return spacing_; }
  KOKKOS_FORCEINLINE_FUNCTION int slot_at(int site) const { return slot_of_site_(site) - 1; }
  KOKKOS_FORCEINLINE_FUNCTION int step(int id) const { return step_(id); }
  const Stencil& stencil() const { return stencil_; }
  KOKKOS_FORCEINLINE_FUNCTION double separation(int id, int d) const { return stencil_.separation(id, d); }
  KOKKOS_FORCEINLINE_FUNCTION double of_distance(int id) const { return stencil_.of_distance(id); }

 private:
  using BitsView = Kokkos::View<Word**, Kokkos::LayoutRight, MemorySpace>;
  Kokkos::View<int*, MemorySpace> site_;          // owned slot -> its site
  Kokkos::View<int*, MemorySpace> slot_of_site_;  // site -> slot + 1, 0 where no slot
  Kokkos::View<int*, MemorySpace> step_;          // stencil id -> its site difference
  BitsView bits_;                                 // [owned mask words | ghost mask words] per row
  Stencil stencil_;
  int words_ = 0;
  Kokkos::Array<int, Dim> extent_{};
  double spacing_ = 0;
};

}  // namespace poresph
