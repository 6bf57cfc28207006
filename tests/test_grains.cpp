// Grains: reading, checks before any work, lattice filling, porosity.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <tuple>

#include "geometry/GrainMap.hpp"
#include "geometry/Solid.hpp"
#include "geometry/Grains.hpp"
#include "geometry/Lattice.hpp"
#include "physics/GrainContact.hpp"
#include "ErrorOf.hpp"

namespace poresph {
namespace {

using testing::error_of;

SceneConfig unit_cell(double dx = 0.02) {
  SceneConfig s;
  s.dimension = 2;
  s.cell_size = {1.0, 1.0, 0};
  s.particle_spacing = dx;
  s.kinematic_viscosity = 1e-3;
  s.end_time = 1;
  return s;
}

std::string write_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path.string();
}

TEST(Grains, FileWithCommentsAndBlankLines) {
  const auto path = write_file("grains-ok.txt", "# cx cy r\n0.5 0.5 0.2   # centre\n\n  0.1 0.9 0.05\n");
  const auto grains = read_grain_file(path, 2);
  ASSERT_EQ(grains.size(), 2u);
  EXPECT_EQ(grains[1].centre[0], 0.1);
  EXPECT_EQ(grains[1].radius, 0.05);
  EXPECT_NE(grains[1].origin.find(":4"), std::string::npos);
}

TEST(Grains, FileErrorsNameTheLine) {
  const auto path = write_file("grains-bad.txt", "0.5 0.5 0.2\n0.5 x 0.1\n");
  EXPECT_NE(error_of([&] { read_grain_file(path, 2); }).find(":2"), std::string::npos);
  const auto short_line = write_file("grains-short.txt", "0.5 0.5\n");
  EXPECT_NE(error_of([&] { read_grain_file(short_line, 2); }).find("expected 3 numbers"), std::string::npos);
  EXPECT_NE(error_of([&] { read_grain_file("/nonexistent/grains.txt", 2); }).find("cannot open"), std::string::npos);
}

// Moving grains may each take their solid's density as a last column,
// under a header that names it; a column more without one is refused (it
// may be an id), as is a line without the density the header promises.
TEST(Grains, FileGivesEachGrainItsDensityUnderAHeaderNamingIt) {
  const auto path = write_file("grains-density.txt", "# two grains\ncx cy r density\n0.3 0.3 0.1 2500\n0.7 0.7 0.05 1200\n");
  const auto grains = read_grain_file(path, 2);
  ASSERT_EQ(grains.size(), 2u);
  EXPECT_EQ(grains[0].density, 2500.0);
  EXPECT_EQ(grains[1].density, 1200.0);
  EXPECT_EQ(grains[1].radius, 0.05);
  EXPECT_EQ(read_grain_file(write_file("grains-rho.csv", "x,y,r,rho\n0.3,0.3,0.1,2500\n"), 2)[0].density, 2500.0);
  EXPECT_EQ(read_grain_file(write_file("grains-plain.txt", "0.3 0.3 0.1\n"), 2)[0].density, 0.0);
  const auto no_header = write_file("grains-no-header.txt", "0.3 0.3 0.1 2500\n");
  EXPECT_NE(error_of([&] { read_grain_file(no_header, 2); })
                .find(":1: expected 3 numbers (cx cy r), found 4 (as a file of 3D grains has); a density column needs "
                      "a first line naming the columns"),
            std::string::npos)
      << error_of([&] { read_grain_file(no_header, 2); });
  const auto missing = write_file("grains-missing-density.txt", "cx cy r density\n0.3 0.3 0.1 2500\n0.7 0.7 0.05\n");
  EXPECT_NE(error_of([&] { read_grain_file(missing, 2); }).find(":3: expected 4 numbers (cx cy r density"),
            std::string::npos)
      << error_of([&] { read_grain_file(missing, 2); });
  const auto id_header = write_file("grains-id.txt", "id cx cy r\n1 0.3 0.3 0.1\n");
  EXPECT_NE(error_of([&] { read_grain_file(id_header, 2); }).find(":1: the header names 4 columns"), std::string::npos);
  const auto zero = write_file("grains-zero-density.txt", "cx cy r density\n0.3 0.3 0.1 0\n");
  EXPECT_NE(error_of([&] { read_grain_file(zero, 2); }).find(":2: density 0 kg/m^3: a grain's density must be positive"),
            std::string::npos);
  // grains_used.txt keeps the column and reads back to the same bits.
  SceneConfig scene = unit_cell();
  scene.grains = grains;
  const auto again = read_grain_file(write_file("grains-density-again.txt", grains_used_text(scene)), 2);
  ASSERT_EQ(again.size(), 2u);
  for (size_t g = 0; g < 2; ++g) {
    EXPECT_EQ(again[g].density, grains[g].density);
    EXPECT_EQ(again[g].radius, grains[g].radius);
  }
}

TEST(Grains, InlineListNeedsWholeGrains) {
  EXPECT_EQ(grains_from_list({0.5, 0.5, 0.1, 0.2, 0.2, 0.05}, 2).size(), 2u);
  EXPECT_FALSE(error_of([] { grains_from_list({0.5, 0.5, 0.1, 0.2}, 2); }).empty());
}

TEST(Grains, ChecksRefuseBadGrainsNamingThem) {
  SceneConfig scene = unit_cell();
  auto grains = grains_from_list({0.5, 0.5, 0.0}, 2);
  EXPECT_NE(error_of([&] { check_grains(grains, scene); }).find("Grains/Inline #1"), std::string::npos);
  grains = grains_from_list({0.5, 0.5, 0.6}, 2);
  EXPECT_NE(error_of([&] { check_grains(grains, scene); }).find("wider than the cell"), std::string::npos);
  // Overlap across the periodic boundary: centres 0.05 and 0.95 are 0.1 apart.
  grains = grains_from_list({0.05, 0.5, 0.06, 0.95, 0.5, 0.06}, 2);
  const auto message = error_of([&] { check_grains(grains, scene); });
  EXPECT_NE(message.find("#1 and Grains/Inline #2 overlap"), std::string::npos) << message;
  scene.allow_overlapping_grains = true;
  EXPECT_TRUE(error_of([&] { check_grains(grains, scene); }).empty());
}

TEST(Grains, PorosityExactAndSampled) {
  SceneConfig scene = unit_cell();
  EXPECT_NEAR(porosity(grains_from_list({0.5, 0.5, 0.2}, 2), scene), 1 - M_PI * 0.04, 1e-15);
  // Two overlapping grains (lens area known in closed form).
  scene.allow_overlapping_grains = true;
  const double r = 0.2, d = 0.2;
  const double lens = 2 * r * r * std::acos(d / (2 * r)) - 0.5 * d * std::sqrt(4 * r * r - d * d);
  EXPECT_NEAR(porosity(grains_from_list({0.4, 0.5, r, 0.6, 0.5, r}, 2), scene), 1 - (2 * M_PI * r * r - lens), 2e-4);
}

// Every fluid point lies outside every grain (periodic images included);
// every grain boundary particle lies in its grain's shell r - 3h .. r.
TEST(Grains, LatticeFillingRespectsGrainsAcrossTheCorner) {
  SceneConfig scene = unit_cell(0.02);
  scene.grains = grains_from_list({0.02, 0.97, 0.15, 0.5, 0.5, 0.2}, 2);  // the first crosses the corner
  const double shell = 3 * scene.particle_spacing, rounding = 1e-9 * scene.particle_spacing;
  const auto seeds = fill_lattice<2>(scene);
  int boundary_near_corner[4] = {0, 0, 0, 0};  // one per quadrant of the cell
  for (const auto& s : seeds) {
    const std::array<double, 3> p{s.x[0], s.x[1], 0};
    double nearest_surface = 1e9;
    for (const auto& g : scene.grains) {
      const auto d = periodic_difference(p, g.centre, scene);
      nearest_surface = std::min(nearest_surface, std::hypot(d[0], d[1]) - g.radius);
    }
    if (s.kind == kFluid) {
      EXPECT_GT(nearest_surface, 0.0) << s.x[0] << ", " << s.x[1];
    } else {
      EXPECT_EQ(s.kind, kGrainBoundary);
      EXPECT_LE(nearest_surface, rounding);  // on the surface counts as in the solid
      EXPECT_GE(nearest_surface, -shell - rounding);
      // The stored offset and radius describe the grain image the particle belongs to.
      EXPECT_NEAR(std::hypot(s.wall_vector[0], s.wall_vector[1]) - s.wall_scalar, nearest_surface, 1e-12);
      if (std::hypot(s.wall_vector[0], s.wall_vector[1]) > 0 && s.wall_scalar == 0.15)
        ++boundary_near_corner[(s.x[0] > 0.5) + 2 * (s.x[1] > 0.5)];
    }
  }
  for (int q = 0; q < 4; ++q) EXPECT_GT(boundary_near_corner[q], 0) << "quadrant " << q;
}

// The lattice of a grain scene, from the solid interface (Solid.hpp), is
// the grains' rule point for point: checked against every
// lattice point, every grain and every periodic image, by brute force. A
// point within a grain's radius (and 1e-9 dx) is solid; deeper than the
// shell, 3h, below any surface it is buried; otherwise it belongs to the
// grain whose surface is nearest (the first listed on a tie) and carries its
// offset from that image of the centre (to rounding: the image is taken
// another way) and its radius. Grains overlapping each other, across an
// edge and across the corner.
TEST(Grains, LatticeIsTheGrainRuleAtEveryPoint) {
  SceneConfig scene = unit_cell(0.02);
  scene.allow_overlapping_grains = true;
  scene.grains = grains_from_list({0.03, 0.96, 0.15,  0.5, 0.5, 0.2,  0.66, 0.5, 0.12,  0.98, 0.3, 0.1}, 2);
  const double dx = scene.particle_spacing, shell = 3 * dx, on_surface = 1e-9 * dx;
  const auto seeds = fill_lattice<2>(scene);
  size_t next = 0;
  for (int j = 0; j < 50; ++j)
    for (int i = 0; i < 50; ++i) {
      const double x[2] = {(i + 0.5) * dx, (j + 0.5) * dx};
      bool buried = false;
      int owner = -1;
      double depth = 0, offset[2] = {0, 0};
      for (int g = 0; g < static_cast<int>(scene.grains.size()); ++g)
        for (int sx = -1; sx <= 1; ++sx)
          for (int sy = -1; sy <= 1; ++sy) {
            const auto& grain = scene.grains[g];
            const double r[2] = {x[0] - (grain.centre[0] + sx), x[1] - (grain.centre[1] + sy)};
            const double dist = std::sqrt(r[0] * r[0] + r[1] * r[1]);
            if (dist > grain.radius + on_surface) continue;
            const double below = grain.radius - dist;
            if (below > shell + on_surface) buried = true;
            else if (owner < 0 || below < depth) owner = g, depth = below, offset[0] = r[0], offset[1] = r[1];
          }
      if (buried) continue;  // no particle here
      ASSERT_LT(next, seeds.size());
      const auto& s = seeds[next++];
      ASSERT_EQ(s.x[0], x[0]);
      ASSERT_EQ(s.x[1], x[1]);
      if (owner < 0) {
        EXPECT_EQ(s.kind, kFluid) << x[0] << ", " << x[1];
        continue;
      }
      EXPECT_EQ(s.kind, kGrainBoundary) << x[0] << ", " << x[1];
      EXPECT_NEAR(s.wall_vector[0], offset[0], 1e-14) << x[0] << ", " << x[1];
      EXPECT_NEAR(s.wall_vector[1], offset[1], 1e-14) << x[0] << ", " << x[1];
      EXPECT_EQ(s.wall_scalar, scene.grains[owner].radius) << x[0] << ", " << x[1];
    }
  EXPECT_EQ(next, seeds.size());
}

// The map lists, for every point, each grain containing it (periodic images
// included); checked against a scan of all grains on a fine grid of points.
TEST(Grains, MapFindsEveryGrainContainingAPoint) {
  auto scene = unit_cell();
  scene.grains = grains_from_list({0.05, 0.95, 0.2,   // across the corner
                                   0.5, 0.5, 0.15,    // inside
                                   0.98, 0.4, 0.1},   // across the x boundary
                                  2);
  const auto map = make_grain_map<2, Kokkos::HostSpace>(scene, 0.07);
  int inside_points = 0;
  for (int a = 0; a < 200; ++a)
    for (int b = 0; b < 200; ++b) {
      const double x[2] = {(a + 0.3) / 200.0 + (a % 3 == 0 ? 1.0 : 0.0), (b + 0.6) / 200.0 - (b % 5 == 0 ? 1.0 : 0.0)};
      std::vector<int> listed;
      map.for_each_grain_near(x, [&](int g) { listed.push_back(g); });
      for (int g = 0; g < 3; ++g) {
        const auto r = periodic_difference({x[0], x[1], 0}, scene.grains[g].centre, scene);
        if (std::hypot(r[0], r[1]) >= scene.grains[g].radius) continue;
        ++inside_points;
        EXPECT_NE(std::find(listed.begin(), listed.end(), g), listed.end()) << "grain " << g << " at " << x[0] << ", " << x[1];
      }
    }
  EXPECT_GT(inside_points, 5000);
}

// A fluid particle inside a grain goes back to the surface along the normal
// and keeps only its tangential and outward velocity; one outside is untouched.
TEST(Grains, PenetratingFluidIsPutBackOnTheSurface) {
  auto scene = unit_cell();
  scene.grains = grains_from_list({0.0, 0.0, 0.3}, 2);  // a quarter in each corner of the cell
  const auto map = make_solid_map<2, Kokkos::HostSpace>(scene, 0.1);
  Particles<2, Kokkos::HostSpace> P;
  P.reserve(3);
  P.owned = 3;
  const double points[3][2] = {{0.99, 0.29}, {0.2, 0.2}, {0.5, 0.5}};  // inside (image), inside, outside
  for (int i = 0; i < 3; ++i) {
    P.kind(i) = kFluid;
    P.x(i, 0) = points[i][0], P.x(i, 1) = points[i][1];
    P.v(i, 0) = -1.0, P.v(i, 1) = -2.0;
  }
  const auto found = fluid_in_grains(Kokkos::DefaultHostExecutionSpace(), P, map, true, 1e-9);
  EXPECT_EQ(found.particles, 2);
  EXPECT_NEAR(found.max_depth, 0.3 - std::hypot(0.2, 0.2), 1e-14);
  for (int i = 0; i < 2; ++i) {
    const double rx = P.x(i, 0) - (i == 0 ? 1.0 : 0.0), ry = P.x(i, 1);
    EXPECT_NEAR(std::hypot(rx, ry), 0.3 + 1e-9, 1e-14);
    const double n[2] = {rx / 0.3, ry / 0.3};
    EXPECT_NEAR(P.v(i, 0) * n[0] + P.v(i, 1) * n[1], 0.0, 1e-12);  // inward part removed
    EXPECT_NEAR(-P.v(i, 0) * n[1] + P.v(i, 1) * n[0], -(-1.0 * n[1]) + (-2.0) * n[0], 1e-12);  // tangential kept
  }
  EXPECT_EQ(P.x(2, 0), 0.5);
  EXPECT_EQ(P.v(2, 1), -2.0);
  EXPECT_EQ(fluid_in_grains(Kokkos::DefaultHostExecutionSpace(), P, map, false, 0.0).particles, 0);
}

// A channel's walls are solid too: a fluid particle carried past y = 0 or
// y = L_y goes back to the wall and keeps only its velocity along it; one in
// the channel is untouched, however close to a wall.
TEST(Grains, FluidPastAChannelWallIsPutBackOnTheWall) {
  auto scene = unit_cell();
  scene.cell_size = {1.0, 0.5, 0};
  scene.periodic = {1, 0, 0};
  scene.walls = WallType::Channel;
  const auto map = make_solid_map<2, Kokkos::HostSpace>(scene, 0.1);
  ASSERT_FALSE(map.empty());
  Particles<2, Kokkos::HostSpace> P;
  P.reserve(3);
  P.owned = 3;
  const double points[3][2] = {{0.3, 0.503}, {0.7, -0.002}, {0.5, 0.4999}};  // above, below, in the channel
  for (int i = 0; i < 3; ++i) {
    P.kind(i) = kFluid;
    P.x(i, 0) = points[i][0], P.x(i, 1) = points[i][1];
    P.v(i, 0) = 0.25, P.v(i, 1) = i == 1 ? -2.0 : 2.0;  // each moving into its wall
  }
  const auto found = fluid_in_grains(Kokkos::DefaultHostExecutionSpace(), P, map, true, 1e-9);
  EXPECT_EQ(found.particles, 2);
  EXPECT_NEAR(found.max_depth, 0.003, 1e-15);
  EXPECT_NEAR(P.x(0, 1), 0.5 - 1e-9, 1e-15);
  EXPECT_NEAR(P.x(1, 1), 1e-9, 1e-15);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(P.x(i, 0), points[i][0]);
    EXPECT_EQ(P.v(i, 0), 0.25);  // along the wall: kept
    EXPECT_EQ(P.v(i, 1), 0.0);   // into it: removed
  }
  EXPECT_EQ(P.x(2, 1), 0.4999);
  EXPECT_EQ(P.v(2, 1), 2.0);
  EXPECT_EQ(fluid_in_grains(Kokkos::DefaultHostExecutionSpace(), P, map, false, 0.0).particles, 0);
}

// Throats: refused below one spacing, a warning below three, silent above;
// closed (touching) throats and throats with a grain's own image count too.
TEST(Grains, ThroatCheckRefusesAndWarnsExactlyWhenItShould) {
  auto scene = unit_cell(0.01);  // dx = 0.01
  auto two_grains = [&](double gap) {
    return grains_from_list({0.3, 0.5, 0.1, 0.5 + gap, 0.5, 0.1}, 2);  // gap between surfaces
  };
  const auto refused = error_of([&] { check_throats(two_grains(0.0099), scene); });
  EXPECT_NE(refused.find("Grains/Inline #1 and grain Grains/Inline #2"), std::string::npos) << refused;
  EXPECT_NE(refused.find("narrower than one spacing"), std::string::npos) << refused;
  EXPECT_EQ(error_of([&] { check_throats(two_grains(0.0101), scene); }), "");
  const auto warned = check_throats(two_grains(0.0101), scene);
  ASSERT_EQ(warned.size(), 1u);
  EXPECT_NE(warned[0].find("1.01 particle spacings"), std::string::npos) << warned[0];
  EXPECT_EQ(check_throats(two_grains(0.0299), scene).size(), 1u);
  EXPECT_TRUE(check_throats(two_grains(0.0301), scene).empty());
  EXPECT_TRUE(check_throats(two_grains(0.0), scene).empty());  // touching: no throat at all
  // A grain and its own periodic image: gap 1 - 2 r.
  const auto big = grains_from_list({0.5, 0.5, 0.486}, 2);
  const auto image = check_throats(big, scene);  // gap 0.028: 2.8 spacings
  ASSERT_EQ(image.size(), 1u);
  EXPECT_NE(image[0].find("and its periodic image"), std::string::npos) << image[0];
  scene.particle_spacing = 0.05;
  EXPECT_NE(error_of([&] { check_throats(big, scene); }).find("its periodic image"), std::string::npos);
  // Across the periodic boundary, to the nearest image of the other grain.
  scene.particle_spacing = 0.01;
  const auto across = grains_from_list({0.05, 0.5, 0.1, 0.85 - 0.005, 0.5, 0.1}, 2);  // gap 0.005 through x = 0
  EXPECT_NE(error_of([&] { check_throats(across, scene); }).find("0.005 wide"), std::string::npos);
}

// The checks look at neighbouring bins only (issue 18: 40,000 grains took
// 86 s pairwise). They must find what a scan of all pairs finds: every
// throat, with the same gap, and the same first overlap, also across the
// periodic boundary, along a wall, and with radii of different sizes.
TEST(Grains, BinnedChecksAgreeWithAllPairs) {
  for (const bool periodic_y : {true, false}) {
    SceneConfig scene = unit_cell(0.004);
    scene.cell_size = {1.0, 0.7, 0};
    scene.periodic = {true, periodic_y, true};
    std::mt19937 random(7);
    std::uniform_real_distribution<double> x(0, 1.0), y(0, 0.7), r(0.005, 0.05);
    std::vector<double> values;
    for (int g = 0; g < 400; ++g) values.insert(values.end(), {x(random), y(random), r(random)});
    const auto grains = grains_from_list(values, 2);
    const double max_gap = 0.03;
    // All pairs, every image within one cell, as before the bins.
    struct Found {
      size_t i, j;
      double gap;
    };
    std::vector<Found> reference;
    size_t first_i = grains.size(), first_j = 0;
    for (size_t i = 0; i < grains.size(); ++i)
      for (size_t j = i; j < grains.size(); ++j) {
        double narrowest = INFINITY;
        for (int sx = -1; sx <= 1; ++sx)
          for (int sy = -1; sy <= 1; ++sy) {
            if ((i == j && sx == 0 && sy == 0) || (sy != 0 && !periodic_y)) continue;
            const double dx = grains[j].centre[0] + sx * 1.0 - grains[i].centre[0];
            const double dy = grains[j].centre[1] + sy * 0.7 - grains[i].centre[1];
            narrowest = std::min(narrowest, std::sqrt(dx * dx + dy * dy) - grains[i].radius - grains[j].radius);
          }
        if (narrowest > 1e-12 && narrowest < max_gap) reference.push_back({i, j, narrowest});
        if (i != j && narrowest < 0 && first_i == grains.size()) first_i = i, first_j = j;
      }
    ASSERT_GT(reference.size(), 50u);
    ASSERT_LT(first_i, grains.size()) << "the random packing should overlap somewhere";
    std::sort(reference.begin(), reference.end(), [](const Found& a, const Found& b) {
      return std::tie(a.gap, a.i, a.j) < std::tie(b.gap, b.i, b.j);
    });
    const auto survey = narrow_throats(grains, scene, max_gap, 1000000);
    ASSERT_EQ(survey.count, static_cast<long long>(reference.size()));
    ASSERT_EQ(survey.narrowest.size(), reference.size());
    for (size_t k = 0; k < reference.size(); ++k) {
      EXPECT_EQ(survey.narrowest[k].first, &grains[reference[k].i]) << k;
      EXPECT_EQ(survey.narrowest[k].second, &grains[reference[k].j]) << k;
      EXPECT_NEAR(survey.narrowest[k].gap, reference[k].gap, 1e-15) << k;  // to rounding: the formula is the same
    }
    const auto few = narrow_throats(grains, scene, max_gap, 10);
    EXPECT_EQ(few.count, survey.count);
    ASSERT_EQ(few.narrowest.size(), 10u);
    EXPECT_NEAR(few.narrowest.back().gap, reference[9].gap, 1e-15);
    const auto message = error_of([&] { check_grains(grains, scene); });
    EXPECT_NE(message.find("grains Grains/Inline #" + std::to_string(first_i + 1) + " and Grains/Inline #" +
                           std::to_string(first_j + 1) + " overlap"),
              std::string::npos)
        << message;
  }
}

// 40,000 grains on a jittered square lattice: the checks, the throats and the
// porosity take a fraction of a second with bins (86 s pairwise before).
TEST(Grains, FortyThousandGrainsAreCheckedInLinearTime) {
  SceneConfig scene = unit_cell(0.0002);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> jitter(-0.0005, 0.0005);
  std::vector<double> values;
  for (int a = 0; a < 200; ++a)
    for (int b = 0; b < 200; ++b)
      values.insert(values.end(), {(a + 0.5) * 0.005 + jitter(random), (b + 0.5) * 0.005 + jitter(random), 0.0015});
  const auto grains = grains_from_list(values, 2);
  const auto start = std::chrono::steady_clock::now();
  check_grains(grains, scene);
  const auto warnings = check_throats(grains, scene);
  const double phi = porosity(grains, scene);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(warnings.empty());  // every gap is at least 0.001 = 5 spacings
  EXPECT_NEAR(phi, 1 - 40000 * M_PI * 0.0015 * 0.0015, 1e-12);
  EXPECT_LT(seconds, 10.0) << "the grain checks are quadratic again?";
  // A spacing coarser than the gaps: a throat at every grain. Refused naming
  // the narrowest, and the warnings of a scene with thousands are bounded.
  scene.particle_spacing = 0.0008;  // 3 spacings: 0.0024, wider than most gaps
  const auto many = check_throats(grains, scene);
  ASSERT_EQ(many.size(), kThroatWarnings + 1);
  EXPECT_NE(many.back().find("more throats narrower than 3 particle spacings"), std::string::npos) << many.back();
  scene.particle_spacing = 0.005;
  EXPECT_NE(error_of([&] { check_throats(grains, scene); }).find("narrower than one spacing"), std::string::npos);
}

SceneConfig unit_cube(double dx = 0.02) {
  SceneConfig s = unit_cell(dx);
  s.dimension = 3;
  s.cell_size = {1.0, 1.0, 1.0};
  return s;
}

// Sphere lists as DEM and packing tools write them: columns separated by
// blanks, commas or semicolons, a first line naming the columns.
TEST(Grains3D, FileReadsColumnsCommasAndAHeader) {
  const auto csv = write_file("spheres.csv", "x,y,z,r\n0.5,0.5,0.5,0.1\n0.1, 0.2, 0.3, 0.05 # a comment\n");
  const auto grains = read_grain_file(csv, 3);
  ASSERT_EQ(grains.size(), 2u);
  EXPECT_EQ(grains[1].centre[2], 0.3);
  EXPECT_EQ(grains[1].radius, 0.05);
  EXPECT_NE(grains[0].origin.find(":2"), std::string::npos);  // lines are counted with the header
  const auto semicolons = write_file("spheres-semicolons.txt", "# cx;cy;cz;r\ncx;cy;cz;r\n0.5;0.5;0.5;0.1\n");
  EXPECT_EQ(read_grain_file(semicolons, 3).size(), 1u);
  // A header that does not name four columns, a second header, and nan are refused, naming the line.
  const auto wrong_header = write_file("spheres-wrong-header.txt", "id x y z r\n1 0.5 0.5 0.5 0.1\n");
  EXPECT_NE(error_of([&] { read_grain_file(wrong_header, 3); }).find(":1: the header names 5 columns"),
            std::string::npos);
  const auto late_header = write_file("spheres-late-header.txt", "0.5 0.5 0.5 0.1\nx y z r\n");
  EXPECT_NE(error_of([&] { read_grain_file(late_header, 3); }).find(":2: 'x'"), std::string::npos);
  const auto nan = write_file("spheres-nan.txt", "nan nan nan nan\n");
  EXPECT_NE(error_of([&] { read_grain_file(nan, 3); }).find(":1: 'nan'"), std::string::npos);
  // grains_used.txt reads back to the same bits.
  SceneConfig scene = unit_cube();
  scene.grains = grains;
  const auto again = read_grain_file(write_file("spheres-again.txt", grains_used_text(scene)), 3);
  ASSERT_EQ(again.size(), grains.size());
  for (size_t g = 0; g < grains.size(); ++g) {
    EXPECT_EQ(again[g].radius, grains[g].radius);
    for (int d = 0; d < 3; ++d) EXPECT_EQ(again[g].centre[d], grains[g].centre[d]);
  }
}

// Two spheres in contact: the porosity subtracts their lens exactly (the
// volume of two caps, checked by its own closed form here); three spheres
// sharing a region fall back to sampling, which must agree with the exact
// sum of pairwise lenses minus the triple region, within the sampling error.
TEST(Grains3D, PorosityOfSpheresInContactIsExact) {
  SceneConfig scene = unit_cube();
  scene.allow_overlapping_grains = true;
  const double r1 = 0.2, r2 = 0.15, d = 0.33;
  // Cap heights of the lens, from the plane where the surfaces meet.
  const double x1 = (d * d + r1 * r1 - r2 * r2) / (2 * d);
  const double h1 = r1 - x1, h2 = r2 - (d - x1);
  const double caps = M_PI * h1 * h1 * (3 * r1 - h1) / 3 + M_PI * h2 * h2 * (3 * r2 - h2) / 3;
  EXPECT_NEAR(overlap_volume(r1, r2, d, 3), caps, 1e-15);
  const double spheres = 4.0 / 3.0 * M_PI * (r1 * r1 * r1 + r2 * r2 * r2);
  const auto pair = grains_from_list({0.05, 0.05, 0.05, r1, 0.05 + d, 0.05, 0.05, r2}, 3);
  EXPECT_NEAR(porosity(pair, scene), 1 - (spheres - caps), 1e-14);
  // Across the corner of the cell: the pair meets through the periodic images.
  const auto across = grains_from_list({0.9, 0.95, 0.97, r1, 0.9 + d - 1.0, 0.95, 0.97, r2}, 3);
  EXPECT_NEAR(porosity(across, scene), 1 - (spheres - caps), 1e-14);
  // Three spheres sharing a region (4.8e-4 of the cell, by Monte Carlo
  // with 4e7 points: porosity 0.90859 +- 5e-5): sampled on 160^3 points,
  // not the pairwise sum, which would subtract that region twice too often.
  const auto three = grains_from_list({0.5, 0.5, 0.5, 0.2, 0.8, 0.5, 0.5, 0.2, 0.65, 0.75, 0.5, 0.2}, 3);
  const double side = std::hypot(0.15, 0.25);
  const double pairwise = 3 * 4.0 / 3.0 * M_PI * 0.008 - overlap_volume(0.2, 0.2, 0.3, 3) -
                          2 * overlap_volume(0.2, 0.2, side, 3);
  const double sampled = porosity(three, scene);
  EXPECT_NEAR(sampled, 0.90859, 2e-4);
  EXPECT_LT(sampled, 1 - pairwise - 3e-4);
}

// A sphere across the corner of the cube (its eighths in the eight
// corners) gives the lattice the same particles as the same sphere inside,
// moved by whole spacings: the periodic wrap of the filling in 3D.
TEST(Grains3D, SphereAcrossEdgesAndCornersFillsLikeOneInside) {
  SceneConfig scene = unit_cube(0.05);
  auto count = [&](double cx, double cy, double cz) {
    scene.grains = grains_from_list({cx, cy, cz, 0.3}, 3);
    int fluid = 0, boundary = 0, octants[8] = {};
    for (const auto& s : fill_lattice<3>(scene)) {
      if (s.kind == kFluid) {
        ++fluid;
        continue;
      }
      ++boundary;
      const double depth = scene.grains[0].radius -
                           std::sqrt(s.wall_vector[0] * s.wall_vector[0] + s.wall_vector[1] * s.wall_vector[1] +
                                     s.wall_vector[2] * s.wall_vector[2]);
      EXPECT_GE(depth, -1e-12);
      EXPECT_LE(depth, 3 * scene.particle_spacing + 1e-12);
      ++octants[(s.x[0] > 0.5) + 2 * (s.x[1] > 0.5) + 4 * (s.x[2] > 0.5)];
    }
    return std::make_tuple(fluid, boundary, std::vector<int>(octants, octants + 8));
  };
  const auto [fluid_in, boundary_in, octants_in] = count(0.5, 0.5, 0.5);
  const auto [fluid_corner, boundary_corner, octants_corner] = count(0.0, 0.0, 0.0);
  const auto [fluid_edge, boundary_edge, octants_edge] = count(0.0, 0.5, 1.0);
  EXPECT_EQ(fluid_corner, fluid_in);
  EXPECT_EQ(boundary_corner, boundary_in);
  EXPECT_EQ(fluid_edge, fluid_in);
  EXPECT_EQ(boundary_edge, boundary_in);
  for (int o = 0; o < 8; ++o) EXPECT_EQ(octants_corner[o], boundary_in / 8) << "octant " << o;
  EXPECT_GT(boundary_in, 0);
}

// Throats between spheres in 3D: refused below a spacing, warned below
// three, between a sphere and its own images across an edge and a corner
// of the cell too; the binned survey finds every throat a scan of all pairs
// and all 27 images finds, with the same gap.
TEST(Grains3D, ThroatsAreCheckedAsInTwoDimensions) {
  SceneConfig scene = unit_cube(0.01);
  auto two = [&](double gap) { return grains_from_list({0.3, 0.5, 0.5, 0.1, 0.5 + gap, 0.5, 0.5, 0.1}, 3); };
  EXPECT_NE(error_of([&] { check_throats(two(0.0099), scene); }).find("narrower than one spacing"), std::string::npos);
  EXPECT_EQ(check_throats(two(0.0101), scene).size(), 1u);
  EXPECT_TRUE(check_throats(two(0.0301), scene).empty());
  // The diagonal of the cube: a sphere at the corner and one at the centre, gap 0.005 along (1,1,1).
  const double half_diagonal = std::sqrt(3.0) / 2;
  const auto diagonal = grains_from_list({0.0, 0.0, 0.0, 0.3, 0.5, 0.5, 0.5, half_diagonal - 0.3 - 0.005}, 3);
  const auto refused = error_of([&] { check_throats(diagonal, scene); });
  EXPECT_NE(refused.find("0.005 wide"), std::string::npos) << refused;

  std::mt19937 random(5);
  std::uniform_real_distribution<double> x(0, 1.0), r(0.02, 0.08);
  std::vector<double> values;
  for (int g = 0; g < 300; ++g) values.insert(values.end(), {x(random), x(random), x(random), r(random)});
  const auto grains = grains_from_list(values, 3);
  const double max_gap = 0.04;
  std::vector<std::tuple<double, size_t, size_t>> reference;
  for (size_t i = 0; i < grains.size(); ++i)
    for (size_t j = i; j < grains.size(); ++j) {
      double narrowest = INFINITY;
      for (int image = 0; image < 27; ++image) {
        const int s[3] = {image % 3 - 1, image / 3 % 3 - 1, image / 9 - 1};
        if (i == j && s[0] == 0 && s[1] == 0 && s[2] == 0) continue;
        double d_sq = 0;
        for (int k = 0; k < 3; ++k) {
          const double dk = grains[j].centre[k] + s[k] - grains[i].centre[k];
          d_sq += dk * dk;
        }
        narrowest = std::min(narrowest, std::sqrt(d_sq) - grains[i].radius - grains[j].radius);
      }
      if (narrowest > 1e-12 && narrowest < max_gap) reference.emplace_back(narrowest, i, j);
    }
  std::sort(reference.begin(), reference.end());
  ASSERT_GT(reference.size(), 30u);
  const auto survey = narrow_throats(grains, scene, max_gap, 1000000);
  ASSERT_EQ(survey.count, static_cast<long long>(reference.size()));
  for (size_t k = 0; k < reference.size(); ++k) {
    EXPECT_EQ(survey.narrowest[k].first, &grains[std::get<1>(reference[k])]) << k;
    EXPECT_EQ(survey.narrowest[k].second, &grains[std::get<2>(reference[k])]) << k;
    EXPECT_NEAR(survey.narrowest[k].gap, std::get<0>(reference[k]), 1e-15) << k;
  }
}

}  // namespace
}  // namespace poresph
