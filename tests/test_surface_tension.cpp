// Surface tension's geometry (physics/SurfaceTension.hpp) on lattice discs
// and spheres: the shares of physics/PairTerms.hpp summed by hand over a
// lattice give the divergence of a radial unit field, 1/r (2D) and 2/r
// (3D); interface_geometry's curvature of a disc (sphere) of radius 20
// spacings is 1/R (2/R) along its interface; its colour-gradient normal
// sums to the jump of the colour across the interface.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/Kernel.hpp"
#include "physics/PairTerms.hpp"
#include "physics/SurfaceTension.hpp"

namespace poresph {
namespace {

// -div(nhat) at a lattice point a distance r from the origin of nhat = -x/|x|
// (the normal of a drop: the colour gradient points into phase 1), from
// the shares of every lattice neighbour within the support of h.
template <int Dim>
double curvature_of_radial_field(double r, double h) {
  const QuinticKernel<Dim> kernel(h);
  const long long reach = static_cast<long long>(std::ceil(kernel.cutoff));
  const auto normal = [](const Vec<Dim>& x) { return (-1.0 / std::sqrt(dot(x, x))) * x; };
  Vec<Dim> a = Vec<Dim>::zero();
  a[0] = r;
  double divergence = 0, shepard = kernel.value(0.0);
  const long long width = 2 * reach + 1;
  long long total = 1;
  for (int d = 0; d < Dim; ++d) total *= width;
  for (long long k = 0; k < total; ++k) {
    Vec<Dim> offset;
    long long rest = k;
    for (int d = 0; d < Dim; ++d, rest /= width) offset[d] = static_cast<double>(rest % width - reach);
    const double distance = std::sqrt(dot(offset, offset));
    if (distance == 0 || !(distance < kernel.cutoff)) continue;
    const Vec<Dim> b = a + offset, r_ab = (-1.0) * offset;
    divergence += normal_divergence_share<Dim>(1.0, normal(a), normal(b), r_ab, kernel.derivative_over_r(distance));
    shepard += kernel.value(distance);
  }
  return curvature_from_sums(divergence, shepard);
}

TEST(SurfaceTension, DivergenceOfARadialNormalIsTheCurvature) {
  for (const double r : {20.0, 40.0}) {
    EXPECT_NEAR(curvature_of_radial_field<2>(r, 2.0) * r, 1.0, 0.01) << r;
    EXPECT_NEAR(curvature_of_radial_field<3>(r, 2.0) * r, 2.0, 0.02) << r;
  }
}

// A disc of radius R (in spacings) at the centre of a periodic square of
// side L: its interface geometry at every lattice point, the colour phase
// 1's share of each lattice cell (16 x 16 samples) or its phase (0 or 1).
struct Disc {
  double R;
  long long L;
  bool fraction;
  std::vector<std::array<long long, 2>> points;
  std::vector<InterfacePoint<2>> geometry;
  Disc(double radius, long long side, bool by_fraction) : R(radius), L(side), fraction(by_fraction) {
    for (long long i = 0; i < L; ++i)
      for (long long j = 0; j < L; ++j) points.push_back({i, j});
    const double centre = 0.5 * static_cast<double>(L);
    const auto colour = [&](const std::array<long long, 2>& p) {
      const double x = static_cast<double>(p[0]) + 0.5 - centre, y = static_cast<double>(p[1]) + 0.5 - centre;
      if (!fraction) return std::hypot(x, y) < R ? 1.0 : 0.0;
      int inside = 0;
      for (int u = 0; u < 16; ++u)
        for (int v = 0; v < 16; ++v) inside += std::hypot(x + (u + 0.5) / 16 - 0.5, y + (v + 0.5) / 16 - 0.5) < R;
      return inside / 256.0;
    };
    geometry = interface_geometry<2>(points, {L, L}, 1.0, 1.0, colour);
  }
  double radius_of(size_t k) const {
    return std::hypot(static_cast<double>(points[k][0]) + 0.5 - 0.5 * static_cast<double>(L),
                      static_cast<double>(points[k][1]) + 0.5 - 0.5 * static_cast<double>(L));
  }
};

TEST(SurfaceTension, CurvatureOfALatticeDiscIsOneOverItsRadius) {
  const Disc disc(20.0, 80, true);
  // Along the interface (|r - R| < 0.75 spacings), every point's curvature.
  int along = 0;
  double worst = 0;
  for (size_t k = 0; k < disc.points.size(); ++k) {
    if (std::abs(disc.radius_of(k) - disc.R) >= 0.75) continue;
    ++along;
    worst = std::max(worst, std::abs(disc.geometry[k].smoothed_curvature * disc.R - 1.0));
  }
  std::printf("  disc: %d points along the interface, kappa R - 1 at most %.4f\n", along, worst);
  EXPECT_GT(along, 150);
  EXPECT_LT(worst, 0.02) << "largest relative error of kappa along the interface";
  // The normal's integral across the interface is the jump of the colour:
  // sum over a ray's side of n . r_hat dV = -(2 pi R) for phase 1 inside.
  double flux = 0;
  for (size_t k = 0; k < disc.points.size(); ++k) {
    const double x = static_cast<double>(disc.points[k][0]) + 0.5 - 40.0;
    const double y = static_cast<double>(disc.points[k][1]) + 0.5 - 40.0;
    const double r = std::hypot(x, y);
    if (r > 0) flux += (disc.geometry[k].normal[0] * x + disc.geometry[k].normal[1] * y) / r;
  }
  EXPECT_NEAR(flux / (-2 * M_PI * disc.R), 1.0, 0.02);
  // Nothing far from the interface.
  for (size_t k = 0; k < disc.points.size(); ++k)
    if (std::abs(disc.radius_of(k) - disc.R) > 4.0) {
      ASSERT_EQ(disc.geometry[k].normal[0], 0.0) << disc.radius_of(k);
      ASSERT_EQ(disc.geometry[k].smoothed_curvature, 0.0);
    }
}

TEST(SurfaceTension, CurvatureOfALatticeSphereIsTwoOverItsRadius) {
  // A sphere of R = 20 spacings at the centre of a periodic cube of 80: the
  // points along its surface only (the geometry is taken where asked).
  const double R = 20, centre = 40;
  const long long L = 80;
  std::vector<std::array<long long, 3>> points;
  std::vector<double> radii;
  for (long long i = 0; i < L; ++i)
    for (long long j = 0; j < L; ++j)
      for (long long k = 0; k < L; ++k) {
        const double r = std::sqrt(std::pow(i + 0.5 - centre, 2) + std::pow(j + 0.5 - centre, 2) +
                                   std::pow(k + 0.5 - centre, 2));
        if (std::abs(r - R) < 0.75) points.push_back({i, j, k}), radii.push_back(r);
      }
  const auto colour = [&](const std::array<long long, 3>& p) {
    int inside = 0;
    for (int u = 0; u < 8; ++u)
      for (int v = 0; v < 8; ++v)
        for (int w = 0; w < 8; ++w)
          inside += std::sqrt(std::pow(p[0] + (u + 0.5) / 8 - centre, 2) + std::pow(p[1] + (v + 0.5) / 8 - centre, 2) +
                              std::pow(p[2] + (w + 0.5) / 8 - centre, 2)) < R;
    return inside / 512.0;
  };
  const auto geometry = interface_geometry<3>(points, {L, L, L}, 1.0, 1.0, colour);
  double worst = 0;
  for (const auto& g : geometry) worst = std::max(worst, std::abs(g.smoothed_curvature * R / 2 - 1.0));
  std::printf("  sphere: %zu points along the surface, kappa R / 2 - 1 at most %.4f\n", points.size(), worst);
  EXPECT_GT(points.size(), 3000u);
  EXPECT_LT(worst, 0.02) << "largest relative error of kappa along the sphere's surface";
}

TEST(SurfaceTension, ThePhaseAsColourFollowsTheLatticesStairs) {
  // The phase (0 or 1) as colour: a staircase, whose unsmoothed curvature
  // at a point is far from 1/R even where the smoothed one is close.
  const Disc disc(20.0, 80, false);
  double worst_point = 0, worst_smoothed = 0;
  for (size_t k = 0; k < disc.points.size(); ++k) {
    if (std::abs(disc.radius_of(k) - disc.R) >= 0.75) continue;
    worst_point = std::max(worst_point, std::abs(disc.geometry[k].curvature * disc.R - 1.0));
    worst_smoothed = std::max(worst_smoothed, std::abs(disc.geometry[k].smoothed_curvature * disc.R - 1.0));
  }
  EXPECT_GT(worst_point, 0.2);
  EXPECT_LT(worst_smoothed, 0.1);
}

}  // namespace
}  // namespace poresph
