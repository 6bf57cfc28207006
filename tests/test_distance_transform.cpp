// The distance transform of voxel images: exact against every pair of
// voxels, periodic across the faces, and the signed distance of a
// rasterised circle and sphere within the staircase's bound of theirs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "geometry/DistanceTransform.hpp"

namespace poresph {
namespace {

// min over sites of the squared distance, periodic axes wrapped: every pair of voxels.
std::vector<double> brute_force(const std::array<long long, 3>& shape, const std::array<bool, 3>& periodic,
                                const std::vector<char>& site) {
  const long long count = shape[0] * shape[1] * shape[2];
  std::vector<double> d(count, std::numeric_limits<double>::infinity());
  auto coordinates = [&](long long n) {
    return std::array<long long, 3>{{n % shape[0], n / shape[0] % shape[1], n / (shape[0] * shape[1])}};
  };
  for (long long p = 0; p < count; ++p)
    for (long long q = 0; q < count; ++q) {
      if (!site[q]) continue;
      const auto a = coordinates(p), b = coordinates(q);
      double s = 0;
      for (int axis = 0; axis < 3; ++axis) {
        long long delta = std::abs(a[axis] - b[axis]);
        if (periodic[axis]) delta = std::min(delta, shape[axis] - delta);
        s += static_cast<double>(delta * delta);
      }
      d[p] = std::min(d[p], s);
    }
  return d;
}

TEST(DistanceTransform, ExactAgainstEveryPairOfVoxels) {
  std::mt19937 random(7);
  struct Case {
    std::array<long long, 3> shape;
    int dimension;
    std::array<bool, 3> periodic;
    double site_fraction;
  };
  const Case cases[] = {{{17, 11, 1}, 2, {false, false, false}, 0.05},
                        {{17, 11, 1}, 2, {true, true, false}, 0.02},
                        {{13, 9, 1}, 2, {true, false, false}, 0.3},
                        {{9, 7, 6}, 3, {true, true, true}, 0.01},
                        {{9, 7, 6}, 3, {false, true, false}, 0.1}};
  for (const auto& c : cases) {
    const long long count = c.shape[0] * c.shape[1] * c.shape[2];
    std::vector<char> site(count);
    std::bernoulli_distribution draw(c.site_fraction);
    long long sites = 0;
    for (auto& s : site) sites += (s = draw(random));
    ASSERT_GT(sites, 0);
    const auto expected = brute_force(c.shape, c.periodic, site);
    const auto found = squared_distance_transform(c.shape, c.dimension, c.periodic, site);
    ASSERT_EQ(found.size(), expected.size());
    for (long long n = 0; n < count; ++n)
      ASSERT_EQ(found[n], expected[n]) << "voxel " << n << " of " << c.shape[0] << " x " << c.shape[1] << " x "
                                       << c.shape[2];
  }
}

TEST(DistanceTransform, ReachesAcrossAPeriodicFaceOnlyWhenPeriodic) {
  // One site at x = 0 of a line of 10: x = 9 is 1 away through the face, 9 without.
  std::vector<char> site(10, 0);
  site[0] = 1;
  const auto wrapped = squared_distance_transform({10, 1, 1}, 2, {true, true, true}, site);
  const auto bounded = squared_distance_transform({10, 1, 1}, 2, {false, false, false}, site);
  EXPECT_EQ(wrapped[9], 1.0);
  EXPECT_EQ(wrapped[5], 25.0);
  EXPECT_EQ(bounded[9], 81.0);
  const auto none = squared_distance_transform({10, 1, 1}, 2, {true, true, true}, std::vector<char>(10, 0));
  EXPECT_TRUE(std::isinf(none[3]));
}

// A ball of radius R voxels rasterised (solid where the voxel centre is
// inside) against its exact signed distance |x - c| - R. The nearest solid
// centre is inside the ball, so no further than the surface, and a solid
// centre lies within sqrt(D) of every surface point: the voxel distance less
// half a voxel is within max(1/2, sqrt(D) - 1/2) voxel of the exact one.
void expect_ball_distance(int dimension, long long n, double radius) {
  VoxelImage image;
  image.dimension = dimension;
  image.shape = {n, n, dimension == 3 ? n : 1};
  image.values.assign(static_cast<size_t>(image.count()), 0);
  const double centre = 0.4 * n + 0.123;  // off the voxel grid and off the cell's middle
  auto exact = [&](long long i, long long j, long long k) {
    const double x = i + 0.5 - centre, y = j + 0.5 - centre, z = dimension == 3 ? k + 0.5 - centre : 0.0;
    return std::sqrt(x * x + y * y + z * z) - radius;
  };
  for (long long k = 0; k < image.shape[2]; ++k)
    for (long long j = 0; j < n; ++j)
      for (long long i = 0; i < n; ++i)
        if (exact(i, j, k) < 0) image.values[image.index(i, j, k)] = 1;
  const double voxel = 1e-3;
  // Not periodic: the ball's distance is to the one ball, not to its images.
  const auto distance = signed_distance(image, {1}, voxel, {false, false, false});
  const double bound = std::max(0.5, std::sqrt(static_cast<double>(dimension)) - 0.5) + 1e-12;
  double worst = 0;
  for (long long k = 0; k < image.shape[2]; ++k)
    for (long long j = 0; j < n; ++j)
      for (long long i = 0; i < n; ++i) {
        const double found = distance[image.index(i, j, k)] / voxel, expected = exact(i, j, k);
        ASSERT_EQ(found > 0, expected >= 0) << i << " " << j << " " << k;  // the sign is the phase
        worst = std::max(worst, std::abs(found - expected));
        // Beside a voxel of the other phase across a face, the surface is that face: half a voxel away.
        bool face = false;
        const long long at[3] = {i, j, k};
        for (int axis = 0; axis < dimension; ++axis)
          for (int step : {-1, 1}) {
            long long next[3] = {at[0], at[1], at[2]};
            next[axis] += step;
            if (next[axis] < 0 || next[axis] >= n) continue;
            face = face || image.at(next[0], next[1], next[2]) != image.at(i, j, k);
          }
        if (face) {
          EXPECT_DOUBLE_EQ(distance[image.index(i, j, k)], (expected >= 0 ? 0.5 : -0.5) * voxel);
        }
      }
  // A distance that is not Euclidean (city block, chessboard) is off by a
  // good fraction of the distance along the diagonals: many voxels here.
  EXPECT_LE(worst, bound);
  EXPECT_GT(worst, 0.1);  // the staircase is there: this is the voxels' distance, not the ball's own
}

TEST(DistanceTransform, SignedDistanceOfARasterisedCircle) { expect_ball_distance(2, 64, 13.3); }

TEST(DistanceTransform, SignedDistanceOfARasterisedSphere) { expect_ball_distance(3, 32, 7.7); }

}  // namespace
}  // namespace poresph
