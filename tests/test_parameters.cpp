// Scene parameters: validation errors name the parameter; --set overrides.
#include <gtest/gtest.h>

#include <Teuchos_Array.hpp>

#include "app/Simulation.hpp"
#include "geometry/Lattice.hpp"
#include "io/Parameters.hpp"
#include "scene/SceneBuilder.hpp"
#include "io/TextValues.hpp"
#include "ErrorOf.hpp"
#include "MinimalScene.hpp"

namespace poresph {
namespace {

using Teuchos::Array;
using Teuchos::ParameterList;

using testing::array;
using testing::minimal_scene;

// The message of the ParameterError that `f` raises ("" if none).
template <class F>
std::string error_of(F&& f) {
  return testing::error_of<ParameterError>(std::forward<F>(f));
}

TEST(Parameters, MinimalSceneValidatesAndGetsDefaults) {
  auto list = minimal_scene();
  validate_parameters(list);
  const SceneConfig scene = scene_from_parameters(list);
  EXPECT_EQ(scene.dimension, 2);
  EXPECT_EQ(scene.density, 1000.0);
  EXPECT_TRUE(scene.periodic[0] && scene.periodic[1]);
  EXPECT_EQ(scene.walls, WallType::None);
  EXPECT_EQ(list.sublist("Discretization").get<double>("Smoothing Length Ratio"), 1.0);
}

// Fluid/Raise Sound Speed: where the viscous limit sets dt, c rises until the
// acoustic limit meets it (same dt, stiffer fluid); where the acoustic limit
// sets dt already, nothing changes; a given Sound Speed excludes it.
TEST(Parameters, RaisedSoundSpeedKeepsTheTimeStep) {
  auto derived_with = [](double nu, bool raise) {
    auto list = minimal_scene();
    list.sublist("Fluid").set("Kinematic Viscosity", nu);
    list.sublist("Fluid").set("Raise Sound Speed", raise);
    list.sublist("Discretization").set("Particle Motion", std::string("lagrangian"));  // fixed ones always raise
    validate_parameters(list);
    return derive_parameters(scene_from_parameters(list));
  };
  const auto plain = derived_with(1e-2, false), raised = derived_with(1e-2, true);
  ASSERT_LT(plain.limits.viscous, plain.limits.acoustic);  // the case the option is for
  EXPECT_GT(raised.sound_speed, 1.2 * plain.sound_speed);
  EXPECT_NEAR(raised.time_step, plain.time_step, 1e-12 * plain.time_step);
  EXPECT_NEAR(raised.limits.acoustic, raised.limits.viscous, 1e-12 * raised.limits.viscous);

  const auto acoustic_plain = derived_with(1e-6, false), acoustic_raised = derived_with(1e-6, true);
  ASSERT_LT(acoustic_plain.limits.acoustic, acoustic_plain.limits.smallest() * (1 + 1e-12));
  EXPECT_EQ(acoustic_raised.sound_speed, acoustic_plain.sound_speed);
  EXPECT_EQ(acoustic_raised.time_step, acoustic_plain.time_step);

  auto list = minimal_scene();
  list.sublist("Fluid").set("Raise Sound Speed", true);
  list.sublist("Fluid").set("Sound Speed", 1.0);
  const auto message = error_of([&] {
    validate_parameters(list);
    scene_from_parameters(list);
  });
  EXPECT_NE(message.find("Raise Sound Speed"), std::string::npos) << message;
}

TEST(Parameters, UnknownNameIsNamed) {
  auto list = minimal_scene();
  list.sublist("Fluid").set("Kinematic Viscosty", 1e-6);  // misspelt
  const auto message = error_of([&] { validate_parameters(list); });
  EXPECT_NE(message.find("Kinematic Viscosty"), std::string::npos) << message;
}

TEST(Parameters, UnknownSublistIsNamed) {
  auto list = minimal_scene();
  list.sublist("Fluids").set("Density", 1.0);
  const auto message = error_of([&] { validate_parameters(list); });
  EXPECT_NE(message.find("Fluids"), std::string::npos) << message;
}

TEST(Parameters, WrongTypeIsNamed) {
  auto list = minimal_scene();
  list.sublist("Fluid").set("Density", std::string("water"));
  const auto message = error_of([&] { validate_parameters(list); });
  EXPECT_NE(message.find("Density"), std::string::npos) << message;
}

TEST(Parameters, NegativeViscosityIsOutOfRange) {
  auto list = minimal_scene();
  list.sublist("Fluid").set("Kinematic Viscosity", -1e-6);
  const auto message = error_of([&] { validate_parameters(list); });
  EXPECT_NE(message.find("Kinematic Viscosity"), std::string::npos) << message;
}

TEST(Parameters, OutOfRangeIntegerIsNamed) {
  auto list = minimal_scene();
  list.sublist("Run").set("Max Steps", -5);
  const auto message = error_of([&] { validate_parameters(list); });
  EXPECT_NE(message.find("Max Steps"), std::string::npos) << message;
}

TEST(Parameters, WordOutsideTheChoicesIsNamed) {
  auto list = minimal_scene();
  list.sublist("Walls").set("Type", std::string("channnel"));
  const auto message = error_of([&] { validate_parameters(list); });
  EXPECT_NE(message.find("channnel"), std::string::npos) << message;
}

TEST(Parameters, MissingRequiredValueIsNamed) {
  auto list = minimal_scene();
  list.sublist("Discretization").remove("Particle Spacing");
  const auto message = error_of([&] { validate_parameters(list); });
  EXPECT_NE(message.find("Discretization/Particle Spacing"), std::string::npos) << message;
}

TEST(Parameters, ArrayLengthMustMatchTheDimension) {
  auto list = minimal_scene();
  list.sublist("Fluid").set("Body Force", array<double>({1.0, 0.0, 0.0}));
  validate_parameters(list);
  const auto message = error_of([&] { scene_from_parameters(list); });
  EXPECT_NE(message.find("Fluid/Body Force"), std::string::npos) << message;
}

TEST(Parameters, ChannelNeedsANonPeriodicY) {
  auto list = minimal_scene();
  list.sublist("Walls").set("Type", std::string("channel"));
  validate_parameters(list);
  const auto message = error_of([&] { scene_from_parameters(list); });
  EXPECT_NE(message.find("Domain/Periodic"), std::string::npos) << message;
}

TEST(Parameters, NonPeriodicDirectionWithoutWallsIsRefused) {
  auto list = minimal_scene();
  list.sublist("Domain").set("Periodic", array<int>({1, 0}));
  validate_parameters(list);
  EXPECT_FALSE(error_of([&] { scene_from_parameters(list); }).empty());
}

TEST(Parameters, SetOverridesKeepTheDeclaredType) {
  auto list = minimal_scene();
  apply_override(list, "Fluid/Kinematic Viscosity=2.5e-3");
  apply_override(list, "Domain/Cell Size={2.0, 1.0}");
  apply_override(list, "Run/Max Steps=7");
  apply_override(list, "Scene/Name=override test");
  validate_parameters(list);
  const SceneConfig scene = scene_from_parameters(list);
  EXPECT_EQ(scene.kinematic_viscosity, 2.5e-3);
  EXPECT_EQ(scene.cell_size[0], 2.0);
  EXPECT_EQ(scene.max_steps, 7);
  EXPECT_EQ(scene.name, "override test");
}

// The steady solver's outer and inner restarts are set apart: the outer
// one (a Newton step's GMRES) by Solver/Krylov Restart, the inner solves'
// by Solver/Inner Krylov Restart.
TEST(Parameters, OuterAndInnerKrylovRestartsAreApart) {
  auto list = minimal_scene();
  validate_parameters(list);
  const SceneConfig defaults = scene_from_parameters(list);
  EXPECT_EQ(defaults.solver.restart, 30);
  EXPECT_EQ(defaults.solver.inner_restart, 30);
  apply_override(list, "Solver/Krylov Restart=120");
  apply_override(list, "Solver/Inner Krylov Restart=20");
  validate_parameters(list);
  const SceneConfig scene = scene_from_parameters(list);
  EXPECT_EQ(scene.solver.restart, 120);
  EXPECT_EQ(scene.solver.inner_restart, 20);
  auto too_short = minimal_scene();
  too_short.sublist("Solver").set("Inner Krylov Restart", 1);
  const auto message = error_of([&] { validate_parameters(too_short); });
  EXPECT_NE(message.find("Inner Krylov Restart"), std::string::npos) << message;
}

// Solver/DG Preconditioner: 'auto' by default, 'schwarz' taken in 2D and
// refused in 3D (its set-up and factors are too dear there), by name;
// 'auto' taken in 3D (it never switches there).
TEST(Parameters, SchwarzDgPreconditionerIsFor2D) {
  auto list = minimal_scene();
  validate_parameters(list);
  EXPECT_EQ(scene_from_parameters(list).solver.dg_preconditioner, DgPreconditioner::Auto);
  apply_override(list, "Solver/Method=steady");
  apply_override(list, "Solver/DG Preconditioner=schwarz");
  validate_parameters(list);
  EXPECT_EQ(scene_from_parameters(list).solver.dg_preconditioner, DgPreconditioner::Schwarz);
  list.sublist("Domain").set("Cell Size", array<double>({1.0, 1.0, 1.0}));
  list.sublist("Fluid").set("Body Force", array<double>({1e-3, 0.0, 0.0}));
  validate_parameters(list);
  const auto message = error_of([&] { scene_from_parameters(list); });
  EXPECT_NE(message.find("Solver/DG Preconditioner = schwarz is for 2D"), std::string::npos) << message;
  apply_override(list, "Solver/DG Preconditioner=auto");
  EXPECT_EQ(scene_from_parameters(list).solver.dg_preconditioner, DgPreconditioner::Auto);
  auto misspelt = minimal_scene();
  misspelt.sublist("Solver").set("DG Preconditioner", std::string("ras"));
  EXPECT_NE(error_of([&] { validate_parameters(misspelt); }).find("'ras' is not one of"), std::string::npos);
}

TEST(Parameters, SetRejectsUnknownPathsAndBadValues) {
  auto list = minimal_scene();
  EXPECT_NE(error_of([&] { apply_override(list, "Fluid/Viscosity=1"); }).find("Fluid/Viscosity"), std::string::npos);
  EXPECT_NE(error_of([&] { apply_override(list, "Flud/Density=1"); }).find("Flud"), std::string::npos);
  EXPECT_NE(error_of([&] { apply_override(list, "Fluid/Density=heavy"); }).find("heavy"), std::string::npos);
  EXPECT_NE(error_of([&] { apply_override(list, "Run/Max Steps=1.5"); }).find("integer"), std::string::npos);
  EXPECT_FALSE(error_of([&] { apply_override(list, "Fluid/Density"); }).empty());
}

TEST(Parameters, CellSideMustHoldWholeSpacings) {
  auto list = minimal_scene();
  list.sublist("Discretization").set("Particle Spacing", 0.03);
  validate_parameters(list);
  // Refused as the scene is read (the pore-path check counts the lattice),
  // and by the lattice itself for a scene made otherwise.
  try {
    scene_from_parameters(list);
    FAIL() << "no error for a cell side of 33.3 spacings";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("is not a whole multiple of Discretization/Particle Spacing"),
              std::string::npos)
        << e.what();
  }
  list.sublist("Discretization").set("Particle Spacing", 0.025);
  SceneConfig scene = scene_from_parameters(list);
  scene.particle_spacing = 0.03;
  try {
    fill_lattice<2>(scene);
    FAIL() << "no error for a cell side of 33.3 spacings";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("Particle Spacing"), std::string::npos) << e.what();
  }
}

TEST(Parameters, EveryParameterIsDocumented) {
  std::ostringstream help;
  print_valid_parameters(help);
  for (const char* name : {"Cell Size", "Periodic", "Density", "Kinematic Viscosity", "Body Force",
                           "Particle Spacing", "End Time", "Max Steps"})
    EXPECT_NE(help.str().find(name), std::string::npos) << name;
}

// The one reading of numbers for the XML, --set and grain files: the whole
// text, finite, in range; nothing read "as far as it goes".
TEST(TextValues, NumbersAreReadWholeOrNotAtAll) {
  EXPECT_EQ(parse_number<double>(" 0.005 ").value, 0.005);
  EXPECT_EQ(parse_number<double>("+2.5e-3").value, 2.5e-3);
  EXPECT_EQ(parse_number<double>("-1").value, -1.0);
  for (const char* bad : {"0.005abc", "", "  ", "nan", "NaN", "inf", "-infinity", "0x10", "1e400", "1,5", "1 2"}) {
    const auto parsed = parse_number<double>(bad);
    EXPECT_FALSE(parsed.value) << "'" << bad << "' read as " << *parsed.value;
    EXPECT_FALSE(parsed.problem.empty()) << bad;
  }
  EXPECT_NE(parse_number<double>("nan").problem.find("finite"), std::string::npos);
  EXPECT_NE(parse_number<double>("1e400").problem.find("range"), std::string::npos);
  EXPECT_EQ(parse_number<int>("12").value, 12);
  for (const char* bad : {"12.5", "1e3", "12abc", "99999999999"}) EXPECT_FALSE(parse_number<int>(bad).value) << bad;
  EXPECT_EQ(parse_number<long long>("99999999999").value, 99999999999LL);
  EXPECT_EQ(parse_bool("true").value, true);
  EXPECT_EQ(parse_bool("0").value, false);
  EXPECT_FALSE(parse_bool("yes").value);
  EXPECT_EQ(parse_array<double>("{1, 2.5}").value, (std::vector<double>{1.0, 2.5}));
  EXPECT_EQ(parse_array<int>(" { } ").value, std::vector<int>{});
  for (const char* bad : {"1, 2", "{1, 2", "{1,, 2}", "{1, nan}", "{1, 2x}", "{1, }"})
    EXPECT_FALSE(parse_array<double>(bad).value) << bad;
  EXPECT_NE(parse_array<double>("{1, 2x}").problem.find("element 2 '2x'"), std::string::npos);
}

// Scene/Name makes the default output directory: no way out of it.
TEST(Parameters, SceneNameWithAPathSeparatorIsRefused) {
  for (const char* name : {"../up", "a/b", "a\\b"}) {
    auto list = minimal_scene();
    list.sublist("Scene").set("Name", std::string(name));
    validate_parameters(list);
    const auto message = error_of([&] { scene_from_parameters(list); });
    EXPECT_NE(message.find("path separator"), std::string::npos) << name << ": " << message;
  }
}

}  // namespace
}  // namespace poresph
