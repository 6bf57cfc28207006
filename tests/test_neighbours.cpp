// Cell-list neighbour search with periodic images (halo) against brute
// force over all periodic images, on random particles.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <tuple>

#include "TestSpaces.hpp"
#include "core/CellList.hpp"
#include "core/NeighbourList.hpp"
#include "core/Particles.hpp"
#include "parallel/Halo.hpp"

namespace poresph {
namespace {

template <class Space>
class NeighbourSearch : public ::testing::Test {};
TYPED_TEST_SUITE(NeighbourSearch, testing::ExecutionSpaces);

// A neighbour: (particle id, image shift in units of the cell side per direction).
using Neighbour = std::tuple<long long, int, int, int>;

// The halo of a single process owning the whole cell: periodic images only.
template <int Dim, class Space>
Halo<Dim, Space> one_process_halo(const double (&side)[Dim], const std::array<bool, Dim>& periodic, double width) {
  std::array<double, Dim> cell{};
  std::array<std::vector<double>, Dim> cuts;
  for (int d = 0; d < Dim; ++d) cell[d] = side[d], cuts[d] = {0.0, side[d]};
  return Halo<Dim, Space>(Communicator(MPI_COMM_SELF), Decomposition<Dim>::cartesian(cell, periodic, cuts), width);
}

template <int Dim, class Space>
Particles<Dim, typename Space::memory_space> random_particles(int n, const double (&side)[Dim], unsigned seed) {
  Particles<Dim, typename Space::memory_space> P;
  P.reserve(n);
  P.owned = n;
  auto x = Kokkos::create_mirror_view(P.x);
  auto id = Kokkos::create_mirror_view(P.id);
  std::mt19937 rng(seed);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < Dim; ++d) x(i, d) = std::uniform_real_distribution<double>(0.0, side[d])(rng);
    id(i) = i;
  }
  Kokkos::deep_copy(P.x, x);
  Kokkos::deep_copy(P.id, id);
  return P;
}

// Every (i, neighbour) pair within the cutoff, over all images k in {-1,0,1}^Dim
// of the periodic directions.
template <int Dim, class HostX>
std::vector<std::set<Neighbour>> brute_force(const HostX& x, int n, const double (&side)[Dim],
                                             const std::array<bool, Dim>& periodic, double cutoff) {
  std::vector<std::set<Neighbour>> result(n);
  const int images = static_cast<int>(std::pow(3, Dim));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < images; ++k) {
        int shift[3] = {0, 0, 0};
        bool allowed = true;
        double r_sq = 0;
        for (int d = 0, rest = k; d < Dim; ++d, rest /= 3) {
          shift[d] = rest % 3 - 1;
          if (shift[d] != 0 && !periodic[d]) allowed = false;
          const double r = x(i, d) - (x(j, d) + shift[d] * side[d]);
          r_sq += r * r;
        }
        if (!allowed || r_sq >= cutoff * cutoff || (i == j && k == images / 2)) continue;
        result[i].insert({j, shift[0], shift[1], shift[2]});
      }
  return result;
}

template <int Dim, class Space>
void compare_with_brute_force(const double (&side)[Dim], const std::array<bool, Dim>& periodic, double cutoff,
                              int n, unsigned seed) {
  const Space space;
  auto P = random_particles<Dim, Space>(n, side, seed);
  Vec<Dim> search_lo, search_hi;
  for (int d = 0; d < Dim; ++d) search_lo[d] = -cutoff, search_hi[d] = side[d] + cutoff;
  one_process_halo<Dim, Space>(side, periodic, cutoff).build(P);
  CellList<Dim, Space> cells;
  cells.build(space, P.x, P.total(), search_lo, search_hi, cutoff);

  // Both searches: the cells directly, and the Verlet list built from them.
  NeighbourList<Dim, Space> list;
  list.build(space, cells, P.x, n, cutoff);
  Kokkos::View<int*, typename Space::memory_space> count("count", n);
  const int capacity = 4 * n;
  Kokkos::View<int**, typename Space::memory_space> found("found", n, capacity);
  Kokkos::View<int*, typename Space::memory_space> list_mismatch("list_mismatch", n);
  const auto x = P.x;
  const double cutoff_sq = cutoff * cutoff;
  Kokkos::parallel_for(
      "test::search", Kokkos::RangePolicy<Space>(space, 0, n), KOKKOS_LAMBDA(int i) {
        const Vec<Dim> xi = row<Dim>(x, i);
        cells.for_each_candidate(xi, [&](int j) {
          const Vec<Dim> r = xi - row<Dim>(x, j);
          if (j == i || dot(r, r) >= cutoff_sq) return;
          if (count(i) < capacity) found(i, count(i)) = j;
          ++count(i);
        });
        // The half list holds the neighbours with a larger index (every
        // ghost, and each pair of owned particles once): the owned ones in
        // the cell search's order, then the ghosts in the reverse order.
        int owned_k = list.begin(i), ghost_k = list.end(i), listed = 0;
        for (int c = 0; c < count(i) && c < capacity && !list_mismatch(i); ++c) {
          const int j = found(i, c);
          if (!NeighbourList<Dim, Space>::listed(i, j)) continue;
          if (j < n) list_mismatch(i) = owned_k >= list.ghosts_begin(i) || list.neighbour(owned_k++) != j;
          else list_mismatch(i) = ghost_k <= list.ghosts_begin(i) || list.neighbour(--ghost_k) != j;
          ++listed;
        }
        list_mismatch(i) = list_mismatch(i) || owned_k != list.ghosts_begin(i) || ghost_k != list.ghosts_begin(i);
        int larger = 0;
        for (int c = 0; c < count(i) && c < capacity; ++c) larger += found(i, c) > i;
        list_mismatch(i) = list_mismatch(i) || listed != larger;
        list_mismatch(i) = list_mismatch(i) || list.end(i) - list.begin(i) != listed;
      });
  auto h_mismatch = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), list_mismatch);
  for (int i = 0; i < n; ++i) EXPECT_EQ(h_mismatch(i), 0) << "Verlet list differs from the cell search at " << i;
  auto h_count = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), count);
  auto h_found = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), found);
  auto h_x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  auto h_id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.id);
  const auto expected = brute_force<Dim>(h_x, n, side, periodic, cutoff);
  long long pairs = 0;
  for (int i = 0; i < n; ++i) {
    ASSERT_LE(h_count(i), capacity);
    std::set<Neighbour> got;
    for (int k = 0; k < h_count(i); ++k) {
      const int j = h_found(i, k);
      const long long source = h_id(j);
      int shift[3] = {0, 0, 0};
      for (int d = 0; d < Dim; ++d) shift[d] = static_cast<int>(std::lround((h_x(j, d) - h_x(source, d)) / side[d]));
      const bool inserted = got.insert({source, shift[0], shift[1], shift[2]}).second;
      EXPECT_TRUE(inserted) << "particle " << i << " sees a neighbour image twice";
    }
    EXPECT_EQ(got, expected[i]) << "particle " << i;
    pairs += h_count(i);
  }
  EXPECT_GT(pairs, n);  // the test found something to compare
}

TYPED_TEST(NeighbourSearch, MatchesBruteForceWithoutPeriodicity2D) {
  compare_with_brute_force<2, TypeParam>({1.0, 0.7}, {false, false}, 0.12, 600, 1);
}
TYPED_TEST(NeighbourSearch, MatchesBruteForcePeriodic2D) {
  compare_with_brute_force<2, TypeParam>({1.0, 0.7}, {true, true}, 0.12, 600, 2);
}
TYPED_TEST(NeighbourSearch, MatchesBruteForcePeriodicInXOnly2D) {
  compare_with_brute_force<2, TypeParam>({1.0, 0.7}, {true, false}, 0.12, 600, 3);
}
TYPED_TEST(NeighbourSearch, MatchesBruteForceWhenTheCellHoldsTwoImagesOfASupport) {
  // Cell side between 3h and 6h: a particle can see two images of one neighbour.
  compare_with_brute_force<2, TypeParam>({1.0, 1.0}, {true, true}, 0.45, 300, 4);
}
TYPED_TEST(NeighbourSearch, MatchesBruteForcePeriodic3D) {
  compare_with_brute_force<3, TypeParam>({1.0, 0.8, 0.6}, {true, true, true}, 0.2, 500, 5);
}
TYPED_TEST(NeighbourSearch, MatchesBruteForceMixed3D) {
  compare_with_brute_force<3, TypeParam>({1.0, 0.8, 0.6}, {true, false, true}, 0.2, 500, 6);
}

TYPED_TEST(NeighbourSearch, CornerParticleArrivesOnceAtEachImageWithItsShift) {
  Particles<2, typename TypeParam::memory_space> P;
  P.reserve(1);
  P.owned = 1;
  auto x = Kokkos::create_mirror_view(P.x);
  x(0, 0) = 0.05, x(0, 1) = 0.98;  // near the corner (0, 1)
  Kokkos::deep_copy(P.x, x);
  one_process_halo<2, TypeParam>({1.0, 1.0}, {true, true}, 0.1).build(P);
  ASSERT_EQ(P.ghosts, 3);
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  std::set<std::pair<long, long>> shifts;
  for (int g = 1; g <= 3; ++g) shifts.insert({std::lround(h(g, 0) - h(0, 0)), std::lround(h(g, 1) - h(0, 1))});
  const std::set<std::pair<long, long>> expected{{1, 0}, {0, -1}, {1, -1}};
  EXPECT_EQ(shifts, expected);
}

TEST(Halo, RefusesACellNarrowerThanTheSupport) {
  EXPECT_THROW((one_process_halo<2, Kokkos::Serial>({0.2, 1.0}, {true, true}, 0.3)), std::invalid_argument);
  EXPECT_NO_THROW((one_process_halo<2, Kokkos::Serial>({0.2, 1.0}, {false, true}, 0.3)));
}

TEST(Halo, WrapKeepsCoordinatesInsideTheCell) {
  using H = Halo<2, Kokkos::Serial>;
  EXPECT_DOUBLE_EQ(H::wrap_coordinate(1.25, 0.0, 1.0), 0.25);
  EXPECT_DOUBLE_EQ(H::wrap_coordinate(-0.25, 0.0, 1.0), 0.75);
  EXPECT_LT(H::wrap_coordinate(-1e-20, 0.0, 1.0), 1.0);  // -1e-20 + 1 rounds to 1
  EXPECT_DOUBLE_EQ(H::wrap_coordinate(0.5, 0.0, 1.0), 0.5);
}

}  // namespace
}  // namespace poresph
