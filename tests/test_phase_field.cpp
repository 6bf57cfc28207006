// The moving interface's phase field on the lattice (physics/PhaseField.hpp):
// phi summed over the fluid is conserved to round-off by any flow, with
// walls and grains; a compressing flow leaves the bulk alone; a flat layer
// at rest keeps its profile; a layer carried by a uniform flow moves with
// it; a disc's curvature is 1/R; the wetting condition's solid neighbour
// continues a flat layer that meets the wall at the contact angle, and the
// layer's normal beside the wall makes that angle, each solid's own where
// solids wet at different angles; a flat layer meeting a wall at 90 degrees
// feels no force; a disc under the update alone stays round; and the
// surface force's grad phi (the pressure term's operator) of a uniform phi
// is zero beside walls and grains.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "physics/PhaseField.hpp"

namespace poresph {
namespace {

constexpr double kPi = 3.14159265358979323846;

LatticePhaseField<2> field(long long nx, long long ny, bool walls_in_y, double theta_degrees, double mobility,
                           std::vector<char> fluid = {}) {
  PhaseFieldSettings s;
  s.width = 1.0, s.mobility = mobility, s.cos_contact_angle = std::cos(theta_degrees * kPi / 180);
  if (fluid.empty()) fluid.assign(static_cast<std::size_t>(nx * ny), 1);
  return LatticePhaseField<2>({nx, ny}, {true, !walls_in_y}, 1.0, s, fluid);
}

// A stripe of phase 1 between x = lo and x = hi (lattice points at i + 1/2).
void fill_stripe(LatticePhaseField<2>& f, double lo, double hi) {
  for (std::size_t k = 0; k < f.size(); ++k) {
    const double x = static_cast<double>(f.point(k)[0]) + 0.5;
    f.values()[k] = phase_field_profile(x - lo, 1.0) * phase_field_profile(hi - x, 1.0);
  }
}

// The first moment of phi along x over its amount.
double centroid_x(const LatticePhaseField<2>& f) {
  double moment = 0, amount = 0;
  for (std::size_t k = 0; k < f.size(); ++k) {
    if (!f.fluid(k)) continue;
    moment += f.values()[k] * (static_cast<double>(f.point(k)[0]) + 0.5);
    amount += f.values()[k];
  }
  return moment / amount;
}

// A cell with walls below and above and a square grain, wetted at 40 degrees.
LatticePhaseField<2> walled_cell_with_grain(long long nx, long long ny) {
  std::vector<char> fluid(static_cast<std::size_t>(nx * ny), 1);
  for (long long j = 10; j < 16; ++j)
    for (long long i = 22; i < 30; ++i) fluid[static_cast<std::size_t>(j * nx + i)] = 0;
  return field(nx, ny, true, 40, 0.5, fluid);
}

// phi and the velocity at each lattice point from set(x, y, phi, v), the
// point's position in spacings; returns the velocities.
template <class Set>
std::vector<Vec<2>> set_by_position(LatticePhaseField<2>& f, Set&& set) {
  std::vector<Vec<2>> u(f.size(), Vec<2>::zero());
  for (std::size_t k = 0; k < f.size(); ++k) {
    const auto i = f.point(k);
    set(static_cast<double>(i[0]) + 0.5, static_cast<double>(i[1]) + 0.5, f.values()[k], u[k]);
  }
  return u;
}

// Any flow, one with divergence too, by walls and a grain: the advection's
// gain or loss is given back within the layer.
TEST(PhaseField, AmountIsConservedByAnyFlowWallsAndGrains) {
  const long long nx = 40, ny = 30;
  auto f = walled_cell_with_grain(nx, ny);
  const auto u = set_by_position(f, [&](double x, double y, double& phi, Vec<2>& v) {
    phi = phase_field_profile(8 - std::hypot(x - 12, y - 14), 1.0);
    v = Vec<2>{{0.3 * std::sin(2 * kPi * y / ny), 0.2 * std::cos(2 * kPi * x / nx) + 0.05 * x / nx}};
  });
  const double start = f.amount();
  for (int step = 0; step < 400; ++step) f.advance(0.1, u);
  EXPECT_NEAR(f.amount(), start, 1e-12 * start);
  EXPECT_GT(std::abs(centroid_x(f) - 12.0), 0.5);
}

// A flow that compresses (as a weakly compressible one does, a little)
// leaves a phase's bulk as it is: a cell of phase 1 alone stays phi = 1,
// with walls and a grain, however long it runs (the form d(u phi)/dx would
// pile phi up where the flow converges).
TEST(PhaseField, CompressingFlowLeavesTheBulkAlone) {
  const long long nx = 40, ny = 30;
  auto f = walled_cell_with_grain(nx, ny);
  const auto u = set_by_position(f, [&](double x, double y, double& phi, Vec<2>& v) {
    phi = 1.0;
    v = Vec<2>{{0.2 * std::sin(2 * kPi * x / nx), 0.1 * std::sin(kPi * y / ny)}};
  });
  for (int step = 0; step < 2000; ++step) f.advance(0.1, u);
  for (std::size_t k = 0; k < f.size(); ++k)
    if (f.fluid(k)) {
      EXPECT_EQ(f.values()[k], 1.0) << k;
    }
}

TEST(PhaseField, FlatLayerAtRestKeepsItsProfile) {
  auto f = field(64, 4, false, 90, 0.5);
  fill_stripe(f, 20.0, 44.0);
  const std::vector<double> start = f.values();
  for (int step = 0; step < 2000; ++step) f.advance(0.25, std::vector<Vec<2>>(f.size(), Vec<2>::zero()));
  double largest = 0;
  for (std::size_t k = 0; k < f.size(); ++k) largest = std::max(largest, std::abs(f.values()[k] - start[k]));
  // The lattice's layer differs from the continuous profile by O(dx^2 / epsilon^2), not by a drift.
  EXPECT_LT(largest, 0.03);
  EXPECT_NEAR(centroid_x(f), 32.0, 1e-9);
}

TEST(PhaseField, UniformFlowCarriesTheLayer) {
  const long long nx = 80;
  auto f = field(nx, 4, false, 90, 0.2);
  fill_stripe(f, 20.0, 40.0);
  const std::vector<Vec<2>> u(f.size(), Vec<2>{{0.1, 0.0}});
  const double dt = 0.5;
  const int steps = 400;  // 20 spacings
  for (int step = 0; step < steps; ++step) f.advance(dt, u);
  EXPECT_NEAR(centroid_x(f), 30.0 + 0.1 * dt * steps, 0.05);
  // Still a layer of phase 1 in the middle (not smeared away).
  const double middle = f.values()[f.index({50, 1})];
  EXPECT_GT(middle, 0.99);
}

// Where phi crosses 1/2 between lattice neighbours of a lattice `side`
// points a side, the distance of each crossing from (cx, cy): the spread of
// those distances measures how far a disc is from round.
std::vector<double> crossing_radii(const LatticePhaseField<2>& f, long long side, double cx, double cy) {
  std::vector<double> radii;
  for (std::size_t k = 0; k < f.size(); ++k) {
    const auto i = f.point(k);
    for (int d = 0; d < 2; ++d) {
      auto j = i;
      if (++j[d] >= side) continue;
      const double a = f.values()[k] - 0.5, b = f.values()[f.index(j)] - 0.5;
      if ((a < 0) == (b < 0)) continue;
      double x = i[0] + 0.5, y = i[1] + 0.5;
      (d == 0 ? x : y) += a / (a - b);
      radii.push_back(std::hypot(x - cx, y - cy));
    }
  }
  return radii;
}

// The Allen-Cahn update alone keeps a disc round: the sharpening's phi (1 -
// phi) on a face is the profile's at the face's distance, and the normals
// are those of the distance, so no direction of the lattice is a rest state
// the others are not. (With phi (1 - phi) of the face's mean phi and the
// normals of grad phi the same disc squares towards the axes: its crossings
// spread over 2.4 spacings, where they spread over 0.19 now.)
TEST(PhaseField, DiscUnderTheUpdateAloneStaysRound) {
  const long long side = 64;
  auto f = field(side, side, false, 90, 1.0);
  const double R = 15, centre = side / 2.0;
  const auto at_rest = set_by_position(f, [&](double x, double y, double& phi, Vec<2>&) {
    phi = phase_field_profile(R - std::hypot(x - centre, y - centre), 1.0);
  });
  const double start = f.amount();
  for (int step = 0; step < 4000; ++step) f.advance(0.2, at_rest);
  const auto radii = crossing_radii(f, side, centre, centre);
  const auto [low, high] = std::minmax_element(radii.begin(), radii.end());
  EXPECT_LT(*high - *low, 0.3);
  EXPECT_NEAR(*low, R, 0.3);
  EXPECT_NEAR(f.amount(), start, 1e-12 * start);
}

TEST(PhaseField, DiscCurvatureIsOneOverTheRadius) {
  const double R = 20;
  auto f = field(96, 96, false, 90, 0.0);
  for (std::size_t k = 0; k < f.size(); ++k) {
    const auto i = f.point(k);
    f.values()[k] = phase_field_profile(R - std::hypot(i[0] + 0.5 - 48, i[1] + 0.5 - 48), 1.0);
  }
  const double sigma = 2.0;
  const auto force = f.surface_force(sigma);
  // kappa weighted by |grad phi|^2: sum f . g / (sigma sum |g|^2).
  double fg = 0, gg = 0;
  for (std::size_t k = 0; k < f.size(); ++k) {
    const Vec<2> g = f.gradient(k);
    fg += dot(force[k], g), gg += dot(g, g);
  }
  EXPECT_NEAR(fg / (sigma * gg), 1 / R, 0.02 / R);
}

TEST(PhaseField, WettingNeighbourContinuesTheLayerThatMeetsTheWallAtItsAngle) {
  // A flat layer meeting the wall y = 0 at theta through phase 0: its normal
  // n (into phase 1) has n . e_y = cos(theta). The solid point below a fluid
  // point takes the layer's own value there, from the fluid point's alone.
  for (double theta : {20.0, 30.0, 60.0, 90.0, 120.0, 150.0, 160.0}) {
    auto f = field(8, 8, true, theta, 0.0);
    const double c = std::cos(theta * kPi / 180), s = std::sin(theta * kPi / 180);
    for (double x : {-2.3, -0.4, 0.0, 0.7, 1.9}) {
      const double above = phase_field_profile(s * x + c * 0.5, 1.0), below = phase_field_profile(s * x - c * 0.5, 1.0);
      EXPECT_NEAR(wetting_neighbour_value(above, 1.0, f.settings()), below, 1e-14) << theta << " " << x;
    }
  }
}

TEST(PhaseField, FlatLayerMeetsTheWallAtItsAngleInTheWallsRow) {
  // A flat layer of the profile at rest meeting the wall y = 0 at theta
  // (through phase 0): in the row beside the wall, wherever the layer is
  // (0.01 < phi < 0.99), the normal grad phi / |grad phi| makes theta with
  // the wall within 1.9 degrees, n . e_y = cos(theta) (the central difference
  // with the profile's solid value alone: 2.03 degrees at 20 and 160).
  for (double theta : {20.0, 30.0, 45.0, 60.0, 90.0, 120.0, 135.0, 150.0, 160.0}) {
    auto f = field(64, 12, true, theta, 0.0);
    const double c = std::cos(theta * kPi / 180), s = std::sin(theta * kPi / 180);
    for (double shift : {0.0, 0.25, 0.5}) {
      set_by_position(f, [&](double x, double y, double& phi, Vec<2>&) {
        phi = phase_field_profile(s * (x - 32 - shift) + c * y, 1.0);
      });
      double worst = 0;
      for (long long i = 0; i < 64; ++i) {
        const std::size_t k = f.index({i, 0});
        const double phi = f.values()[k];
        if (phi < 0.01 || phi > 0.99) continue;
        const Vec<2> g = f.gradient(k);
        const double angle = std::acos(g[1] / std::sqrt(dot(g, g))) * 180 / kPi;
        worst = std::max(worst, std::fabs(angle - theta));
      }
      EXPECT_LT(worst, 1.9) << theta << " " << shift;
    }
  }
}

TEST(PhaseField, EachSolidWetsAtItsOwnAngle) {
  // Solid rows at j = 0 and j = ny - 1 (faces at y = 1 and y = ny - 1), each
  // with its own angle, the settings' 90 degrees for neither: a flat layer
  // meeting a solid at that solid's angle has its normal at that angle in
  // the row beside it, within the 1.9 degrees of one angle everywhere.
  const long long nx = 64, ny = 14;
  for (const auto& [lower, upper] : {std::pair{30.0, 120.0}, std::pair{150.0, 60.0}}) {
    PhaseFieldSettings settings;
    settings.width = 1.0, settings.mobility = 0.0, settings.cos_contact_angle = 0.0;
    std::vector<char> fluid(static_cast<std::size_t>(nx * ny), 1);
    std::vector<double> solid_cos(fluid.size(), 0.0);
    for (long long i = 0; i < nx; ++i) {
      fluid[static_cast<std::size_t>(i)] = fluid[static_cast<std::size_t>((ny - 1) * nx + i)] = 0;
      solid_cos[static_cast<std::size_t>(i)] = std::cos(lower * kPi / 180);
      solid_cos[static_cast<std::size_t>((ny - 1) * nx + i)] = std::cos(upper * kPi / 180);
    }
    LatticePhaseField<2> f({nx, ny}, {true, true}, 1.0, settings, fluid, solid_cos);
    // at_lower: the layer meets the lower solid (n . e_y = cos), else the upper (n . -e_y = cos).
    for (bool at_lower : {true, false}) {
      const double theta = at_lower ? lower : upper;
      const double c = std::cos(theta * kPi / 180), s = std::sin(theta * kPi / 180);
      set_by_position(f, [&](double x, double y, double& phi, Vec<2>&) {
        phi = phase_field_profile(s * (x - 32.25) + (at_lower ? c * (y - 1) : -c * (y - (ny - 1))), 1.0);
      });
      const long long row = at_lower ? 1 : ny - 2;
      double worst = 0;
      for (long long i = 0; i < nx; ++i) {
        const std::size_t k = f.index({i, row});
        if (f.values()[k] < 0.01 || f.values()[k] > 0.99) continue;
        const Vec<2> g = f.gradient(k);
        const double angle = std::acos((at_lower ? g[1] : -g[1]) / std::sqrt(dot(g, g))) * 180 / kPi;
        worst = std::max(worst, std::fabs(angle - theta));
      }
      EXPECT_LT(worst, 1.9) << lower << " " << upper << " " << at_lower;
    }
  }
}

// The surface force's grad phi is the pressure term's operator, with the
// solid points and the points beyond a wall taking the fluid's phi
// extrapolated as a wall's pressure is: a uniform phi has no gradient
// anywhere, beside walls and a grain too, as a uniform pressure pushes
// nowhere. (Left out of the sum, the solid would pull on every point
// within the kernel's reach of it.)
TEST(PhaseField, UniformPhiHasNoPressureGradientBesideWallsAndGrains) {
  auto f = walled_cell_with_grain(40, 30);
  for (double& phi : f.values()) phi = 0.7;
  f.extrapolate_to_walls();
  double largest = 0;
  for (std::size_t k = 0; k < f.size(); ++k)
    if (f.fluid(k)) largest = std::max(largest, std::sqrt(dot(f.pressure_gradient(k), f.pressure_gradient(k))));
  EXPECT_LT(largest, 1e-13);
  // A wave along the walls: its gradient up to the lattice sum's error;
  // across, none beyond the kernel's reach of the walls, and within it what
  // the Shepard mean (exact for a constant only) leaves, as it leaves a
  // wall's pressure.
  auto g = field(40, 30, true, 90, 0.0);
  const double wave = 2 * kPi / 40, scale = 0.01 * wave;
  for (std::size_t k = 0; k < g.size(); ++k) g.values()[k] = 0.3 + 0.01 * std::sin(wave * (g.point(k)[0] + 0.5));
  g.extrapolate_to_walls();
  for (std::size_t k = 0; k < g.size(); ++k) {
    const auto i = g.point(k);
    const Vec<2> grad = g.pressure_gradient(k);
    EXPECT_NEAR(grad[0], scale * std::cos(wave * (i[0] + 0.5)), 0.02 * scale) << k;
    const bool beside_a_wall = i[1] < 3 || i[1] >= 27;
    EXPECT_NEAR(grad[1], 0.0, beside_a_wall ? 0.02 * scale : 1e-13) << k;
  }
}

TEST(PhaseField, LayerMeetingAWallAtNinetyDegreesFeelsNoForce) {
  auto f = field(64, 24, true, 90, 0.0);
  fill_stripe(f, 20.0, 44.0);
  const auto force = f.surface_force(1.0);
  double largest = 0, scale = 0;
  for (std::size_t k = 0; k < f.size(); ++k) {
    largest = std::max(largest, std::sqrt(dot(force[k], force[k])));
    scale = std::max(scale, std::sqrt(dot(f.gradient(k), f.gradient(k))));
  }
  // Beyond round-off only where phi is flat to e^-12 (mid-stripe, where
  // the normal turns): there the force is that of a disc of 10^4 spacings.
  EXPECT_LT(largest, 1e-4 * scale);
  // At 45 degrees the wall pulls the layer's ends: the force is not zero.
  auto tilted = field(64, 24, true, 45, 0.0);
  tilted.values() = f.values();
  const auto pulled = tilted.surface_force(1.0);
  double strongest = 0;
  for (const auto& v : pulled) strongest = std::max(strongest, std::sqrt(dot(v, v)));
  EXPECT_GT(strongest, 1e-2 * scale);
}

}  // namespace
}  // namespace poresph
