// Grains/Random Pack: the porosity asked for, every pair either in contact
// or at least the gap apart, the same pack for the same seed, refusals that
// say why, and the grain checks of a pack of 10^4 spheres in linear time.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "geometry/Grains.hpp"
#include "geometry/RandomPack.hpp"
#include "io/Parameters.hpp"
#include "scene/SceneBuilder.hpp"
#include "ErrorOf.hpp"

namespace poresph {
namespace {

using testing::error_of;

SceneConfig cube(double side, double dx, int dim = 3) {
  SceneConfig s;
  s.dimension = dim;
  s.cell_size = {side, side, dim == 3 ? side : 0.0};
  s.particle_spacing = dx;
  s.kinematic_viscosity = 1e-6;
  s.end_time = 1;
  return s;
}

// Every pair of grains, at every periodic image: the narrowest open gap,
// and the deepest overlap relative to the contact bound.
void expect_rule_holds(const RandomPack& pack, const SceneConfig& scene, double gap) {
  const int dim = scene.dimension;
  long long contacts = 0;
  for (size_t i = 0; i < pack.grains.size(); ++i)
    for (size_t j = i + 1; j < pack.grains.size(); ++j) {
      const auto& a = pack.grains[i];
      const auto& b = pack.grains[j];
      const int images = dim == 3 ? 27 : 9;
      for (int image = 0; image < images; ++image) {
        double d_sq = 0;
        for (int k = 0, rest = image; k < dim; ++k, rest /= 3) {
          const double dk = b.centre[k] + (rest % 3 - 1) * scene.cell_size[k] - a.centre[k];
          d_sq += dk * dk;
        }
        const double s = std::sqrt(d_sq) - a.radius - b.radius;
        if (s >= gap * (1 - 1e-9)) continue;
        ++contacts;
        EXPECT_LE(s, 1e-9 * gap) << "grains " << i << " and " << j << ": a throat of " << s / gap << " gaps";
        EXPECT_GE(s, -std::min(gap, 0.1 * std::min(a.radius, b.radius)) * (1 + 1e-9)) << i << ", " << j;
      }
    }
  EXPECT_EQ(contacts, pack.contacts);
}

// The pack: porosity 0.40, at least 20 spheres, at least 12
// particles per diameter, a gap of one spacing.
TEST(RandomPack, PorosityPointFourWithTwelveSpacingsPerDiameter) {
  const SceneConfig scene = cube(0.09, 0.0025);
  RandomPackSpec spec;
  spec.porosity = 0.40;
  spec.min_radius = 0.015, spec.max_radius = 0.018;
  spec.seed = 1;
  const auto pack = make_random_pack(spec, scene);
  EXPECT_GE(pack.grains.size(), 20u);
  double smallest = INFINITY;
  for (const auto& g : pack.grains) smallest = std::min(smallest, g.radius);
  EXPECT_GE(2 * smallest / scene.particle_spacing, 12.0);
  SceneConfig overlapping = scene;
  overlapping.allow_overlapping_grains = true;
  EXPECT_NEAR(porosity(pack.grains, overlapping), 0.40, 1e-6);
  EXPECT_NEAR(pack.porosity, 0.40, 1e-6);
  EXPECT_GT(pack.contacts, 0);
  expect_rule_holds(pack, scene, scene.particle_spacing);
  // The scene checks accept it: no throat under one spacing, no overlap beyond what contacts allow.
  EXPECT_NO_THROW(check_grains(pack.grains, overlapping));
  EXPECT_NO_THROW(check_throats(pack.grains, overlapping));
  for (const auto& g : pack.grains)
    for (int d = 0; d < 3; ++d) EXPECT_TRUE(g.centre[d] >= 0 && g.centre[d] < scene.cell_size[d]);
}

TEST(RandomPack, TheSameSeedGivesTheSamePack) {
  const SceneConfig scene = cube(0.09, 0.0025);
  RandomPackSpec spec;
  spec.porosity = 0.45;
  spec.distribution = RandomPackSpec::Distribution::Lognormal;
  spec.min_radius = 0.012, spec.max_radius = 0.02, spec.median_radius = 0.015, spec.log_deviation = 0.15;
  spec.seed = 42;
  const auto first = make_random_pack(spec, scene), second = make_random_pack(spec, scene);
  ASSERT_EQ(first.grains.size(), second.grains.size());
  for (size_t g = 0; g < first.grains.size(); ++g) {
    EXPECT_EQ(first.grains[g].radius, second.grains[g].radius);
    for (int d = 0; d < 3; ++d) EXPECT_EQ(first.grains[g].centre[d], second.grains[g].centre[d]);
  }
  spec.seed = 43;
  const auto other = make_random_pack(spec, scene);
  EXPECT_NE(other.grains[0].centre[0], first.grains[0].centre[0]);
  EXPECT_NEAR(other.porosity, 0.45, 1e-6);
  expect_rule_holds(first, scene, scene.particle_spacing);
}

// Without contacts every pair keeps the gap: possible at porosity 0.6, and
// refused at 0.4 (spheres plus half the gap would fill 0.76 of the cell).
TEST(RandomPack, WithoutContactsEveryThroatStaysOpen) {
  const SceneConfig scene = cube(0.09, 0.0025);
  RandomPackSpec spec;
  spec.porosity = 0.6;
  spec.min_radius = 0.012, spec.max_radius = 0.016;
  spec.contacts = false;
  const auto pack = make_random_pack(spec, scene);
  EXPECT_EQ(pack.contacts, 0);
  EXPECT_GE(pack.narrowest_gap, scene.particle_spacing * (1 - 1e-9));
  expect_rule_holds(pack, scene, scene.particle_spacing);
  EXPECT_NO_THROW(check_grains(pack.grains, scene));  // no overlap at all
  spec.porosity = 0.4;
  spec.min_radius = 0.015, spec.max_radius = 0.018;
  EXPECT_NE(error_of([&] { make_random_pack(spec, scene); }).find("jammed at porosity"), std::string::npos);
}

TEST(RandomPack, CirclesInTwoDimensions) {
  const SceneConfig scene = cube(0.1, 0.001, 2);
  RandomPackSpec spec;
  spec.porosity = 0.3;
  spec.min_radius = 0.006, spec.max_radius = 0.01;
  const auto pack = make_random_pack(spec, scene);
  EXPECT_NEAR(pack.porosity, 0.3, 1e-6);
  expect_rule_holds(pack, scene, scene.particle_spacing);
}

TEST(RandomPack, RefusalsSayWhy) {
  RandomPackSpec spec;
  spec.porosity = 0.4;
  spec.min_radius = 0.03, spec.max_radius = 0.03;
  EXPECT_NE(error_of([&] { make_random_pack(spec, cube(0.09, 0.0025)); }).find("twice the largest diameter"),
            std::string::npos);
  spec.min_radius = 0.00001, spec.max_radius = 0.00001;
  EXPECT_NE(error_of([&] { make_random_pack(spec, cube(0.09, 0.0025)); }).find("more than 1000000 grains"),
            std::string::npos);
  SceneConfig channel = cube(0.09, 0.0025);
  channel.periodic[1] = false;
  spec.min_radius = 0.015, spec.max_radius = 0.018;
  EXPECT_NE(error_of([&] { make_random_pack(spec, channel); }).find("periodic in every direction"), std::string::npos);
}

// The scene's parameters make the pack, and it replaces neither a grain
// file nor inline grains.
TEST(RandomPack, FromTheSceneParameters) {
  auto list = Teuchos::rcp(new Teuchos::ParameterList("PoreSPH"));
  for (const auto& set :
       {"Domain/Cell Size={0.09, 0.09, 0.09}", "Fluid/Kinematic Viscosity=1e-6", "Discretization/Particle Spacing=0.0025",
        "Run/End Time=1", "Grains/Random Pack/Porosity=0.42", "Grains/Random Pack/Min Radius=0.015",
        "Grains/Random Pack/Max Radius=0.018", "Grains/Random Pack/Seed=3"})
    apply_override(*list, set);
  validate_parameters(*list);
  const SceneConfig scene = scene_from_parameters(*list);
  EXPECT_NEAR(porosity(scene.grains, scene), 0.42, 1e-6);
  EXPECT_TRUE(scene.allow_overlapping_grains);
  EXPECT_NE(scene.grains_note.find("porosity 0.42"), std::string::npos) << scene.grains_note;
  EXPECT_NE(grains_used_text(scene).find(scene.grains_note), std::string::npos);
  apply_override(*list, "Grains/Inline={0.01, 0.01, 0.01, 0.005}");
  validate_parameters(*list);
  try {
    scene_from_parameters(*list);
    FAIL() << "a pack with inline grains was accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("leave Grains/File and Grains/Inline empty"), std::string::npos);
  }
}

// 10^4 spheres: the pack, the checks, the throats and the porosity in
// seconds (issue 15: the checks took 8 s for 10^4 grains when quadratic).
TEST(RandomPack, TenThousandSpheresArePackedAndCheckedInLinearTime) {
  const SceneConfig scene = cube(0.22, 0.0005);  // about 11,000 spheres
  RandomPackSpec spec;
  spec.porosity = 0.45;
  spec.min_radius = 0.0045, spec.max_radius = 0.0055;  // 20 spacings across
  auto start = std::chrono::steady_clock::now();
  const auto pack = make_random_pack(spec, scene);
  const double pack_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_GT(pack.grains.size(), 9000u);
  start = std::chrono::steady_clock::now();
  SceneConfig overlapping = scene;
  overlapping.allow_overlapping_grains = true;
  check_grains(pack.grains, overlapping);
  const auto warnings = check_throats(pack.grains, overlapping);
  const double phi = porosity(pack.grains, overlapping);
  const double check_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NEAR(phi, 0.45, 1e-6);
  EXPECT_FALSE(warnings.empty());  // throats of one spacing: warned, not refused
  std::printf("%zu spheres: packed in %.2f s (%d stages, %lld sweeps), checked in %.2f s\n", pack.grains.size(),
              pack_seconds, pack.stages, pack.sweeps, check_seconds);
  EXPECT_LT(check_seconds, 10.0) << "the grain checks are quadratic again?";
  EXPECT_LT(pack_seconds, 120.0);
}

}  // namespace
}  // namespace poresph
