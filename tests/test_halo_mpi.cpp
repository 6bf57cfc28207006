// The ghost exchange on hand-made decompositions: every periodic image of
// every particle that falls in a process's halo arrives there exactly once,
// with the right shift, whatever the boxes (process grids, and RCB-like
// boxes where a face has two neighbours). CTest runs it on 1, 2 and 4 ranks.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>
#include <sstream>

#include "parallel/Halo.hpp"

namespace poresph {
namespace {

using Space = Kokkos::Serial;
using Set = Particles<2, Space::memory_space>;
constexpr double kWidth = 0.12;

// Boxes for `ranks` processes: a process grid, or (rcb = true, 4 ranks)
// x cut at 0.5, then y cut at 0.5 on the left and at 0.3 on the right.
Decomposition<2> boxes(int ranks, bool rcb, const std::array<bool, 2>& periodic, bool thin = false) {
  const std::array<double, 2> cell{1.0, 1.0};
  if (thin) {  // boxes 0.05 wide, narrower than the width 0.12; the last takes the rest
    std::vector<double> cuts{0.0};
    for (int r = 1; r < ranks; ++r) cuts.push_back(0.05 * r);
    cuts.push_back(1.0);
    return Decomposition<2>::cartesian(cell, periodic, {cuts, {0.0, 1.0}});
  }
  if (rcb) {
    std::vector<Box<2>> b(4);
    b[0].lo = {0.0, 0.0}, b[0].hi = {0.5, 0.5};
    b[1].lo = {0.0, 0.5}, b[1].hi = {0.5, 1.0};
    b[2].lo = {0.5, 0.0}, b[2].hi = {1.0, 0.3};
    b[3].lo = {0.5, 0.3}, b[3].hi = {1.0, 1.0};
    return Decomposition<2>(b, cell, periodic);
  }
  const int nx = ranks >= 2 ? 2 : 1, ny = ranks / nx;
  return Decomposition<2>::cartesian(cell, periodic,
                                     {Decomposition<2>::equal_cuts(1.0, nx), Decomposition<2>::equal_cuts(1.0, ny)});
}

// The same particles on every rank's view of the cell; each rank keeps those in its box.
std::vector<std::array<double, 2>> particles() {
  std::vector<std::array<double, 2>> p{{0.01, 0.99}, {0.995, 0.005}, {0.5, 0.3}, {0.49, 0.51}};  // corners, box corners
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 300; ++i) p.push_back({u(rng), u(rng)});
  return p;
}

void check_exchange(bool rcb, const std::array<bool, 2>& periodic, bool thin = false) {
  const Communicator comm;
  if (rcb && comm.size() != 4) GTEST_SKIP() << "the RCB-like layout needs 4 ranks";
  const auto decomposition = boxes(comm.size(), rcb, periodic, thin);
  Halo<2, Space> halo(comm, decomposition, kWidth);
  const auto all = particles();
  Set P;
  P.reserve(static_cast<int>(all.size()));
  for (size_t k = 0; k < all.size(); ++k) {
    if (!halo.box().contains(all[k].data())) continue;
    P.x(P.owned, 0) = all[k][0], P.x(P.owned, 1) = all[k][1];
    P.id(P.owned) = static_cast<long long>(k);
    ++P.owned;
  }
  halo.build(P);

  // Expected: every image (shift in {-1,0,1}^2 along periodic directions) of
  // every particle inside this rank's box grown by the width, except the
  // particles it owns.
  std::multiset<std::tuple<long long, int, int>> expected, got;
  const Box<2>& mine = halo.box();
  for (size_t k = 0; k < all.size(); ++k)
    for (int sx = -1; sx <= 1; ++sx)
      for (int sy = -1; sy <= 1; ++sy) {
        if ((sx && !periodic[0]) || (sy && !periodic[1])) continue;
        const double x = all[k][0] + sx, y = all[k][1] + sy;
        const bool in_halo = x >= mine.lo[0] - kWidth && x < mine.hi[0] + kWidth && y >= mine.lo[1] - kWidth &&
                             y < mine.hi[1] + kWidth;
        const double xy[2] = {x, y};
        if (in_halo && !mine.contains(xy)) expected.insert({static_cast<long long>(k), sx, sy});
      }
  for (int g = P.owned; g < P.total(); ++g) {
    const auto& origin = all[P.id(g)];
    got.insert({P.id(g), static_cast<int>(std::lround(P.x(g, 0) - origin[0])),
                static_cast<int>(std::lround(P.x(g, 1) - origin[1]))});
    EXPECT_NEAR(P.x(g, 0) - origin[0], std::lround(P.x(g, 0) - origin[0]), 1e-15);  // shift is a whole cell
  }
  EXPECT_EQ(got, expected) << "rank " << comm.rank() << " of " << comm.size();
  EXPECT_GT(expected.size(), 0u);
  // With boxes wider than the width, the particle within the width of the
  // cell's corner exists four times over all processes together (itself and
  // its images across x, y and the corner), whatever the number of processes.
  // (Thinner boxes need more copies: the exact sets above cover them.)
  int corner_copies = 0;
  for (const auto& e : got) corner_copies += std::get<0>(e) == 0;
  const int everywhere = comm.sum(corner_copies + (halo.box().contains(all[0].data()) ? 1 : 0));
  if (periodic[0] && periodic[1] && !thin) {
    EXPECT_EQ(everywhere, 4);
  }
}

TEST(HaloExchange, ProcessGridPeriodic) { check_exchange(false, {true, true}); }
TEST(HaloExchange, ProcessGridPeriodicInXOnly) { check_exchange(false, {true, false}); }
TEST(HaloExchange, RcbBoxesWhereAFaceHasTwoNeighbours) { check_exchange(true, {true, true}); }
TEST(HaloExchange, BoxesThinnerThanTheWidth) { check_exchange(false, {true, true}, true); }

// Migration hands each particle to the owner of its position, and none is lost.
TEST(HaloExchange, MigrationDeliversEveryParticleToItsOwner) {
  const Communicator comm;
  const auto decomposition = boxes(comm.size(), false, {true, true});
  Halo<2, Space> halo(comm, decomposition, kWidth);
  const auto all = particles();
  Set P;
  P.reserve(static_cast<int>(all.size()));
  // Every rank starts with a strided share, wherever it lies.
  for (size_t k = comm.rank(); k < all.size(); k += comm.size()) {
    P.x(P.owned, 0) = all[k][0], P.x(P.owned, 1) = all[k][1];
    P.id(P.owned) = static_cast<long long>(k);
    ++P.owned;
  }
  halo.migrate(P);
  for (int i = 0; i < P.owned; ++i) {
    const double xi[2] = {P.x(i, 0), P.x(i, 1)};
    EXPECT_TRUE(halo.box().contains(xi));
    EXPECT_EQ(P.x(i, 0), all[P.id(i)][0]);
  }
  EXPECT_EQ(comm.sum(P.owned), static_cast<int>(all.size()));
}

}  // namespace
}  // namespace poresph
