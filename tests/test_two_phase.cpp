// Two fluids on fixed particles (the Phases sublist): the layered channel
// (input/two_phase/layered_poiseuille.xml, solved for its steady state)
// against the piecewise-parabolic solution (diagnostics/LayeredChannel.hpp)
// at viscosity ratios 0.1, 1 and 10, its phases' saturations and relative
// permeabilities against their closed forms; each grain's own contact angle
// on a moving interface's lattice; and the refusals of input the phases do
// not take.
#include <gtest/gtest.h>

#include <Teuchos_Array.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "ErrorOf.hpp"
#include "MinimalScene.hpp"
#include "RunInput.hpp"
#include "Scenes.hpp"
#include "app/SceneCheck.hpp"
#include "app/Simulation.hpp"
#include "diagnostics/LayeredChannel.hpp"
#include "io/Parameters.hpp"
#include "scene/SceneBuilder.hpp"

namespace poresph {
namespace {

using testing::array;
using testing::run_input;

// Without Fluid/Sound Speed, surface tension's pressure sets the speed of
// sound: the Laplace pressure of the sharpest bend the kernel resolves,
// (Dim - 1) sigma / h, compresses the fluid by at most Fluid/Density
// Variation. (At the flow's scale alone a drop of 1e-6 N/m in the sphere
// pack's image compressed a particle by 10 % within 15 steps.)
TEST(TwoPhase, SurfaceTensionSetsTheSpeedOfSound) {
  for (int dim : {2, 3}) {
    SceneConfig scene = testing::periodic_box(dim, 20);
    scene.sound_speed = 0;
    scene.density = 1000;
    scene.kinematic_viscosity = 1e-6;
    scene.body_force = {1e-9, 0, 0};
    scene.phases.resize(2);
    scene.phases[0].density = scene.phases[1].density = 1000;
    scene.phases[0].kinematic_viscosity = scene.phases[1].kinematic_viscosity = 1e-6;
    scene.surface_tension = 1e-3;
    const DerivedParameters p = derive_parameters(scene);
    const double laplace = (dim - 1) * scene.surface_tension / p.smoothing_length;
    EXPECT_LE(laplace / (1000 * p.sound_speed * p.sound_speed), scene.density_variation * (1 + 1e-12)) << dim;
    scene.surface_tension = 0;  // the flow's scale alone
    EXPECT_LT(derive_parameters(scene).sound_speed, 0.1 * p.sound_speed) << dim;
    scene.surface_tension = 1e-3;
    scene.sound_speed = 0.25;  // a speed given is kept
    EXPECT_EQ(derive_parameters(scene).sound_speed, 0.25) << dim;
  }
}

TEST(LayeredChannel, OneViscosityIsPlanePoiseuille) {
  // mu_A = mu_B: u = G y (H - y) / (2 mu), each half holds half the flux.
  const LayeredChannel c{2.0, 1.0, 0.5, 0.5, 3.0};
  EXPECT_DOUBLE_EQ(c.zero_stress(), 1.0);
  EXPECT_DOUBLE_EQ(c.velocity(0.5), 3.0 * 0.5 * 1.5 / 1.0);
  EXPECT_DOUBLE_EQ(c.velocity(1.5), 3.0 * 1.5 * 0.5 / 1.0);
  EXPECT_DOUBLE_EQ(c.lower_relative_permeability(), 0.5);
  EXPECT_DOUBLE_EQ(c.upper_relative_permeability(), 0.5);
}

// Stokes flow is linear in its forces: the profiles and fluxes of the
// force on each layer alone add up to those of the force on both; and its
// operator is self-adjoint, so the coupling is reciprocal (Onsager): the
// flux the force on A drives in B is the flux the same force on B drives in A.
TEST(LayeredChannel, OneLayerDrivenAtATimeAddsUpToBothDriven) {
  const double H = 1.0, a = 0.3, mu_A = 1.0, mu_B = 7.0, G = 2.0;
  const LayeredChannel both{H, a, mu_A, mu_B, G};
  const LayeredChannel lower{H, a, mu_A, mu_B, G, 1.0, 0.0}, upper{H, a, mu_A, mu_B, G, 0.0, 1.0};
  for (double y : {0.05, 0.2, 0.29, 0.31, 0.6, 0.95})
    EXPECT_NEAR(lower.velocity(y) + upper.velocity(y), both.velocity(y), 1e-14 * both.peak()) << "y = " << y;
  EXPECT_NEAR(lower.lower_flux() + upper.lower_flux(), both.lower_flux(), 1e-14 * both.lower_flux());
  EXPECT_NEAR(lower.upper_flux() + upper.upper_flux(), both.upper_flux(), 1e-14 * both.upper_flux());
  EXPECT_GT(lower.upper_flux(), 0.0);  // dragged along
  EXPECT_NEAR(lower.upper_flux(), upper.lower_flux(), 1e-14 * upper.lower_flux());
  // Each layer's velocity and stress continuous at the interface, no slip at the plates.
  const double e = 1e-7;
  for (const LayeredChannel* c : {&lower, &upper}) {
    EXPECT_NEAR(c->velocity(a - e), c->velocity(a), 1e-6 * c->peak());
    const double below = mu_A * (c->velocity(a) - c->velocity(a - e)) / e;
    const double above = mu_B * (c->velocity(a + e) - c->velocity(a)) / e;
    EXPECT_NEAR(below, above, 1e-5 * G);
    EXPECT_DOUBLE_EQ(c->velocity(0.0), 0.0);
    EXPECT_NEAR(c->velocity(H), 0.0, 1e-15);
  }
  // The undriven upper layer carries a constant stress: its profile is a straight line.
  EXPECT_NEAR(lower.velocity(0.65), 0.5 * (lower.velocity(0.4) + lower.velocity(0.9)), 1e-14);
}

TEST(LayeredChannel, StressAndVelocityAreContinuousAtTheInterface) {
  const LayeredChannel c{1.0, 0.3, 1.0, 7.0, 2.0};
  const double a = 0.3, e = 1e-7;
  EXPECT_NEAR(c.velocity(a - e), c.velocity(a), 1e-6 * c.peak());
  // mu u' from either side: G (y0 - a).
  const double lower = 1.0 * (c.velocity(a) - c.velocity(a - e)) / e;
  const double upper = 7.0 * (c.velocity(a + e) - c.velocity(a)) / e;
  EXPECT_NEAR(lower, 2.0 * (c.zero_stress() - a), 1e-5);
  EXPECT_NEAR(upper, 2.0 * (c.zero_stress() - a), 1e-5);
  EXPECT_DOUBLE_EQ(c.velocity(0.0), 0.0);
  EXPECT_NEAR(c.velocity(1.0), 0.0, 1e-15);
}

// The layered scene at phase 1's viscosity ratio: each fluid particle of
// particles.csv against the solution, max |v_x - u| / u_max, and the
// summary's phases against the closed forms.
// driven: Phases/Driven Phase ('both', '0' or '1').
void expect_layered_profile(double ratio, const std::string& tag, const std::string& driven = "both") {
  const double H = 1e-3, nu = 1e-6, rho = 1000, F = 2e-4;
  std::ostringstream nu_b;
  nu_b.precision(17);
  nu_b << ratio * nu;
  const RunReport report = run_input(
      "two_phase/layered_poiseuille.xml",
      {"Phases/Phase 1/Kinematic Viscosity=" + nu_b.str(), "Phases/Driven Phase=" + driven}, "layered-" + tag);
  ASSERT_EQ(report.stopped_by, "steady_state");
  EXPECT_TRUE(report.solver.converged);
  const double share[2] = {driven == "1" ? 0.0 : 1.0, driven == "0" ? 0.0 : 1.0};
  const LayeredChannel exact{H, 0.5 * H, rho * nu, rho * ratio * nu, rho * F, share[0], share[1]};
  const auto csv = testing::output_directory("layered-" + tag) / "particles.csv";
  std::ifstream in(csv);
  ASSERT_TRUE(in) << csv;
  std::string line;
  std::getline(in, line);
  ASSERT_EQ(line, "id,kind,x,y,vx,vy,rho,p,phase");
  double worst = 0;
  int fluid = 0;
  while (std::getline(in, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream row(line);
    double id, kind, x, y, vx, vy, density, p;
    int phase = -1;
    row >> id >> kind >> x >> y >> vx >> vy >> density >> p >> phase;
    if (kind != 0) continue;
    ++fluid;
    EXPECT_EQ(phase, y > 0.5 * H ? 1 : 0) << "particle " << id << " at y = " << y;  // the upper half is phase 1
    worst = std::max(worst, std::abs(vx - exact.velocity(y)) / exact.peak());
  }
  EXPECT_EQ(fluid, report.fluid_particles);
  EXPECT_LT(worst, 0.01) << "viscosity ratio " << ratio;
  EXPECT_GT(worst, 0.0);  // measured, not a copy of the solution
  std::printf("viscosity ratio %g: max |v_x - u| / u_max = %.3e\n", ratio, worst);

  ASSERT_EQ(report.phases.size(), 2u);
  const double expected_kr[2] = {exact.lower_relative_permeability(), exact.upper_relative_permeability()};
  for (int p = 0; p < 2; ++p) {
    const auto& phase = report.phases[p];
    EXPECT_DOUBLE_EQ(phase.saturation, 0.5);  // 20 of the 40 rows each
    EXPECT_EQ(phase.axis, 0);
    EXPECT_EQ(phase.driven, share[p] > 0);
    ASSERT_TRUE(phase.has_relative_permeability);
    EXPECT_NEAR(phase.relative_permeability / expected_kr[p], 1.0, 0.01)
        << "phase " << p << " at viscosity ratio " << ratio;
    std::printf("  phase %d: k_r = %.5f, closed form %.5f\n", p, phase.relative_permeability, expected_kr[p]);
  }
  EXPECT_EQ(report.phases[1].name, "upper");
}

TEST(TwoPhase, LayeredChannelAtViscosityRatioTenth) { expect_layered_profile(0.1, "0.1"); }
TEST(TwoPhase, LayeredChannelAtViscosityRatioOne) { expect_layered_profile(1.0, "1"); }
TEST(TwoPhase, LayeredChannelAtViscosityRatioTen) { expect_layered_profile(10.0, "10"); }
// The force on one layer alone: the other is dragged along across the
// interface (its k_r the viscous coupling), both layers within 1 % of the
// piecewise-parabolic profile of that force.
TEST(TwoPhase, LayeredChannelDrivenInTheLowerLayerOnly) { expect_layered_profile(10.0, "10-driven-0", "0"); }
TEST(TwoPhase, LayeredChannelDrivenInTheUpperLayerOnly) { expect_layered_profile(10.0, "10-driven-1", "1"); }

// Each particle's phase goes into the checkpoint: a march stopped and
// continued ends as the march in one go, bit for bit.
std::string file_text(const std::string& tag, const std::string& name) {
  std::ifstream in(testing::output_directory(tag) / name, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}
// With one phase driven, its body force is carried by its particles into
// the checkpoint too (a continuation that added it twice, or lost it, would
// end elsewhere).
void expect_march_continued_as_in_one_go(const std::string& driven) {
  const std::string scene = "two_phase/layered_poiseuille.xml";
  const auto steps = [&](const std::string& n) {
    return std::vector<std::string>{"Solver/Method=explicit", "Run/Max Steps=" + n, "Phases/Driven Phase=" + driven};
  };
  const RunReport whole = run_input(scene, steps("400"), "phases-whole-" + driven);
  run_input(scene, steps("200"), "phases-parts-" + driven);
  const RunReport continued = run_input(scene, steps("400"), "phases-parts-" + driven, "checkpoint.h5");
  EXPECT_EQ(continued.restarted_from_step, 200);
  EXPECT_EQ(continued.steps, 400);
  const std::string particles = file_text("phases-whole-" + driven, "particles.csv");
  EXPECT_GT(particles.size(), 1000u);
  EXPECT_EQ(particles, file_text("phases-parts-" + driven, "particles.csv"));
  ASSERT_EQ(whole.phases.size(), 2u);
  ASSERT_EQ(continued.phases.size(), 2u);
  for (int p = 0; p < 2; ++p) {
    EXPECT_GT(whole.phases[p].superficial_velocity, 0.0);
    EXPECT_EQ(whole.phases[p].superficial_velocity, continued.phases[p].superficial_velocity);
  }
}
TEST(TwoPhase, AMarchContinuedFromItsCheckpointIsTheMarchInOneGo) { expect_march_continued_as_in_one_go("both"); }
TEST(TwoPhase, AMarchOfOneDrivenPhaseContinuedIsTheMarchInOneGo) { expect_march_continued_as_in_one_go("1"); }

// The driven phase is in each particle's phase acceleration: a checkpoint
// continued with another phase driven (or both) is refused, naming it.
TEST(TwoPhase, AMarchContinuedWithAnotherDrivenPhaseIsRefused) {
  const std::string scene = "two_phase/layered_poiseuille.xml";
  const auto steps = [&](const std::string& n, const std::string& driven) {
    return std::vector<std::string>{"Solver/Method=explicit", "Run/Max Steps=" + n, "Phases/Driven Phase=" + driven};
  };
  run_input(scene, steps("50", "1"), "phases-driven-changed");
  for (const std::string other : {"0", "both"}) {
    const std::string m = testing::error_of<std::exception>(
        [&] { run_input(scene, steps("100", other), "phases-driven-changed", "checkpoint.h5"); });
    EXPECT_NE(m.find("Phases/Driven Phase"), std::string::npos) << m;
  }
}

// The surface tension's acceleration goes into the checkpoint with each
// particle: a drop marched, stopped and continued ends as in one go (a
// continuation without the force, or with it on other particles, would not).
TEST(TwoPhase, ADropContinuedFromItsCheckpointIsTheMarchInOneGo) {
  const std::string scene = "two_phase/laplace_drop.xml";
  const auto steps = [](const std::string& n) {
    return std::vector<std::string>{"Solver/Method=explicit", "Run/Max Steps=" + n, "Output/Final Particles CSV=true"};
  };
  run_input(scene, steps("300"), "drop-whole");
  run_input(scene, steps("150"), "drop-parts");
  const RunReport continued = run_input(scene, steps("300"), "drop-parts", "checkpoint.h5");
  EXPECT_EQ(continued.restarted_from_step, 150);
  const std::string particles = file_text("drop-whole", "particles.csv");
  EXPECT_GT(particles.size(), 1000u);
  EXPECT_EQ(particles, file_text("drop-parts", "particles.csv"));
}

// The minimal scene with a second phase in its upper half.
Teuchos::ParameterList two_phase_scene() {
  auto list = testing::minimal_scene();
  auto& phases = list.sublist("Phases");
  phases.set("Count", 2);
  auto& second = phases.sublist("Phase 1");
  second.set("Kinematic Viscosity", 1e-3);
  second.set("Region Low", array<double>({0.0, 0.5}));
  second.set("Region High", array<double>({1.0, 1.0}));
  return list;
}

// What the phases do not take is refused before any work, naming the parameter.
std::string refusal(const std::function<void(Teuchos::ParameterList&)>& change) {
  auto list = two_phase_scene();
  change(list);
  return testing::error_of<ParameterError>([&] {
    validate_parameters(list);
    scene_from_parameters(list, "");
  });
}

// A moving interface's phase field is whole on every process: the memory
// estimate counts it on each, (57 + 48 D) bytes a lattice point and 24 a
// point of the lattice padded by twice the kernel's reach (3 spacings) each
// side, whatever the number of processes.
TEST(TwoPhase, MovingInterfaceCountsItsFieldOnEveryProcess) {
  auto list = two_phase_scene();
  validate_parameters(list);
  SceneConfig fixed = scene_from_parameters(list, "");
  list.sublist("Phases").set("Interface", std::string("moving"));
  validate_parameters(list);
  SceneConfig moving = scene_from_parameters(list, "");
  ASSERT_TRUE(moving.moving_interface);
  MemoryBudget budget;
  budget.available_bytes = 1e12;
  for (int ranks : {1, 4}) {
    const RunEstimate a = check_scene(fixed, ranks, budget), b = check_scene(moving, ranks, budget);
    ASSERT_GT(a.lattice_points, 0);
    ASSERT_EQ(a.lattice_points, 20 * 20);  // the unit cell at 0.05
    EXPECT_NEAR(b.bytes_per_process - a.bytes_per_process, (57.0 + 48.0 * 2) * 400 + 24.0 * 32 * 32, 1e-6) << ranks;
  }
}

// Phases/Contact Angles with grains: every solid lattice point that a fluid
// point faces takes the angle of the grain it lies in.
TEST(TwoPhase, EachGrainWetsAtItsOwnAngle) {
  auto list = two_phase_scene();
  list.sublist("Grains").set("Inline", array<double>({0.25, 0.3, 0.15, 0.7, 0.6, 0.2}));
  auto& phases = list.sublist("Phases");
  phases.set("Interface", std::string("moving"));
  phases.set("Surface Tension", 1e-3);
  phases.set("Contact Angles", array<double>({30.0, 150.0}));
  list.sublist("Solver").set("Method", std::string("explicit"));
  validate_parameters(list);
  const SceneConfig scene = scene_from_parameters(list, "");
  Simulation<2, Kokkos::DefaultHostExecutionSpace> sim(scene);
  const auto& field = *sim.phase_field();
  const double dx = scene.particle_spacing;
  int faced[2] = {0, 0};
  for (std::size_t k = 0; k < field.size(); ++k) {
    if (field.fluid(k)) continue;
    const auto i = field.point(k);
    bool faces_fluid = false;
    for (int d = 0; d < 2; ++d)
      for (int step : {-1, 1}) {
        auto j = i;
        j[d] = (j[d] + step + 20) % 20;
        faces_fluid = faces_fluid || field.fluid(field.index(j));
      }
    if (!faces_fluid) continue;
    const double x = (static_cast<double>(i[0]) + 0.5) * dx, y = (static_cast<double>(i[1]) + 0.5) * dx;
    const int grain = std::hypot(x - 0.25, y - 0.3) < std::hypot(x - 0.7, y - 0.6) ? 0 : 1;
    EXPECT_NEAR(field.solid_cos(k), std::cos((grain ? 150.0 : 30.0) * 3.14159265358979323846 / 180), 1e-15)
        << x << " " << y;
    ++faced[grain];
  }
  EXPECT_GT(faced[0], 10);
  EXPECT_GT(faced[1], 10);
}

TEST(TwoPhase, BadInputIsRefusedByName) {
  EXPECT_EQ(refusal([](auto&) {}), "");  // the scene the others change is taken
  const auto has = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos;
  };
  auto m = refusal([](auto& l) { l.sublist("Phases").set("Count", 3); });
  EXPECT_TRUE(has(m, "Phases/Count")) << m;
  m = refusal([](auto& l) { l.sublist("Phases").sublist("Phase 1").set("Kinematic Viscosity", 0.0); });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Kinematic Viscosity must be positive")) << m;
  m = refusal([](auto& l) { l.sublist("Phases").sublist("Phase 1").set("Region High", array<double>({1.0, 1.5})); });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Region Low and Region High")) << m;
  EXPECT_TRUE(has(m, "outside the cell")) << m;
  m = refusal([](auto& l) { l.sublist("Phases").sublist("Phase 1").set("Region Low", array<double>({0.0})); });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Region Low must have one value per direction")) << m;
  m = refusal([](auto& l) { l.sublist("Phases").sublist("Phase 1").set("Region Low", array<double>({0.5, 0.5})); 
                            l.sublist("Phases").sublist("Phase 1").set("Region High", array<double>({0.5, 1.0})); });
  EXPECT_TRUE(has(m, "Region Low must lie below Region High")) << m;
  m = refusal([](auto& l) { l.sublist("Discretization").set("Particle Motion", std::string("lagrangian")); });
  EXPECT_TRUE(has(m, "Phases/Count = 2 needs Discretization/Particle Motion = fixed")) << m;
  m = refusal([](auto& l) { l.sublist("Phases").sublist("Phase 1").set("Density", 800.0); });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Density")) << m;
  EXPECT_TRUE(has(m, "density ratio of 1")) << m;
  m = refusal([](auto& l) { l.sublist("Permeability").set("Tensor", true); });
  EXPECT_TRUE(has(m, "Permeability/Tensor with Phases/Count = 2")) << m;
  // The ladder takes phases by region (test_ladder); a drainage target is another Pc at each level.
  EXPECT_EQ(refusal([](auto& l) { l.sublist("Convergence").set("Levels", 2); }), "");
  m = refusal([](auto& l) { l.sublist("Fluid").set("Body Force", array<double>({0.0, 0.0}));
                            l.sublist("Fluid").set("Velocity Scale", 1.0);
                            l.sublist("Phases").set("Single Phase Permeability", 1e-3); });
  EXPECT_TRUE(has(m, "Phases/Single Phase Permeability")) << m;
  // Phase 1 with one phase: said, not ignored.
  m = refusal([](auto& l) { l.sublist("Phases").set("Count", 1); });
  EXPECT_TRUE(has(m, "Phases/Phase 1 is given, but Phases/Count = 1")) << m;
  // Viscosity ratios beyond the validated 0.01 to 100 (Fluid/Kinematic Viscosity is 1e-2 here).
  m = refusal([](auto& l) { l.sublist("Phases").sublist("Phase 1").set("Kinematic Viscosity", 1.5); });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Kinematic Viscosity = 1.5 is 150 times Fluid/Kinematic Viscosity")) << m;
  EXPECT_TRUE(has(m, "viscosity ratios from 0.01 to 100 are supported")) << m;
  m = refusal([](auto& l) { l.sublist("Phases").sublist("Phase 1").set("Kinematic Viscosity", 5e-5); });
  EXPECT_TRUE(has(m, "is 0.005 times Fluid/Kinematic Viscosity")) << m;
  EXPECT_EQ(refusal([](auto& l) { l.sublist("Phases").sublist("Phase 1").set("Kinematic Viscosity", 1.0); }), "");
  EXPECT_EQ(refusal([](auto& l) { l.sublist("Phases").sublist("Phase 1").set("Kinematic Viscosity", 1e-4); }), "");
  // The ends of the range, whose quotients miss 100 and 0.01 by a last bit: taken.
  for (const auto& [fluid, phase] : {std::pair<double, double>{1e-6, 1e-4}, {3e-6, 3e-8}})
    EXPECT_EQ(refusal([&, fluid = fluid, phase = phase](auto& l) {
                l.sublist("Fluid").set("Kinematic Viscosity", fluid);
                l.sublist("Phases").sublist("Phase 1").set("Kinematic Viscosity", phase);
              }),
              "")
        << fluid << ", " << phase;
  m = refusal([](auto& l) { l.sublist("Phases").set("Driven Phase", std::string("2")); });
  EXPECT_TRUE(has(m, "Driven Phase")) << m;
  m = refusal([](auto& l) {
    l.sublist("Phases").set("Driven Phase", std::string("1"));
    l.sublist("Fluid").set("Body Force", array<double>({0.0, 0.0}));
    l.sublist("Fluid").set("Velocity Scale", 1.0);
  });
  EXPECT_TRUE(has(m, "Phases/Driven Phase = 1 names the phase Fluid/Body Force acts on")) << m;
}

// One fluid and Phases/Driven Phase: said, not ignored.
TEST(TwoPhase, DrivenPhaseWithOneFluidIsRefused) {
  auto list = testing::minimal_scene();
  list.sublist("Phases").set("Driven Phase", std::string("0"));
  const std::string m = testing::error_of<ParameterError>([&] {
    validate_parameters(list);
    scene_from_parameters(list, "");
  });
  EXPECT_NE(m.find("Phases/Driven Phase = 0 chooses between two phases, and Phases/Count = 1"), std::string::npos) << m;
}

// A round region and surface tension: what they do not take.
TEST(TwoPhase, BadDropIsRefusedByName) {
  const auto has = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos;
  };
  const auto round = [](Teuchos::ParameterList& l) {
    auto& second = l.sublist("Phases").sublist("Phase 1");
    second.remove("Region Low");
    second.remove("Region High");
    second.set("Region Centre", array<double>({0.5, 0.5}));
    second.set("Region Radius", 0.25);
  };
  EXPECT_EQ(refusal(round), "");  // the minimal scene's cell is periodic, without walls or grains
  EXPECT_EQ(refusal([&](auto& l) { round(l), l.sublist("Phases").set("Surface Tension", 0.07); }), "");
  auto m = refusal([&](auto& l) { round(l), l.sublist("Phases").set("Surface Tension", -0.07); });
  EXPECT_TRUE(has(m, "Surface Tension")) << m;
  m = refusal([](auto& l) { l.sublist("Phases").sublist("Phase 1").set("Region Radius", 0.25); });
  EXPECT_TRUE(has(m, "give its region one way: a box (Region Low, Region High), a disc/sphere")) << m;
  m = refusal([](auto& l) {
    l.sublist("Phases").sublist("Phase 1").set("Region Centre", array<double>({0.5, 0.5}));
  });
  EXPECT_TRUE(has(m, "not two")) << m;
  m = refusal([&](auto& l) { round(l), l.sublist("Phases").sublist("Phase 1").set("Region Radius", 0.0); });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Region Radius = 0 must be positive")) << m;
  m = refusal([&](auto& l) { round(l), l.sublist("Phases").sublist("Phase 1").set("Region Radius", -0.1); });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Region Radius = -0.1 must be positive")) << m;
  m = refusal([&](auto& l) { round(l), l.sublist("Phases").sublist("Phase 1").set("Region Radius", 0.6); });
  EXPECT_TRUE(has(m, "narrower than the cell")) << m;
  m = refusal([&](auto& l) {
    round(l), l.sublist("Phases").sublist("Phase 1").set("Region Centre", array<double>({0.5}));
  });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Region Centre must have one value per direction")) << m;
  m = refusal([&](auto& l) {
    round(l), l.sublist("Phases").sublist("Phase 1").set("Region Centre", array<double>({0.5, 1.5}));
  });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Region Centre")) << m;
  EXPECT_TRUE(has(m, "outside the cell")) << m;
  m = refusal([](auto& l) {
    auto& second = l.sublist("Phases").sublist("Phase 1");
    second.remove("Region Low");
    second.remove("Region High");
  });
  EXPECT_TRUE(has(m, "Phases/Phase 1 needs its region")) << m;
  // Walls (or grains) carry no colour and there is no wetting yet.
  m = refusal([&](auto& l) {
    round(l), l.sublist("Phases").set("Surface Tension", 0.07);
    l.sublist("Domain").set("Periodic", array<int>({1, 0}));
    l.sublist("Walls").set("Type", std::string("channel"));
  });
  EXPECT_TRUE(has(m, "Phases/Surface Tension with Phases/Interface = fixed needs a cell periodic")) << m;
  m = refusal([&](auto& l) { l.sublist("Phases").set("Count", 1), l.sublist("Phases").remove("Phase 1");
                             l.sublist("Phases").set("Surface Tension", 0.07); });
  EXPECT_TRUE(has(m, "Phases/Surface Tension acts between two phases")) << m;
}

// Drainage (Phases/Phase 1/Drainage): what it does not take.
TEST(TwoPhase, BadDrainageIsRefusedByName) {
  const auto has = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos;
  };
  // The minimal scene as a channel, phase 1 by drainage.
  const auto drained = [](Teuchos::ParameterList& l, double saturation) {
    auto& second = l.sublist("Phases").sublist("Phase 1");
    second.remove("Region Low");
    second.remove("Region High");
    second.sublist("Drainage").set("Saturation", saturation);
    l.sublist("Domain").set("Periodic", array<int>({1, 0}));
    l.sublist("Walls").set("Type", std::string("channel"));
  };
  EXPECT_EQ(refusal([&](auto& l) { drained(l, 0.5); }), "");
  auto m = refusal([&](auto& l) { drained(l, 1.5); });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Drainage/Saturation = 1.5 must lie in (0, 1]")) << m;
  m = refusal([&](auto& l) { drained(l, 0.5), l.sublist("Phases").sublist("Phase 1").sublist("Drainage").set(
                                                  "Radius", 0.1); });
  EXPECT_TRUE(has(m, "give Saturation, Radius or Capillary Pressure, one of them")) << m;
  // A capillary pressure: positive, one way of choosing the step, with the surface tension it needs.
  const auto at_pressure = [&](auto& l, double pc, double sigma) {
    drained(l, 0.5);
    auto& rule = l.sublist("Phases").sublist("Phase 1").sublist("Drainage");
    rule.remove("Saturation");
    rule.set("Capillary Pressure", pc);
    rule.set("Surface Tension", sigma);
  };
  EXPECT_EQ(refusal([&](auto& l) { at_pressure(l, 100.0, 0.07); }), "");
  m = refusal([&](auto& l) { at_pressure(l, 100.0, 0.0); });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Drainage/Capillary Pressure needs Drainage/Surface Tension")) << m;
  m = refusal([&](auto& l) { at_pressure(l, -5.0, 0.07); });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Drainage/Capillary Pressure = -5 must be positive (Pa)")) << m;
  m = refusal([&](auto& l) {
    at_pressure(l, 100.0, 0.07);
    l.sublist("Phases").sublist("Phase 1").sublist("Drainage").set("Radius", 0.1);
  });
  EXPECT_TRUE(has(m, "give Saturation, Radius or Capillary Pressure, one of them")) << m;
  m = refusal([&](auto& l) { drained(l, 0.5), l.sublist("Convergence").set("Levels", 2); });
  EXPECT_TRUE(has(m, "Convergence/Levels > 1 with Phases/Phase 1/Drainage/Saturation")) << m;
  EXPECT_EQ(refusal([&](auto& l) { at_pressure(l, 100.0, 0.07), l.sublist("Convergence").set("Levels", 2); }), "");
  m = refusal([&](auto& l) { drained(l, 0.5), l.sublist("Phases").sublist("Phase 1").sublist("Drainage").set(
                                                  "Contact Angle", 90.0); });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Drainage/Contact Angle = 90 must lie in [0, 90)")) << m;
  m = refusal([&](auto& l) { drained(l, 0.5), l.sublist("Phases").sublist("Phase 1").sublist("Drainage").set(
                                                  "Contact Angle", -10.0); });
  EXPECT_TRUE(has(m, "Contact Angle = -10")) << m;
  m = refusal([&](auto& l) { drained(l, 0.5), l.sublist("Phases").sublist("Phase 1").sublist("Drainage").set(
                                                  "Inlet", std::string("z")); });
  EXPECT_TRUE(has(m, "Inlet = 'z' names an axis the 2D cell has not")) << m;
  m = refusal([&](auto& l) { drained(l, 0.5), l.sublist("Phases").sublist("Phase 1").sublist("Drainage").set(
                                                  "Inlet", std::string("y")); });
  EXPECT_TRUE(has(m, "Inlet = 'y': the cell is closed by walls across that axis")) << m;
  m = refusal([&](auto& l) { drained(l, 0.5), l.sublist("Phases").sublist("Phase 1").sublist("Drainage").set(
                                                  "Inlet", std::string("w")); });
  EXPECT_TRUE(has(m, "Inlet")) << m;
  m = refusal([&](auto& l) {
    auto& rule = l.sublist("Phases").sublist("Phase 1").sublist("Drainage");
    drained(l, 0.5), rule.set("Inlet", std::string("anywhere")), rule.set("Trapping", true);
  });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Drainage/Trapping needs an Inlet axis")) << m;
  m = refusal([&](auto& l) {
    drained(l, 0.5), l.sublist("Phases").sublist("Phase 1").set("Region Low", array<double>({0.0, 0.5}));
  });
  EXPECT_TRUE(has(m, "not two")) << m;
  m = refusal([&](auto& l) {
    drained(l, 0.5), l.sublist("Phases").sublist("Phase 1").set("Image Values", array<int>({2}));
  });
  EXPECT_TRUE(has(m, "not two")) << m;
  // The rest of the Drainage sublist without Saturation or Radius: said, not ignored.
  m = refusal([&](auto& l) { l.sublist("Phases").sublist("Phase 1").sublist("Drainage").set("Trapping", true); });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Drainage is given without Saturation, Radius or Capillary Pressure")) << m;
  m = refusal([&](auto& l) {
    l.sublist("Phases").sublist("Phase 1").sublist("Drainage").set("Contact Angle", 30.0);
  });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Drainage is given without Saturation, Radius or Capillary Pressure")) << m;
  // Image Values without an image.
  m = refusal([&](auto& l) {
    auto& second = l.sublist("Phases").sublist("Phase 1");
    second.remove("Region Low");
    second.remove("Region High");
    second.set("Image Values", array<int>({2}));
  });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Image Values names voxels of an image, and the scene has none")) << m;
  // An open cell: every ball fits.
  m = refusal([&](auto& l) {
    drained(l, 0.5), l.sublist("Domain").set("Periodic", array<int>({1, 1}));
    l.sublist("Walls").set("Type", std::string("none"));
  });
  EXPECT_TRUE(has(m, "Phases/Phase 1/Drainage needs a solid")) << m;
}

// The layered channel's walls 40 rows apart: a ball of radius 19.5
// spacings (half the width less half a spacing, the widest on the lattice)
// fills it, one a little wider does not enter and is refused by name.
TEST(TwoPhase, DrainageFillsAChannelUpToItsHalfWidth) {
  const double H = 1e-3, dx = H / 40;
  const auto by_radius = [&](double r) {
    std::ostringstream radius;
    radius.precision(17);
    radius << r;
    return std::vector<std::string>{"Phases/Phase 1/Region Low={}", "Phases/Phase 1/Region High={}",
                                    "Phases/Phase 1/Drainage/Radius=" + radius.str(),
                                    "Phases/Phase 1/Drainage/Surface Tension=0.02", "Solver/Method=steady"};
  };
  const RunReport full = run_input("two_phase/layered_poiseuille.xml", by_radius(19.5 * dx), "drain-channel");
  ASSERT_TRUE(full.drainage.placed);
  EXPECT_DOUBLE_EQ(full.drainage.saturation, 1.0);
  EXPECT_DOUBLE_EQ(full.phases[1].saturation, 1.0);
  EXPECT_NEAR(full.drainage.capillary_pressure, 0.02 / (19.5 * dx), 1e-9);
  EXPECT_EQ(full.drainage.inlet, "x");
  // A contact angle enters the pressure only: 2D, Pc = sigma cos(theta) / r.
  auto at_60 = by_radius(19.5 * dx);
  at_60.push_back("Phases/Phase 1/Drainage/Contact Angle=60");
  const RunReport wetting = run_input("two_phase/layered_poiseuille.xml", at_60, "drain-channel-60");
  EXPECT_DOUBLE_EQ(wetting.drainage.saturation, 1.0);
  EXPECT_NEAR(wetting.drainage.capillary_pressure / full.drainage.capillary_pressure, 0.5, 1e-12);
  EXPECT_EQ(wetting.drainage.contact_angle, 60.0);
  const std::string m = testing::error_of<std::exception>(
      [&] { run_input("two_phase/layered_poiseuille.xml", by_radius(19.6 * dx), "drain-channel-narrow"); });
  EXPECT_NE(m.find("Phases/Phase 1/Drainage/Radius"), std::string::npos) << m;
  EXPECT_NE(m.find("no ball of that radius reaches from the inlet"), std::string::npos) << m;
  EXPECT_NE(m.find("make it smaller"), std::string::npos) << m;
  // Below half a spacing the lattice has no smaller ball: said, and placed as at half a spacing.
  const RunReport small = run_input("two_phase/layered_poiseuille.xml", by_radius(0.4 * dx), "drain-channel-small");
  EXPECT_DOUBLE_EQ(small.drainage.saturation, 1.0);
  ASSERT_FALSE(small.warnings.empty());
  EXPECT_NE(small.warnings[0].find("is below half a particle spacing"), std::string::npos) << small.warnings[0];
}

// Drainage/Capillary Pressure is the radius of the Young-Laplace law: at
// Pc = sigma cos(theta) / (19.25 spacings) (2D) the channel fills as at that
// radius (19.5 spacings is the widest ball) and reports that Pc; a Pc too
// low for any ball to enter is refused.
TEST(TwoPhase, DrainageAtACapillaryPressureIsDrainageAtItsRadius) {
  const double H = 1e-3, dx = H / 40, sigma = 0.02;
  const auto at_pressure = [&](double pc, double angle) {
    std::ostringstream text;
    text.precision(17);
    text << "Phases/Phase 1/Drainage/Capillary Pressure=" << pc;
    return std::vector<std::string>{"Phases/Phase 1/Region Low={}", "Phases/Phase 1/Region High={}", text.str(),
                                    "Phases/Phase 1/Drainage/Surface Tension=0.02",
                                    "Phases/Phase 1/Drainage/Contact Angle=" + std::to_string(angle),
                                    "Solver/Method=steady"};
  };
  const double pc = sigma * 0.5 / (19.25 * dx);  // cos 60 = 0.5
  const RunReport report = run_input("two_phase/layered_poiseuille.xml", at_pressure(pc, 60), "drain-channel-pc");
  ASSERT_TRUE(report.drainage.placed);
  EXPECT_NEAR(report.drainage.radius / (19.25 * dx), 1.0, 1e-12);
  EXPECT_NEAR(report.drainage.capillary_pressure / pc, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(report.drainage.saturation, 1.0);
  const std::string m = testing::error_of<std::exception>([&] {
    run_input("two_phase/layered_poiseuille.xml", at_pressure(sigma * 0.5 / (19.6 * dx), 60), "drain-channel-pc-low");
  });
  EXPECT_NE(m.find("Phases/Phase 1/Drainage/Capillary Pressure = "), std::string::npos) << m;
  EXPECT_NE(m.find("no ball of that radius reaches from the inlet"), std::string::npos) << m;
  EXPECT_NE(m.find("make it larger"), std::string::npos) << m;
}

// Problem III at a coarse spacing drained to half its pore space: the
// phase placed is the drainage's step (summary.json's drainage and phases
// agree, and particles.csv's phase column holds that share), and the
// curve of drainage.csv fills as the radius falls.
TEST(TwoPhase, DrainageOfProblemThreeReachesItsTarget) {
  const RunReport report = run_input(
      "problem3/problem3.xml",
      {"Discretization/Particle Spacing=0.002", "Phases/Count=2", "Phases/Phase 1/Kinematic Viscosity=2e-6",
       "Phases/Phase 1/Drainage/Saturation=0.5", "Phases/Single Phase Permeability=1e-5", "Solver/Method=steady",
       "Output/Final Particles CSV=true"},
      "drain-problem3");
  ASSERT_TRUE(report.drainage.placed);
  EXPECT_GE(report.drainage.saturation, 0.5);
  EXPECT_LT(report.drainage.saturation, 1.0);
  EXPECT_NEAR(report.phases[1].saturation, report.drainage.saturation, 1e-12);
  EXPECT_NEAR(report.drainage.curvature * report.drainage.radius, 1.0, 1e-12);  // 2D, theta = 0: 1 / r
  const auto dir = testing::output_directory("drain-problem3");
  std::ifstream particles(dir / "particles.csv");
  std::string line;
  std::getline(particles, line);
  ASSERT_EQ(line, "id,kind,x,y,vx,vy,rho,p,phase");
  long long fluid = 0, second = 0;
  while (std::getline(particles, line)) {
    const bool is_fluid = line.substr(line.find(',') + 1, 2) == "0,";
    fluid += is_fluid, second += is_fluid && line.back() == '1';
  }
  EXPECT_EQ(fluid, report.fluid_particles);
  EXPECT_NEAR(double(second) / double(fluid), report.drainage.saturation, 1e-12);
  std::ifstream curve(dir / "drainage.csv");
  std::getline(curve, line);
  EXPECT_EQ(line, "radius,saturation,curvature");
  double last_radius = INFINITY, last_saturation = -1;
  int rows = 0;
  while (std::getline(curve, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream row(line);
    double r, saturation;
    row >> r >> saturation;
    EXPECT_LT(r, last_radius);
    EXPECT_GE(saturation, last_saturation);
    last_radius = r, last_saturation = saturation, ++rows;
  }
  EXPECT_GT(rows, 20);
  EXPECT_DOUBLE_EQ(last_saturation, 1.0);
  EXPECT_DOUBLE_EQ(last_radius, 0.5 * 0.002);
}

// A 2D scene of an nx x ny image of `voxels` (values x fastest; 1 solid),
// written to the test's folder `name`, one particle a voxel of `voxel` m,
// nu and F along x.
Teuchos::ParameterList image_scene_list(const std::vector<char>& voxels, long long nx, long long ny, double voxel,
                                        double nu, double F, const std::string& name) {
  const auto folder = testing::output_directory(name);
  std::filesystem::create_directories(folder);
  const std::string raw = (folder / "image.raw").string();
  std::ofstream(raw, std::ios::binary).write(voxels.data(), static_cast<std::streamsize>(voxels.size()));
  auto list = testing::minimal_scene();
  list.sublist("Domain").set("Cell Size", array<double>({nx * voxel, ny * voxel}));
  list.sublist("Fluid").set("Kinematic Viscosity", nu);
  list.sublist("Fluid").set("Body Force", array<double>({F, 0.0}));
  list.sublist("Discretization").set("Particle Spacing", voxel);
  auto& image = list.sublist("Image");
  image.set("File", raw);
  image.set("Shape", array<int>({static_cast<int>(nx), static_cast<int>(ny)}));
  image.set("Type", std::string("uint8"));
  image.set("Solid Values", array<int>({1}));
  image.set("Voxel Size", voxel);
  list.sublist("Run").set("Progress", std::string("never"));
  return list;
}

// Runs a parameter list as poresph would, into the test folder `name`.
RunReport run_list(Teuchos::ParameterList list, const std::string& name) {
  validate_parameters(list);
  const SceneConfig scene = scene_from_parameters(list, "");
  RunOptions options;
  options.output_dir = testing::output_directory(name).string();
  std::filesystem::create_directories(options.output_dir);
  options.progress_on_terminal = false;
  options.parameters_xml = parameters_to_xml(list);
  return run_scene(scene, options);
}

// A run with phase 1 placed by drainage, continued from its checkpoint,
// reports the same drainage (the phases come with the particles, the step
// and curve are made again) and ends as the run in one go.
// Problem III with the non-wetting phase placed by drainage, driven along x
// in three runs: on both phases, on the wetting phase alone, on the
// non-wetting phase alone. Steady Stokes flow is linear in its forces, so
// each phase's flux (and k_r) of the two one-phase runs adds up to that of
// both, to the solver's tolerance: it does so only if a wall's pressure
// takes the force of the phase beside it (with one force for all the
// fluid next to the grains, the sums miss by 0.08-0.14 %). The coupling is
// reciprocal (Onsager) in the limit of resolution: k_r,nw,w / mu_nw =
// k_r,w,nw / mu_w, 0.28 % apart at this spacing (0.062 % at half of it,
// docs/validation.md).
TEST(TwoPhase, DrainedProblemThreeDrivenOnePhaseAtATimeAddsUp) {
  const auto run = [](const std::string& driven) {
    return run_input("two_phase/drainage_problem3.xml",
                     {"Discretization/Particle Spacing=0.002", "Phases/Driven Phase=" + driven},
                     "drain-driven-" + driven);
  };
  const RunReport both = run("both"), wetting = run("0"), non_wetting = run("1");
  for (const RunReport* r : {&both, &wetting, &non_wetting}) {
    ASSERT_EQ(r->stopped_by, "steady_state");
    ASSERT_EQ(r->phases.size(), 2u);
    ASSERT_TRUE(r->phases[0].has_relative_permeability);
  }
  EXPECT_TRUE(wetting.phases[0].driven && !wetting.phases[1].driven);
  EXPECT_TRUE(!non_wetting.phases[0].driven && non_wetting.phases[1].driven);
  for (int p = 0; p < 2; ++p) {
    const double sum = wetting.phases[p].relative_permeability + non_wetting.phases[p].relative_permeability;
    EXPECT_NEAR(sum / both.phases[p].relative_permeability, 1.0, 1e-4) << "phase " << p;
    EXPECT_GT(wetting.phases[p].relative_permeability, 0.0) << "phase " << p;
    EXPECT_GT(non_wetting.phases[p].relative_permeability, 0.0) << "phase " << p;
  }
  const double mu_ratio = 2.0;  // the non-wetting phase's viscosity over the wetting phase's
  const double reciprocity =
      wetting.phases[1].relative_permeability / mu_ratio / non_wetting.phases[0].relative_permeability;
  EXPECT_NEAR(reciprocity, 1.0, 0.01);
  std::printf("k_r,w = %.5f + %.5f, k_r,nw = %.5f + %.5f; reciprocity - 1 = %.2e\n",
              wetting.phases[0].relative_permeability, non_wetting.phases[0].relative_permeability,
              wetting.phases[1].relative_permeability, non_wetting.phases[1].relative_permeability, reciprocity - 1);
}

TEST(TwoPhase, DrainageContinuedFromItsCheckpointReportsItsStep) {
  const auto steps = [](const std::string& n) {
    return std::vector<std::string>{"Discretization/Particle Spacing=0.002", "Phases/Count=2",
                                    "Phases/Phase 1/Kinematic Viscosity=2e-6",
                                    "Phases/Phase 1/Drainage/Saturation=0.7", "Solver/Method=explicit",
                                    "Run/Max Steps=" + n, "Output/Final Particles CSV=true"};
  };
  const RunReport whole = run_input("problem3/problem3.xml", steps("200"), "drain-whole");
  run_input("problem3/problem3.xml", steps("100"), "drain-parts");
  const RunReport continued = run_input("problem3/problem3.xml", steps("200"), "drain-parts", "checkpoint.h5");
  EXPECT_EQ(continued.restarted_from_step, 100);
  ASSERT_TRUE(continued.drainage.placed);
  EXPECT_GT(whole.drainage.radius, 0.0);
  EXPECT_EQ(continued.drainage.radius, whole.drainage.radius);
  EXPECT_EQ(continued.drainage.saturation, whole.drainage.saturation);
  EXPECT_EQ(continued.drainage.curve.size(), whole.drainage.curve.size());
  EXPECT_EQ(file_text("drain-whole", "particles.csv"), file_text("drain-parts", "particles.csv"));
}

// Entry pressure of a throat: a 2D image (one particle a voxel) of a
// channel open to the cell's faces across x, 38 voxels wide, and below it
// a chamber that a throat w = 30 voxels wide and 20 long is the only way
// into (a ball wider than the throat bulges into it, not through). By the
// drainage rule the non-wetting phase enters the chamber at Pc =
// 2 sigma cos(theta) / w (a ball of radius w / 2): at 5 % below that
// pressure (r = 1.05 w / 2) the chamber stays wetting, at 5 % above it
// (r = 0.95 w / 2) phase 1 fills it. The lattice's widest ball in the
// throat is w / 2 - dx / 2 (3.3 % below w / 2).
TEST(TwoPhase, DrainageEntersAThroatAtItsCapillaryPressure) {
  const long long nx = 120, ny = 100, w = 30;
  const double voxel = 1e-4;
  std::vector<char> voxels(static_cast<size_t>(nx * ny), 1);
  for (long long j = 0; j < ny; ++j)
    for (long long i = 0; i < nx; ++i) {
      const bool channel = j >= 60 && j < 98, throat = j >= 40 && j < 60 && i >= 45 && i < 45 + w,
                 chamber = j >= 2 && j < 40 && i >= 20 && i < 100;
      if (channel || throat || chamber) voxels[static_cast<size_t>(i + nx * j)] = 0;
    }
  // Phase 1 particles in the chamber, at ball radius `ratio` w / 2.
  const auto in_chamber = [&](double ratio, const std::string& name) {
    auto list = image_scene_list(voxels, nx, ny, voxel, 1e-6, 1e-4, "drain-throat-image");
    auto& phases = list.sublist("Phases");
    phases.set("Count", 2);
    phases.sublist("Phase 1").set("Kinematic Viscosity", 1e-6);
    phases.sublist("Phase 1").sublist("Drainage").set("Radius", ratio * 0.5 * w * voxel);
    list.sublist("Run").set("Max Steps", 1);
    list.sublist("Output").set("Final Particles CSV", true);
    const RunReport report = run_list(list, name);
    EXPECT_GT(report.drainage.saturation, 0.0);  // the channel drains at either radius
    std::ifstream in(testing::output_directory(name) / "particles.csv");
    std::string line;
    std::getline(in, line);
    long long chamber = 0, drained = 0;
    while (std::getline(in, line)) {
      std::replace(line.begin(), line.end(), ',', ' ');
      std::istringstream row(line);
      double id, kind, x, y;
      row >> id >> kind >> x >> y;
      const int phase = line.back() - '0';
      if (kind == 0 && y < 40 * voxel) ++chamber, drained += phase == 1;
    }
    EXPECT_GT(chamber, 2500);
    return drained;
  };
  EXPECT_EQ(in_chamber(1.05, "drain-throat-closed"), 0);
  EXPECT_GT(in_chamber(0.95, "drain-throat-open"), 2000);  // of 3,040
}

// Phase 1 from a segmented image's labels (Phases/Phase 1/Image Values):
// the layered channel drawn as an image of 10 x 52 voxels, one particle a
// voxel, solid 12 rows thick (value 1) between the periodic copies, phase 0
// (value 0) in the lower 20 rows of the channel and phase 1 (value 2,
// ten times as viscous) in the upper 20. Each phase fills its half, and
// the k_r of the steady flow, over the single-phase k of the same image,
// are the layered solution's within 1 %.
TEST(TwoPhase, ImageLabelsPlaceTheLayeredChannel) {
  const long long nx = 10, ny = 52;
  const double voxel = 2.5e-5, H = 40 * voxel, nu = 1e-6, ratio = 10, F = 2e-4;
  std::vector<char> voxels(static_cast<size_t>(nx * ny));
  for (long long j = 0; j < ny; ++j)
    for (long long i = 0; i < nx; ++i)
      voxels[static_cast<size_t>(i + nx * j)] = j < 6 || j >= 46 ? 1 : j < 26 ? 0 : 2;
  const auto run = [&](bool two, double k, const std::string& name) {
    auto list = image_scene_list(voxels, nx, ny, voxel, nu, F, "image-labels");
    if (two) {
      auto& phases = list.sublist("Phases");
      phases.set("Count", 2);
      phases.set("Single Phase Permeability", k);
      phases.sublist("Phase 1").set("Kinematic Viscosity", ratio * nu);
      phases.sublist("Phase 1").set("Image Values", array<int>({2}));
    }
    list.sublist("Solver").set("Method", std::string("steady"));
    return run_list(list, name);
  };
  const RunReport single = run(false, 0, "image-labels-single");
  ASSERT_TRUE(single.solver.converged);
  const double k = single.permeability[0][0];
  const RunReport report = run(true, k, "image-labels-two");
  ASSERT_TRUE(report.solver.converged);
  ASSERT_EQ(report.phases.size(), 2u);
  const LayeredChannel exact{H, 0.5 * H, 1000 * nu, 1000 * ratio * nu, 1000 * F};
  const double expected[2] = {exact.lower_relative_permeability(), exact.upper_relative_permeability()};
  for (int p = 0; p < 2; ++p) {
    EXPECT_DOUBLE_EQ(report.phases[p].saturation, 0.5);
    EXPECT_NEAR(report.phases[p].relative_permeability / expected[p], 1.0, 0.01) << "phase " << p;
    std::printf("  phase %d: k_r = %.5f, layered solution %.5f\n", p, report.phases[p].relative_permeability,
                expected[p]);
  }
}

// A disc between the lattice points holds no particle: refused when the
// particles are made.
TEST(TwoPhase, EmptyDiscIsRefused) {
  const std::string m = testing::error_of<std::exception>([] {
    testing::run_input("two_phase/laplace_drop.xml",
                       {"Phases/Phase 1/Region Centre={4.0e-4, 4.0e-4}", "Phases/Phase 1/Region Radius=1.0e-6"},
                       "empty-disc");
  });
  EXPECT_NE(m.find("Phases/Phase 1/Region Centre and Region Radius: the disc (sphere) holds no fluid particle"),
            std::string::npos)
      << m;
}

// Laplace's law (issue 29): the 2D drop of input/two_phase/laplace_drop.xml
// (R = 20 spacings, sigma / R = 5 Pa) at rest, solved for its steady state.
// The pressure jump within 2 % of sigma / R, the largest speed left below
// 1e-4 sigma / mu, and each phase's mass that of its particles.
TEST(TwoPhase, DropAtRestKeepsLaplacesJump) {
  const RunReport report = run_input("two_phase/laplace_drop.xml", {}, "laplace-drop");
  ASSERT_TRUE(report.capillary.measured);
  const double sigma = 1e-3, R = 2e-4;
  EXPECT_DOUBLE_EQ(report.capillary.laplace_pressure, sigma / R);
  EXPECT_NEAR(report.capillary.pressure_jump / (sigma / R), 1.0, 0.02)
      << "jump " << report.capillary.pressure_jump << " Pa";
  EXPECT_LT(report.capillary.capillary_number, 1e-4) << "max |v| mu / sigma";
  // Fixed particles never change phase nor mass: each phase's mass is its
  // lattice points' count times rho0 dx^2, whatever the run did.
  ASSERT_EQ(report.phases.size(), 2u);
  const double dx = 1e-5, particle = 1000.0 * dx * dx;
  const double drop_particles = report.phases[1].mass / particle, all = 80.0 * 80.0;
  // (to the round-off of summing the particles' masses)
  EXPECT_NEAR(drop_particles, std::round(drop_particles), 1e-10 * drop_particles);
  EXPECT_NEAR(report.phases[0].mass / particle + drop_particles, all, 1e-10 * all);
  EXPECT_NEAR(drop_particles / (M_PI * 20 * 20), 1.0, 0.01);  // the disc's lattice points
}

}  // namespace
}  // namespace poresph
