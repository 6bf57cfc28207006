// Quasi-static drainage by the morphological rule (scene/Drainage.hpp) on
// lattices drawn here: the pore radius of a channel, the entry radius of a
// throat, the reservoir that only reaches a pore body through its throats,
// the target saturation's step and the curve's order.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "scene/Drainage.hpp"

namespace poresph {
namespace {

// A 2D lattice nx x ny, periodic along x only (walls beyond y's ends), whose
// fluid points are those `fluid(i, j)` says.
DrainageLattice channel(long long nx, long long ny, const std::function<bool(long long, long long)>& fluid) {
  DrainageLattice lattice;
  lattice.dimension = 2;
  lattice.shape = {nx, ny, 1};
  lattice.periodic = {true, false, true};
  lattice.fluid.resize(static_cast<size_t>(nx * ny));
  for (long long j = 0; j < ny; ++j)
    for (long long i = 0; i < nx; ++i) lattice.fluid[static_cast<size_t>(i + nx * j)] = fluid(i, j);
  return lattice;
}

long long count(const std::vector<char>& marks) {
  long long n = 0;
  for (char m : marks) n += m != 0;
  return n;
}

// Walls at y = 0 and y = 20 spacings: a point's pore radius is its distance
// to the nearer wall, and a ball enters while it is at most half the width
// less half a spacing (the widest ball centred on a lattice point).
TEST(Drainage, ChannelRadiusIsTheDistanceToTheNearerWall) {
  const auto lattice = channel(30, 20, [](long long, long long) { return true; });
  const auto radius = pore_radius(lattice);
  for (long long j = 0; j < 20; ++j)
    EXPECT_DOUBLE_EQ(radius[static_cast<size_t>(7 + 30 * j)], std::min(j + 0.5, 19.5 - j)) << "row " << j;
  const DrainageInlet inlet{0, false};
  EXPECT_EQ(count(drained_points(lattice, radius, 9.5, inlet)), 30 * 20);
  EXPECT_EQ(count(drained_points(lattice, radius, 9.5 + 1e-6, inlet)), 0);
  // Smaller balls fill it too: row 0 lies 4 from a centre on row 4.
  EXPECT_EQ(count(drained_points(lattice, radius, 4.0, inlet)), 30 * 20);
}

// A pore body 30 wide between two throats 10 wide, at the cell's faces
// across x: the reservoir there reaches the body only through a throat, so
// the body stays wetting until the ball passes the throat (radius 4.5),
// though a ball of radius 14.5 fits in it; from anywhere, it fills at once.
TEST(Drainage, BodyBehindAThroatWaitsForTheThroatsRadius) {
  const auto lattice = channel(60, 30, [](long long i, long long j) {
    const bool throat = i < 10 || i >= 50;
    return !throat || (j >= 10 && j < 20);
  });
  const auto radius = pore_radius(lattice);
  const long long fluid = count(lattice.fluid), body = 40 * 30;
  const DrainageInlet inlet{0, false}, anywhere{0, true};
  EXPECT_EQ(count(drained_points(lattice, radius, 10.0, inlet)), 0);
  EXPECT_EQ(count(drained_points(lattice, radius, 4.6, inlet)), 0);
  // Through the throats: they fill, and the body but for its corners.
  const auto through = drained_points(lattice, radius, 4.5, inlet);
  EXPECT_GT(count(through), fluid - 40);
  EXPECT_LT(count(through), fluid);  // a ball leaves the corners between a wall and a throat's solid
  for (long long j = 10; j < 20; ++j) EXPECT_TRUE(through[static_cast<size_t>(60 * j)]) << "throat row " << j;
  // From anywhere a ball of radius 10 fills the body (but its corners), and
  // reaches into a throat only as far as a ball wider than it can poke.
  const auto body_only = drained_points(lattice, radius, 10.0, anywhere);
  EXPECT_GT(count(body_only), body / 2);
  EXPECT_LT(count(body_only), body);
  for (long long j = 0; j < 30; ++j)
    for (long long i = 0; i < 60; ++i)
      if (body_only[static_cast<size_t>(i + 60 * j)]) {
        EXPECT_TRUE(i >= 8 && i < 52) << i << " " << j;
      }
  // Entered along y instead: the walls close that face, and the rows next
  // to it are the reservoir's (a layer of centres at radius 0.5 only).
  EXPECT_EQ(count(drained_points(lattice, radius, 1.0, DrainageInlet{1, false})), 0);
}

// Trapping: a chamber below a channel 15 rows wide, joined to it by a throat
// 3 wide. The non-wetting phase enters at the low layer across x and the
// wetting phase leaves at the high one. Once the channel has drained, the
// chamber's wetting phase has no way out: with trapping it stays to the
// end; without, the smallest balls fill it through the throat.
TEST(Drainage, WettingPhaseCutOffFromTheOutletIsTrapped) {
  const auto lattice = channel(60, 30, [](long long i, long long j) {
    const bool main_channel = j >= 15, throat = (j == 13 || j == 14) && i >= 29 && i < 32,
               chamber = j >= 2 && j < 13 && i >= 20 && i < 41;
    return main_channel || throat || chamber;
  });
  const auto radius = pore_radius(lattice);
  const long long fluid = count(lattice.fluid), pocket = 21 * 11 + 2 * 3;
  auto in_pocket = [](const std::vector<char>& marks) {
    long long n = 0;
    for (long long j = 0; j < 15; ++j)
      for (long long i = 0; i < 60; ++i) n += marks[static_cast<size_t>(i + 60 * j)] != 0;
    return n;
  };
  const DrainageInlet free_flow{0, false, false}, trapping{0, false, true};
  // The channel drains alike either way (r = 6: the chamber's ball cannot pass the throat).
  EXPECT_EQ(count(drained_points(lattice, radius, 6.0, trapping)),
            count(drained_points(lattice, radius, 6.0, free_flow)));
  EXPECT_EQ(in_pocket(drained_points(lattice, radius, 6.0, trapping)), 0);
  // To the end: the pocket drains without trapping, stays with it.
  EXPECT_EQ(count(drained_points(lattice, radius, 0.5, free_flow)), fluid);
  const auto trapped_end = drained_points(lattice, radius, 0.5, trapping);
  EXPECT_EQ(in_pocket(trapped_end), 0);
  EXPECT_EQ(count(trapped_end), fluid - pocket);
  const auto curve = drainage_curve(lattice, radius, trapping);
  EXPECT_NEAR(curve.back().saturation, double(fluid - pocket) / double(fluid), 1e-12);  // the residual
  const DrainageStep all = drain_to_saturation(lattice, radius, 1.0, trapping);
  EXPECT_EQ(all.radius, 0.0);  // not reached: the pocket is trapped
}

// With trapping the cell is a sample: a chamber 15 wide at the inlet, a
// channel 4 wide, and a chamber 15 wide at the outlet, which across the
// periodic face touches the inlet's chamber. Nothing wraps across the face:
// balls of radius 6 from the inlet fill the inlet's chamber and none of the
// rest (the channel is too narrow), where without trapping (both sides of
// the face the reservoir) the outlet's chamber fills from its own side. And
// an outlet closed by solid traps all the wetting phase before any ball.
TEST(Drainage, TrappingSampleHasNoWrapAcrossItsFace) {
  const auto sample = [](bool outlet_open) {
    return channel(45, 30, [outlet_open](long long i, long long j) {
      if (i == 44 && !outlet_open) return false;
      return i < 15 || i >= 30 || (j >= 13 && j < 17);
    });
  };
  const auto beyond_inlet_chamber = [](const std::vector<char>& marks) {
    long long n = 0;
    for (long long j = 0; j < 30; ++j)
      for (long long i = 15; i < 45; ++i) n += marks[static_cast<size_t>(i + 45 * j)] != 0;
    return n;
  };
  const auto lattice = sample(true);
  const auto radius = pore_radius(lattice);
  const DrainageInlet free_flow{0, false, false}, trapping{0, false, true};
  const auto trapped = drained_points(lattice, radius, 6.0, trapping);
  EXPECT_GT(count(trapped), 300);
  EXPECT_EQ(beyond_inlet_chamber(trapped), 0);
  EXPECT_GT(beyond_inlet_chamber(drained_points(lattice, radius, 6.0, free_flow)), 300);
  const auto closed = sample(false);
  const auto closed_radius = pore_radius(closed);
  EXPECT_EQ(count(drained_points(closed, closed_radius, 0.5, trapping)), 0);
  EXPECT_EQ(drainage_curve(closed, closed_radius, trapping).back().saturation, 0.0);
}

// The target's step: the first step of the curve that reaches the
// saturation (the one before does not), the phase placed there the
// curve's row; a given radius is a row of its curve too; and a target no
// path reaches.
TEST(Drainage, SaturationTargetIsTheFirstStepThatReachesIt) {
  // Discs of radius 6 on a periodic 40 x 40 lattice, centres at (10, 10)
  // and (30, 26): uneven pores.
  DrainageLattice lattice;
  lattice.shape = {40, 40, 1};
  lattice.fluid.resize(1600);
  for (long long j = 0; j < 40; ++j)
    for (long long i = 0; i < 40; ++i) {
      auto inside = [&](double cx, double cy) {
        const double dx = std::remainder(i + 0.5 - cx, 40.0), dy = std::remainder(j + 0.5 - cy, 40.0);
        return dx * dx + dy * dy < 36.0;
      };
      lattice.fluid[static_cast<size_t>(i + 40 * j)] = !inside(10, 10) && !inside(30, 26);
    }
  const auto radius = pore_radius(lattice);
  const DrainageInlet inlet{0, false};
  const auto curve = drainage_curve(lattice, radius, inlet);
  for (double target : {0.2, 0.5, 0.8, 0.95}) {
    const DrainageStep step = drain_to_saturation(lattice, radius, target, inlet);
    ASSERT_GT(step.radius, 0.0) << target;
    EXPECT_GE(step.saturation, target);
    EXPECT_DOUBLE_EQ(step.saturation, drained_saturation(lattice, drained_points(lattice, radius, step.radius, inlet)));
    size_t row = 0;
    while (row < curve.size() && curve[row].radius != step.radius) ++row;
    ASSERT_LT(row, curve.size()) << "the step is a row of the curve, target " << target;
    EXPECT_EQ(curve[row].saturation, step.saturation);
    if (row > 0) {
      EXPECT_LT(curve[row - 1].saturation, target) << target;
    }
  }
  // A radius between two steps is a step of its own curve, with the saturation placed there.
  const double between = 0.5 * (curve[3].radius + curve[4].radius);
  const auto own = drainage_curve(lattice, radius, inlet, between);
  ASSERT_EQ(own.size(), curve.size() + 1);
  EXPECT_EQ(own[4].radius, between);
  EXPECT_EQ(own[4].saturation, drained_saturation(lattice, drained_points(lattice, radius, between, inlet)));
  // Sealed pockets: a ring of solid about a pore no path from the inlet reaches.
  auto sealed = lattice;
  for (long long j = 0; j < 40; ++j)
    for (long long i = 0; i < 40; ++i) {
      const double r = std::hypot(i + 0.5 - 30, j + 0.5 - 8);
      if (r >= 3 && r < 5) sealed.fluid[static_cast<size_t>(i + 40 * j)] = 0;
    }
  const auto sealed_radius = pore_radius(sealed);
  const DrainageStep all = drain_to_saturation(sealed, sealed_radius, 1.0, inlet);
  EXPECT_EQ(all.radius, 0.0);
  EXPECT_LT(all.saturation, 1.0);
  EXPECT_GT(all.saturation, 0.9);
}

// The curve: radii from the largest pore radius down to half a spacing, the
// saturation never falling as the radius does (drainage only adds: on the
// lattice, the balls of one radius alone can leave a film that those of
// the step before filled); full at the end.
TEST(Drainage, CurveFillsAsTheRadiusFalls) {
  // 3D: a periodic 24^3 lattice with a sphere of radius 7 and a closed
  // pore space otherwise full.
  DrainageLattice lattice;
  lattice.dimension = 3;
  lattice.shape = {24, 24, 24};
  lattice.fluid.resize(24 * 24 * 24);
  for (long long k = 0; k < 24; ++k)
    for (long long j = 0; j < 24; ++j)
      for (long long i = 0; i < 24; ++i)
        lattice.fluid[static_cast<size_t>(i + 24 * (j + 24 * k))] =
            std::hypot(i + 0.5 - 12, j + 0.5 - 12, k + 0.5 - 12) >= 7.0;
  const auto radius = pore_radius(lattice);
  const auto curve = drainage_curve(lattice, radius, DrainageInlet{2, false});
  ASSERT_GT(curve.size(), 40u);  // a quarter of a spacing apart
  EXPECT_DOUBLE_EQ(curve.back().radius, 0.5);
  EXPECT_DOUBLE_EQ(curve.back().saturation, 1.0);
  for (size_t s = 1; s < curve.size(); ++s) {
    EXPECT_LT(curve[s].radius, curve[s - 1].radius);
    EXPECT_GE(curve[s].saturation, curve[s - 1].saturation) << "at radius " << curve[s].radius;
  }
  EXPECT_GT(curve.front().saturation, 0.0);  // the largest ball fits: it is the largest pore radius
  EXPECT_LT(curve[1].saturation, 1.0);
}

}  // namespace
}  // namespace poresph
