// The lattice stencil of fixed particles' pairs (core/PairGeometry.hpp): on
// a lattice with periodic ghosts, in 2D and 3D, every entry of the pair list
// and of the wall-pressure list is one of the stencil's offsets, and the
// stencil's r and F (W for the walls) are the per-entry cache's to
// round-off; a particle off the lattice sends both lists to the per-entry
// cache (the scene-level check is in test_fixed_particles).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "TestSpaces.hpp"
#include "core/CellList.hpp"
#include "core/Kernel.hpp"
#include "core/NeighbourList.hpp"
#include "core/PairGeometry.hpp"
#include "core/Particles.hpp"
#include "parallel/Halo.hpp"
#include "physics/Density.hpp"
#include "physics/PairRates.hpp"
#include "physics/WallPressure.hpp"

namespace poresph {
namespace {

template <class Space>
class LatticeStencilTest : public ::testing::Test {};
TYPED_TEST_SUITE(LatticeStencilTest, testing::ExecutionSpaces);

// The largest difference between two lists' geometry over their entries:
// of the separations (in spacings) and of the scalar (relative to its
// largest magnitude). An entry of list a is compared with the entry of the
// same row and neighbour in list b (the pair list on the stencil keeps its
// rows in the stencil's order); unmatched counts the entries b lacks.
struct Differences {
  double separation = 0, scalar = 0;
  long long entries = 0, unmatched = 0;
};

template <int Dim, class Space, class List, class Scalar>
Differences differences(const Space& space, const List& a, const List& b, int rows, double dx,
                        const Scalar& scalar) {
  Differences found;
  double largest = 0;
  Kokkos::parallel_reduce(
      "test::differences", Kokkos::RangePolicy<Space>(space, 0, rows),
      KOKKOS_LAMBDA(int i, double& separation, double& difference, double& most, long long& entries,
                    long long& unmatched) {
        for (int k = a.begin(i); k < a.end(i); ++k) {
          int match = -1;
          for (int kb = b.begin(i); kb < b.end(i); ++kb) match = b.neighbour(kb) == a.neighbour(k) ? kb : match;
          ++entries;
          if (match < 0) {
            ++unmatched;
            continue;
          }
          for (int d = 0; d < Dim; ++d) {
            const double e = math::fabs(a.separation(k, d) - b.separation(match, d));
            separation = e > separation ? e : separation;
          }
          const double e = math::fabs(scalar(a, k) - scalar(b, match));
          difference = e > difference ? e : difference;
          const double magnitude = math::fabs(scalar(b, match));
          most = magnitude > most ? magnitude : most;
        }
      },
      Kokkos::Max<double>(found.separation), Kokkos::Max<double>(found.scalar), Kokkos::Max<double>(largest),
      found.entries, found.unmatched);
  found.separation /= dx;
  if (largest > 0) found.scalar /= largest;
  return found;
}

// The lattice points (i + 1/2) dx of a periodic cell of n per side, a slab
// of them boundary particles; `nudge` spacings added to particle 0's x; the
// periodic ghosts and the cell list.
template <int Dim, class Space>
struct PeriodicLattice {
  using MemorySpace = typename Space::memory_space;
  Space space;
  double dx;
  QuinticKernel<Dim> kernel;
  std::array<double, Dim> spacing{};
  Particles<Dim, MemorySpace> P;
  CellList<Dim, Space> cells;
  Halo<Dim, Space> halo;

  PeriodicLattice(int n, double nudge) : dx(1.0 / n), kernel(1.3 * dx) {
    int count = 1;
    for (int d = 0; d < Dim; ++d) count *= n;
    P.reserve(count);
    P.owned = count;
    auto x = Kokkos::create_mirror_view(P.x);
    auto id = Kokkos::create_mirror_view(P.id);
    auto kind = Kokkos::create_mirror_view(P.kind);
    for (int i = 0; i < count; ++i) {
      for (int d = 0, rest = i; d < Dim; ++d, rest /= n) x(i, d) = (rest % n + 0.5) * dx;
      id(i) = i;
      kind(i) = i % n < 2 ? kWallBoundary : kFluid;
    }
    x(0, 0) += nudge * dx;
    Kokkos::deep_copy(P.x, x);
    Kokkos::deep_copy(P.id, id);
    Kokkos::deep_copy(P.kind, kind);

    std::array<double, Dim> cell{};
    std::array<bool, Dim> periodic{};
    std::array<std::vector<double>, Dim> cuts;
    Vec<Dim> lo, hi;
    for (int d = 0; d < Dim; ++d) {
      cell[d] = 1.0, periodic[d] = true, cuts[d] = {0.0, 1.0}, spacing[d] = dx;
      lo[d] = -kernel.cutoff, hi[d] = 1.0 + kernel.cutoff;
    }
    halo = Halo<Dim, Space>(Communicator(MPI_COMM_SELF), Decomposition<Dim>::cartesian(cell, periodic, cuts),
                            kernel.cutoff);
    halo.build(P);
    cells.build(space, P.x, P.total(), lo, hi, kernel.cutoff);
  }
  LatticeStencil<Dim, MemorySpace> pair_stencil() const {
    const auto W = kernel;
    return {spacing, W.cutoff, [&](double r) { return W.derivative_over_r(r); }};
  }
};

// Builds both lists twice, one from the stencil and one cached per entry,
// and compares them. Returns whether the lists were found on the stencil.
template <int Dim, class Space>
bool stencil_against_cache(int n, double nudge) {
  using MemorySpace = typename Space::memory_space;
  PeriodicLattice<Dim, Space> lattice(n, nudge);
  const auto& space = lattice.space;
  const auto& kernel = lattice.kernel;
  const auto& P = lattice.P;
  const auto& cells = lattice.cells;
  const double dx = lattice.dx;
  const auto& spacing = lattice.spacing;
  EXPECT_GT(P.total(), P.owned);  // periodic ghosts are in

  const auto pair_stencil = lattice.pair_stencil();
  const LatticeStencil<Dim, MemorySpace> wall_stencil(spacing, kernel.cutoff,
                                                      [&](double r) { return kernel.value(r); });
  NeighbourList<Dim, Space> on_stencil, cached;
  on_stencil.build(space, cells, P.x, P.owned, kernel.cutoff);
  cached.build(space, cells, P.x, P.owned, kernel.cutoff);
  WallNeighbours<Dim, Space> walls_on_stencil, walls_cached;
  walls_on_stencil.build(space, cells, P, kernel.cutoff);
  walls_cached.build(space, cells, P, kernel.cutoff);

  const bool pairs_found = on_stencil.find_stencil_ids(space, P.x, P.owned, pair_stencil);
  const bool walls_found = walls_on_stencil.find_stencil_ids(space, P.x, P.owned, wall_stencil);
  EXPECT_EQ(pairs_found, walls_found);
  if (pairs_found) {
    on_stencil.use_stencil(space, pair_stencil);
    walls_on_stencil.use_stencil(wall_stencil);
  } else {
    on_stencil.cache_geometry(space, P.x, P.owned, kernel);
    walls_on_stencil.cache_geometry(space, P.x, P.owned, kernel);
  }
  EXPECT_EQ(on_stencil.on_stencil(), pairs_found);
  cached.cache_geometry(space, P.x, P.owned, kernel);
  walls_cached.cache_geometry(space, P.x, P.owned, kernel);
  EXPECT_FALSE(cached.on_stencil());

  using List = NeighbourList<Dim, Space>;
  using Walls = WallNeighbours<Dim, Space>;
  const auto pairs = differences<Dim>(space, on_stencil, cached, P.owned, dx,
                                      KOKKOS_LAMBDA(const List& l, int k) { return l.derivative_over_r(k); });
  const auto walls = differences<Dim>(space, walls_on_stencil, walls_cached, P.owned, dx,
                                      KOKKOS_LAMBDA(const Walls& l, int k) { return l.weight(k); });
  EXPECT_EQ(pairs.entries, cached.pairs());
  EXPECT_GT(pairs.entries, 20LL * P.owned / 2);
  EXPECT_GT(walls.entries, 0);
  EXPECT_EQ(pairs.unmatched, 0);
  EXPECT_EQ(walls.unmatched, 0);
  // Round-off: the cache's r is a difference of coordinates near 1 (and of
  // a ghost's, shifted by the cell side), the stencil's n dx.
  EXPECT_LT(pairs.separation, 1e-12) << Dim << "D";
  EXPECT_LT(pairs.scalar, 1e-12) << Dim << "D";
  EXPECT_LT(walls.separation, 1e-12) << Dim << "D";
  EXPECT_LT(walls.scalar, 1e-12) << Dim << "D";
  return pairs_found;
}

TYPED_TEST(LatticeStencilTest, GivesThePerEntryCachesGeometryOnAPeriodicLattice2D) {
  EXPECT_TRUE((stencil_against_cache<2, TypeParam>(24, 0.0)));
}

TYPED_TEST(LatticeStencilTest, GivesThePerEntryCachesGeometryOnAPeriodicLattice3D) {
  EXPECT_TRUE((stencil_against_cache<3, TypeParam>(12, 0.0)));
}

// One particle a thousandth of a spacing off: the lists fall back to the
// per-entry cache, which is then the reference itself.
TYPED_TEST(LatticeStencilTest, FallsBackToThePerEntryCacheOffTheLattice) {
  EXPECT_FALSE((stencil_against_cache<2, TypeParam>(24, 1e-3)));
  EXPECT_FALSE((stencil_against_cache<3, TypeParam>(12, 1e-3)));
  // A hair within the tolerance (a lattice's own rounding) is still on it.
  EXPECT_TRUE((stencil_against_cache<2, TypeParam>(24, 1e-13)));
}

// Rows as masks over the stencil (core/LatticeRows.hpp), made from the cell
// list, against the list sorted by stencil id: the same neighbours in the
// same order, and the pair loop's rates the same to the bit.
template <int Dim, class Space>
void lattice_rows_against_list(int n) {
  PeriodicLattice<Dim, Space> lattice(n, 0.0);
  const auto& space = lattice.space;
  auto& P = lattice.P;
  const auto stencil = lattice.pair_stencil();
  NeighbourList<Dim, Space> list, rows;
  list.build(space, lattice.cells, P.x, P.owned, lattice.kernel.cutoff);
  ASSERT_TRUE(list.find_stencil_ids(space, P.x, P.owned, stencil));
  list.use_stencil(space, stencil);
  ASSERT_TRUE(
      rows.build_lattice_rows(space, lattice.cells, P.x, P.owned, P.total(), lattice.kernel.cutoff, stencil, lattice.dx));
  EXPECT_TRUE(rows.on_lattice_rows());
  EXPECT_TRUE(rows.on_stencil());
  EXPECT_FALSE(list.on_lattice_rows());
  EXPECT_EQ(rows.pairs(), list.pairs());
  EXPECT_DOUBLE_EQ(rows.neighbours_per_particle(), list.neighbours_per_particle());

  // The rows' neighbours, owned then ghosts, against the list's entries.
  const auto& lattice_rows = rows.lattice_rows();
  long long mismatched = 0, visited = 0;
  Kokkos::parallel_reduce(
      "test::rows_against_list", Kokkos::RangePolicy<Space>(space, 0, P.owned),
      KOKKOS_LAMBDA(int a, long long& bad, long long& seen) {
        int k = list.begin(a);
        auto visit = [&](auto bits_of, int end) {
          for (int w = 0; w < lattice_rows.words(); ++w)
            for (auto bits = bits_of(w); bits != 0; bits &= bits - 1) {
              const int id = w * 64 + lowest_bit(bits);
              ++seen;
              bad += k >= end || lattice_rows.neighbour(a, id) != list.neighbour(k);
              for (int d = 0; d < Dim; ++d) bad += k < end && lattice_rows.separation(id, d) != list.separation(k, d);
              ++k;
            }
          bad += k != end;
          k = end;
        };
        visit([&](int w) { return lattice_rows.template bits<true>(a, w); }, list.ghosts_begin(a));
        visit([&](int w) { return lattice_rows.template bits<false>(a, w); }, list.end(a));
      },
      mismatched, visited);
  EXPECT_EQ(mismatched, 0) << Dim << "D";
  EXPECT_EQ(visited, list.pairs()) << Dim << "D";

  // The pair loop over each, on a random state.
  auto v = Kokkos::create_mirror_view(P.v);
  auto rho = Kokkos::create_mirror_view(P.rho);
  auto m = Kokkos::create_mirror_view(P.m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  for (int i = 0; i < P.owned; ++i) {
    for (int d = 0; d < Dim; ++d) v(i, d) = jitter(rng);
    rho(i) = 1.0 + 0.01 * jitter(rng), m(i) = 1.0;
  }
  Kokkos::deep_copy(P.v, v), Kokkos::deep_copy(P.rho, rho), Kokkos::deep_copy(P.m, m);
  update_pressure(space, P, 10.0, 0.0);
  lattice.halo.update(P);
  PairSums<Dim, Space> sums{pair_sum_components<Dim, Space>(P, PairLoopOptions{})};
  sums.reserve(P.owned);
  const FluidProperties fluid{0.1, 0.0};
  Vec<Dim> force = Vec<Dim>::zero();
  force[0] = 1.0;
  // Passes 2 and 3: the rows again, with the sums' first copy in the rates
  // (core/PairSums.hpp, 3D only), which must be cleared before each loop.
  PairSums<Dim, Space> in_rates{pair_sum_components<Dim, Space>(P, PairLoopOptions{}), true};
  in_rates.reserve(P.owned);
  EXPECT_EQ(in_rates.first_copy_in_rates(), Dim == 3);
  std::vector<double> rates[4];
  for (int pass = 0; pass < 4; ++pass) {
    compute_pair_rates(space, P, pass == 0 ? list : rows, pass < 2 ? sums : in_rates, lattice.kernel, fluid, force);
    auto dvdt = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.dvdt);
    auto drhodt = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.drhodt);
    for (int i = 0; i < P.owned; ++i) {
      rates[pass].push_back(drhodt(i));
      for (int d = 0; d < Dim; ++d) rates[pass].push_back(dvdt(i, d));
    }
  }
  double largest = 0;
  for (double r : rates[0]) largest = std::max(largest, std::fabs(r));
  EXPECT_GT(largest, 0.0);
  EXPECT_EQ(rates[0], rates[1]) << Dim << "D";
  EXPECT_EQ(rates[2], rates[1]) << Dim << "D";
  EXPECT_EQ(rates[3], rates[1]) << Dim << "D";
}

TYPED_TEST(LatticeStencilTest, RowsAsMasksVisitTheSortedListsPairsInItsOrder) {
  lattice_rows_against_list<2, TypeParam>(24);
  lattice_rows_against_list<3, TypeParam>(12);
}

// A particle off the lattice: no rows are made, nothing is held.
TYPED_TEST(LatticeStencilTest, RowsAreNotMadeOffTheLattice) {
  PeriodicLattice<2, TypeParam> lattice(24, 1e-3);
  NeighbourList<2, TypeParam> rows;
  EXPECT_FALSE(rows.build_lattice_rows(lattice.space, lattice.cells, lattice.P.x, lattice.P.owned,
                                       lattice.P.total(), lattice.kernel.cutoff, lattice.pair_stencil(), lattice.dx));
  EXPECT_FALSE(rows.on_lattice_rows());
  EXPECT_FALSE(rows.has_geometry());
  EXPECT_EQ(rows.pairs(), 0);
}

TEST(LatticeStencil, HoldsEveryOffsetWithinTheRadiusOnce) {
  using Stencil = LatticeStencil<3, Kokkos::HostSpace>;
  const Stencil stencil({0.1, 0.1, 0.1}, 0.25, [](double r) { return r; });
  // The offsets n != 0 with |n| <= 2.5 spacings.
  int expected = 0;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j)
      for (int k = -2; k <= 2; ++k) expected += (i || j || k) && i * i + j * j + k * k <= 6;
  EXPECT_EQ(stencil.size(), expected);
  for (int id = 0; id < stencil.size(); ++id) {
    Vec<3> r;
    for (int d = 0; d < 3; ++d) r[d] = stencil.separation(id, d);
    EXPECT_EQ(stencil.id_of(r), id);
    EXPECT_DOUBLE_EQ(stencil.of_distance(id), std::sqrt(dot(r, r)));
  }
  Vec<3> beyond{0.3, 0.0, 0.0}, between{0.15, 0.0, 0.0}, zero{0.0, 0.0, 0.0};
  EXPECT_EQ(stencil.id_of(beyond), -1);
  EXPECT_EQ(stencil.id_of(between), -1);
  EXPECT_EQ(stencil.id_of(zero), -1);
}

}  // namespace
}  // namespace poresph
