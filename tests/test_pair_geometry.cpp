// The lattice stencil of fixed particles' pairs (core/PairGeometry.hpp): on
// a lattice with periodic ghosts, in 2D and 3D, every entry of the pair list
// and of the wall-pressure list is one of the stencil's offsets, and the
// stencil's r and F (W for the walls) are the per-entry cache's to
// round-off; a particle off the lattice sends both lists to the per-entry
// cache (the scene-level check is in test_fixed_particles).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "TestSpaces.hpp"
#include "core/CellList.hpp"
#include "core/Kernel.hpp"
#include "core/NeighbourList.hpp"
#include "core/PairGeometry.hpp"
#include "core/Particles.hpp"
#include "parallel/Halo.hpp"
#include "physics/WallPressure.hpp"

namespace poresph {
namespace {

template <class Space>
class LatticeStencilTest : public ::testing::Test {};
TYPED_TEST_SUITE(LatticeStencilTest, testing::ExecutionSpaces);

// The largest difference between two lists' geometry over their entries:
// of the separations (in spacings) and of the scalar (relative to its
// largest magnitude).
struct Differences {
  double separation = 0, scalar = 0;
  long long entries = 0;
};

template <int Dim, class Space, class List, class Scalar>
Differences differences(const Space& space, const List& a, const List& b, long long entries, double dx,
                        const Scalar& scalar) {
  double separation = 0, difference = 0, largest = 0;
  Kokkos::parallel_reduce(
      "test::separation", Kokkos::RangePolicy<Space>(space, 0, entries),
      KOKKOS_LAMBDA(int k, double& worst) {
        for (int d = 0; d < Dim; ++d) {
          const double e = math::fabs(a.separation(k, d) - b.separation(k, d));
          worst = e > worst ? e : worst;
        }
      },
      Kokkos::Max<double>(separation));
  Kokkos::parallel_reduce(
      "test::scalar", Kokkos::RangePolicy<Space>(space, 0, entries),
      KOKKOS_LAMBDA(int k, double& worst) {
        const double e = math::fabs(scalar(a, k) - scalar(b, k));
        worst = e > worst ? e : worst;
      },
      Kokkos::Max<double>(difference));
  Kokkos::parallel_reduce(
      "test::largest", Kokkos::RangePolicy<Space>(space, 0, entries),
      KOKKOS_LAMBDA(int k, double& most) {
        const double e = math::fabs(scalar(b, k));
        most = e > most ? e : most;
      },
      Kokkos::Max<double>(largest));
  return {separation / dx, largest > 0 ? difference / largest : difference, entries};
}

// The lattice points (i + 1/2) dx of a periodic cell of n per side, a slab
// of them boundary particles; `nudge` spacings added to particle 0's x.
// Builds both lists twice, one from the stencil and one cached per entry,
// and compares them. Returns whether the lists were found on the stencil.
template <int Dim, class Space>
bool stencil_against_cache(int n, double nudge) {
  using MemorySpace = typename Space::memory_space;
  const Space space;
  const double dx = 1.0 / n, h = 1.3 * dx;
  const QuinticKernel<Dim> kernel(h);
  int count = 1;
  for (int d = 0; d < Dim; ++d) count *= n;
  Particles<Dim, MemorySpace> P;
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

  std::array<double, Dim> cell{}, spacing{};
  std::array<bool, Dim> periodic{};
  std::array<std::vector<double>, Dim> cuts;
  Vec<Dim> lo, hi;
  for (int d = 0; d < Dim; ++d) {
    cell[d] = 1.0, periodic[d] = true, cuts[d] = {0.0, 1.0}, spacing[d] = dx;
    lo[d] = -kernel.cutoff, hi[d] = 1.0 + kernel.cutoff;
  }
  Halo<Dim, Space>(Communicator(MPI_COMM_SELF), Decomposition<Dim>::cartesian(cell, periodic, cuts), kernel.cutoff)
      .build(P);
  EXPECT_GT(P.total(), P.owned);  // periodic ghosts are in
  CellList<Dim, Space> cells;
  cells.build(space, P.x, P.total(), lo, hi, kernel.cutoff);

  const LatticeStencil<Dim, MemorySpace> pair_stencil(spacing, kernel.cutoff,
                                                      [&](double r) { return kernel.derivative_over_r(r); });
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
    on_stencil.use_stencil(pair_stencil);
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
  const auto pairs = differences<Dim>(space, on_stencil, cached, cached.pairs(), dx,
                                      KOKKOS_LAMBDA(const List& l, int k) { return l.derivative_over_r(k); });
  long long wall_entries = 0;
  Kokkos::parallel_reduce(
      "test::wall_entries", Kokkos::RangePolicy<Space>(space, 0, P.owned),
      KOKKOS_LAMBDA(int i, long long& sum) { sum += walls_cached.end(i) - walls_cached.begin(i); }, wall_entries);
  const auto walls = differences<Dim>(space, walls_on_stencil, walls_cached, wall_entries, dx,
                                      KOKKOS_LAMBDA(const Walls& l, int k) { return l.weight(k); });
  EXPECT_GT(pairs.entries, 20LL * P.owned / 2);
  EXPECT_GT(walls.entries, 0);
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
