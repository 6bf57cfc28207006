// An image as the solid (geometry/Solid.hpp): the distance field read
// between voxel centres, its smoothing, the width of the widest pore path,
// and the lattice filled from an image against the same solid as a grain.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "geometry/DistanceTransform.hpp"
#include "geometry/Grains.hpp"
#include "geometry/Lattice.hpp"
#include "geometry/Percolation.hpp"
#include "geometry/Solid.hpp"
#include "VoxelSketch.hpp"

namespace poresph {
namespace {

constexpr std::array<bool, 3> kPeriodic{{true, true, true}};

using testing::sketch;

// A periodic 2D scene whose solid is the voxels of value 1 of `voxels`,
// each `voxel` wide, the cell their extent, walls made as a run makes them.
SceneConfig scene_of_image(const VoxelImage& voxels, double voxel) {
  SceneConfig scene;
  scene.dimension = 2;
  scene.cell_size = {voxels.shape[0] * voxel, voxels.shape[1] * voxel, 0};
  scene.image.voxels = std::make_shared<const VoxelImage>(voxels);
  scene.image.voxel_size = voxel;
  scene.image.solid_values = {1};
  scene.image.distance = std::make_shared<const std::vector<float>>(surface_distance(voxels, {1}, voxel, kPeriodic));
  return scene;
}

// Between voxel centres the field is interpolated linearly (a linear field
// exactly), and across a periodic face it joins the last voxel to the first.
TEST(DistanceField, InterpolatesBetweenVoxelCentresAndAcrossPeriodicFaces) {
  const std::array<long long, 3> shape{{12, 10, 1}};
  std::vector<float> values(120);
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 12; ++i) values[i + 12 * j] = static_cast<float>(0.5 * i - 0.25 * j);
  const auto bounded = host_distance_field<2>(values, shape, 0.1, {false, false, false});
  const double inside[2] = {0.57, 0.51};  // u = 5.2, 4.6 voxels from the first centres
  EXPECT_NEAR(bounded.value(inside), 0.5 * 5.2 - 0.25 * 4.6, 1e-6);
  double n[2];
  bounded.normal(inside, n);  // the gradient (5, -2.5) per m
  EXPECT_NEAR(n[0], 2 / std::sqrt(5.0), 1e-6);
  EXPECT_NEAR(n[1], -1 / std::sqrt(5.0), 1e-6);
  // Beyond a bounded side's last centre: that voxel's value.
  const double outside[2] = {1.19, 0.05};
  EXPECT_NEAR(bounded.value(outside), 0.5 * 11, 1e-6);
  // Periodic: on the face x = 0, halfway between voxel 11 and voxel 0.
  const auto periodic = host_distance_field<2>(values, shape, 0.1, kPeriodic);
  const double face[2] = {0.0, 0.05};
  EXPECT_NEAR(periodic.value(face), 0.5 * (5.5 + 0.0), 1e-6);
  const double one_cell_on[2] = {1.2, 1.05};  // the same point one cell further in x and y
  EXPECT_NEAR(periodic.value(one_cell_on), periodic.value(face), 1e-6);
}

// The smoothing keeps a plane surface's distance (linear) where it is, and
// takes the corners off the staircase of a diagonal one.
TEST(DistanceField, SmoothingKeepsPlanesAndRoundsTheStaircase) {
  const std::array<long long, 3> shape{{6, 5, 1}};
  std::vector<double> linear(30);
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 6; ++i) linear[i + 6 * j] = 0.3 * i - 0.7 * j + 0.1;
  const auto smoothed = smoothed_at_voxel_scale(linear, shape, 2, {false, false, false});
  for (size_t n = 0; n < linear.size(); ++n) EXPECT_NEAR(smoothed[n], linear[n], 1e-6) << n;

  // A half plane cut along the diagonal: the staircase distance departs
  // from the true one at each step, the smoothed one much less.
  VoxelImage steps;
  steps.shape = {32, 32, 1};
  steps.values.resize(32 * 32);
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i) steps.values[steps.index(i, j)] = i + j < 32 ? 1 : 0;
  const auto raw = signed_distance(steps, {1}, 1.0, kPeriodic);
  const auto smooth = smoothed_at_voxel_scale(raw, steps.shape, 2, kPeriodic);
  double raw_error = 0, smooth_error = 0;
  for (int j = 8; j < 24; ++j)
    for (int i = 8; i < 24; ++i) {
      // The staircase's own plane keeps its area: x + y = 32.5, so i + j = 31.5 through the voxel centres.
      if (std::abs(i + j - 31.5) > 3) continue;
      const double exact = (i + j - 31.5) / std::sqrt(2.0);
      raw_error = std::max(raw_error, std::abs(raw[steps.index(i, j)] - exact));
      smooth_error = std::max(smooth_error, std::abs(smooth[steps.index(i, j)] - exact));
    }
  EXPECT_GT(raw_error, 0.1);
  EXPECT_LT(smooth_error, 0.6 * raw_error);
}

// The distance the walls are built from, on a disk of radius 54 voxels
// drawn by its voxel centres: at the pore voxels within three voxels of the
// circle it is unbiased to about a hundredth of a voxel, where the
// staircase's own distance (nearest solid centre less half a voxel) reads
// the circle too far out; and on a plane at an irrational angle it is
// within a fifth of a voxel everywhere near the surface.
TEST(SurfaceDistance, FindsTheSurfaceBetweenTheVoxels) {
  VoxelImage disk;
  disk.shape = {160, 160, 1};
  disk.values.resize(160 * 160);
  const double cx = 80.3, cy = 79.6, radius = 54.2;
  for (int j = 0; j < 160; ++j)
    for (int i = 0; i < 160; ++i) disk.values[disk.index(i, j)] = std::hypot(i + 0.5 - cx, j + 0.5 - cy) < radius;
  const auto between = surface_distance(disk, {1}, 1.0, kPeriodic);
  const auto staircase = signed_distance(disk, {1}, 1.0, kPeriodic);
  double bias_between = 0, bias_staircase = 0, worst = 0;
  int near = 0;
  for (int j = 0; j < 160; ++j)
    for (int i = 0; i < 160; ++i) {
      const double exact = std::hypot(i + 0.5 - cx, j + 0.5 - cy) - radius;
      if (exact <= 0 || exact > 3) continue;
      ++near;
      bias_between += between[disk.index(i, j)] - exact;
      bias_staircase += staircase[disk.index(i, j)] - exact;
      worst = std::max(worst, std::abs(between[disk.index(i, j)] - exact));
    }
  bias_between /= near, bias_staircase /= near;
  EXPECT_LT(std::abs(bias_between), 0.03);  // measured 0.012
  EXPECT_LT(bias_staircase, -0.05);         // measured -0.069
  // Where the circle runs along the voxels (its bottom), a row of voxels
  // says only that the surface is within their half: up to half a voxel.
  EXPECT_LT(worst, 0.51);

  VoxelImage slope;
  slope.shape = {64, 64, 1};
  slope.values.resize(64 * 64);
  const double nx = std::cos(0.37), ny = std::sin(0.37);  // solid where n.x < 20.3
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) slope.values[slope.index(i, j)] = nx * (i + 0.5) + ny * (j + 0.5) < 20.3;
  const auto plane = surface_distance(slope, {1}, 1.0, {false, false, false});
  double plane_worst = 0;
  for (int j = 8; j < 56; ++j)
    for (int i = 8; i < 56; ++i) {
      const double exact = nx * (i + 0.5) + ny * (j + 0.5) - 20.3;
      if (std::abs(exact) > 4) continue;
      plane_worst = std::max(plane_worst, std::abs(plane[slope.index(i, j)] - exact));
    }
  EXPECT_LT(plane_worst, 0.25);  // the staircase's ripple through the blur: measured 0.20
}

// The widest pore path's width: a straight channel of n voxels reads n
// (odd) or n - 1 (even); of two channels, the wider; where a channel
// narrows, its narrowest part; no path, 0.
TEST(WidestPath, ChannelWidthsAreReadToWithinAVoxelFromBelow) {
  auto width_of = [](const VoxelImage& image, int axis) {
    return widest_path_width(signed_distance(image, {1}, 1.0, kPeriodic), image.shape, 2, axis, kPeriodic);
  };
  const auto three = sketch({"########", "........", "........", "........", "########", "########"});
  EXPECT_DOUBLE_EQ(width_of(three, 0), 3.0);
  EXPECT_DOUBLE_EQ(width_of(three, 1), 0.0);
  const auto four = sketch({"########", "........", "........", "........", "........", "########"});
  EXPECT_DOUBLE_EQ(width_of(four, 0), 3.0);
  const auto two_channels = sketch({"##########", "..........", "##########", "..........", "..........",
                                    "..........", "..........", "..........", "##########", "##########"});
  EXPECT_DOUBLE_EQ(width_of(two_channels, 0), 5.0);
  const auto narrowing = sketch({"##########", "..........", ".....#####", "..........", "##########",
                                 "##########"});
  EXPECT_DOUBLE_EQ(width_of(narrowing, 0), 1.0);
}

// A disk drawn in voxels four to a particle spacing, and the same disk as a
// grain: the lattice points agree on fluid and solid except in a band of
// about a voxel at the surface; an image boundary particle's plane, and a
// fluid particle's own distance and normal within 3h of the surface, have
// the disk's radial normal to a few degrees and its distance to within
// half a voxel.
TEST(ImageLattice, DiskFromVoxelsFillsTheLatticeAsTheGrainDoes) {
  SceneConfig scene;
  scene.dimension = 2;
  scene.cell_size = {1.0, 1.0, 0};
  scene.particle_spacing = 0.02;
  const double cx = 0.43, cy = 0.61, radius = 0.27, voxel = 0.005;
  VoxelImage disk;
  disk.shape = {200, 200, 1};
  disk.values.resize(200 * 200);
  for (int j = 0; j < 200; ++j)
    for (int i = 0; i < 200; ++i)
      disk.values[disk.index(i, j)] = std::hypot((i + 0.5) * voxel - cx, (j + 0.5) * voxel - cy) < radius;
  SceneConfig from_image = scene_of_image(disk, voxel);
  from_image.particle_spacing = scene.particle_spacing;
  SceneConfig from_grain = scene;
  from_grain.grains = grains_from_list({cx, cy, radius}, 2);

  const auto image_seeds = fill_lattice<2>(from_image);
  const auto grain_seeds = fill_lattice<2>(from_grain);
  auto kind_at = [](const std::vector<SeedParticle<2>>& seeds) {
    std::vector<int> kinds(50 * 50, -1);  // -1: no particle (buried)
    for (const auto& s : seeds) kinds[static_cast<int>(s.x[0] / 0.02) + 50 * static_cast<int>(s.x[1] / 0.02)] = s.kind;
    return kinds;
  };
  const auto image_kinds = kind_at(image_seeds), grain_kinds = kind_at(grain_seeds);
  int boundary = 0;
  for (int n = 0; n < 50 * 50; ++n) {
    const double x = (n % 50 + 0.5) * 0.02, y = (n / 50 + 0.5) * 0.02;
    const double surface = std::hypot(x - cx, y - cy) - radius;  // the exact signed distance
    const bool image_fluid = image_kinds[n] == kFluid, grain_fluid = grain_kinds[n] == kFluid;
    if (std::abs(surface) > voxel) {
      EXPECT_EQ(image_fluid, grain_fluid) << x << ", " << y;
    }
    const bool image_buried = image_kinds[n] == -1, grain_buried = grain_kinds[n] == -1;
    if (std::abs(surface + 3 * scene.particle_spacing) > voxel) {
      EXPECT_EQ(image_buried, grain_buried) << x << ", " << y;
    }
  }
  int fluid_with_surface = 0;
  for (const auto& s : image_seeds) {
    const double rx = s.x[0] - cx, ry = s.x[1] - cy, r = std::hypot(rx, ry);
    const double cos_to_radial = (s.wall_vector[0] * rx + s.wall_vector[1] * ry) / r;
    if (s.kind == kFluid) {
      // Within 3h of the surface: its own distance and normal; beyond: none
      // (within a voxel of 3h: either).
      const double reach = 3 * scene.particle_spacing;
      if (r - radius > reach + voxel) {
        EXPECT_EQ(s.wall_scalar, 0.0) << s.x[0] << ", " << s.x[1];
      }
      if (s.wall_scalar == 0.0) {
        EXPECT_GT(r - radius, reach - voxel) << s.x[0] << ", " << s.x[1];
        continue;
      }
      ++fluid_with_surface;
      EXPECT_NEAR(s.wall_scalar, r - radius, 0.5 * voxel) << s.x[0] << ", " << s.x[1];
      EXPECT_GT(cos_to_radial, std::cos(4 * M_PI / 180)) << s.x[0] << ", " << s.x[1];
      continue;
    }
    ASSERT_EQ(s.kind, kSampledBoundary);  // the tangent plane: normal into the pore, depth below the surface
    ++boundary;
    EXPECT_NEAR(s.wall_scalar, radius - r, 0.5 * voxel) << s.x[0] << ", " << s.x[1];
    EXPECT_GT(cos_to_radial, std::cos(4 * M_PI / 180)) << s.x[0] << ", " << s.x[1];
  }
  EXPECT_GT(fluid_with_surface, 200);
  EXPECT_GT(boundary, 200);
}

// The narrow pore of an image: between two rows of disks 40 voxels apart,
// every passage is 40 voxels wide. No ball of 10 voxels misses any of the
// pore; one of 50 fits nowhere near the gaps, which it leaves uncovered.
TEST(NarrowPore, PoreNoBallOfTheWidthCoversIsCounted) {
  VoxelImage disks;
  disks.shape = {200, 100, 1};
  disks.values.resize(200 * 100);
  for (int j = 0; j < 100; ++j)
    for (int i = 0; i < 200; ++i)
      disks.values[disks.index(i, j)] = std::hypot(i + 0.5 - 50, j + 0.5 - 50) < 30 ||
                                        std::hypot(i + 0.5 - 150, j + 0.5 - 50) < 30;
  const SceneConfig scene = scene_of_image(disks, 1.0);
  EXPECT_LT(pore_fraction_narrower_than(scene, 10.0), 0.002);
  EXPECT_GT(pore_fraction_narrower_than(scene, 50.0), 0.02);  // measured 0.039: the necks of the gaps
}

// Grains and an image alike answer the solid's questions in kernels: how
// deep a point lies and which way is out.
TEST(SolidMap, ImagePointsInsideTheSolidAreFoundWithTheirDepth) {
  VoxelImage slab;
  slab.shape = {10, 10, 1};
  slab.values.resize(100);
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 10; ++i) slab.values[slab.index(i, j)] = j < 6;  // solid below y = 0.6
  const SceneConfig scene = scene_of_image(slab, 0.1);
  const auto map = make_solid_map<2, Kokkos::HostSpace>(scene, 0.1);
  double depth, normal[2];
  const double below[2] = {0.33, 0.52};
  EXPECT_EQ(map.deepest(below, depth, normal), 0);
  EXPECT_NEAR(depth, 0.08, 1e-6);
  EXPECT_NEAR(normal[1], 1.0, 1e-6);
  const double above[2] = {0.33, 0.65};
  EXPECT_EQ(map.deepest(above, depth, normal), -1);
}

}  // namespace
}  // namespace poresph
