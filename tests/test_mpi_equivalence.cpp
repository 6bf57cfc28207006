// The same scene on all ranks of MPI_COMM_WORLD and on rank 0 alone gives
// the same particles (position, velocity, density, matched by id) within
// 1e-10 after 200 steps, and the same forces on its grains and walls
// (diagnostics/SurfaceLoads.hpp). CTest runs this with 1, 2, 3 and 4 ranks.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <utility>

#include "Scenes.hpp"
#include "app/Simulation.hpp"
#include "diagnostics/SurfaceLoads.hpp"
#include "geometry/Grains.hpp"
#include "solver/FluidRegions.hpp"
#include "solver/SchwarzPreconditioner.hpp"
#include "solver/SteadySolver.hpp"
#include "solver/SteadySystem.hpp"

namespace poresph {
namespace {

struct State {
  double x[3], v[3], rho;
};

// Fluid velocities from a smooth field of position (the same whichever
// process holds the particle), so that the runs are not trivially at rest.
template <class Sim>
void stir(Sim& sim, double amplitude) {
  auto& P = sim.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  const auto& L = sim.scene().cell_size;
  for (int i = 0; i < P.owned; ++i) {
    if (kind(i) != kFluid) continue;
    v(i, 0) += amplitude * std::sin(2 * M_PI * x(i, 1) / L[1]) * std::cos(4 * M_PI * x(i, 0) / L[0]);
    v(i, 1) += amplitude * std::cos(2 * M_PI * x(i, 0) / L[0]);
  }
  Kokkos::deep_copy(P.v, v);
  sim.compute_rates();
}

// The loads on every surface, one list: each grain's force and torque, the walls', the image's.
template <int Dim>
std::vector<double> flat(const SurfaceLoads<Dim>& loads) {
  std::vector<double> values;
  for (size_t g = 0; g < loads.grain_force.size(); ++g) {
    values.insert(values.end(), loads.grain_force[g].begin(), loads.grain_force[g].end());
    values.insert(values.end(), loads.grain_torque[g].begin(), loads.grain_torque[g].end());
  }
  values.insert(values.end(), loads.walls.begin(), loads.walls.end());
  values.insert(values.end(), loads.image.begin(), loads.image.end());
  return values;
}

// Runs `steps` steps on `comm` and returns every particle's state on rank 0
// of it, and the loads on its surfaces into `loads`.
template <int Dim>
std::map<long long, State> run(const SceneConfig& scene, const Communicator& comm, double stir_amplitude,
                               int steps, std::vector<double>& loads) {
  Simulation<Dim, Kokkos::Serial> sim(scene, Kokkos::Serial(), comm);
  if (stir_amplitude > 0) stir(sim, stir_amplitude);
  for (int s = 0; s < steps; ++s) sim.step();
  loads = flat(sim.surface_loads());
  // Fixed particles' pairs, other processes' ghosts and periodic images
  // among them, are lattice offsets: every process reads the one stencil,
  // and holds its rows as masks over it.
  if (scene.particle_motion == ParticleMotion::Fixed) {
    EXPECT_TRUE(sim.pairs_on_stencil()) << "rank " << comm.rank();
    EXPECT_TRUE(sim.pairs_on_lattice_rows()) << "rank " << comm.rank();
  }
  const auto& P = sim.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto rho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.rho);
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.id);
  std::string rows;
  char buffer[64];
  for (int i = 0; i < P.owned; ++i) {
    rows += std::to_string(id(i));
    for (int d = 0; d < Dim; ++d) std::snprintf(buffer, sizeof buffer, " %.17g", x(i, d)), rows += buffer;
    for (int d = 0; d < Dim; ++d) std::snprintf(buffer, sizeof buffer, " %.17g", v(i, d)), rows += buffer;
    std::snprintf(buffer, sizeof buffer, " %.17g\n", rho(i));
    rows += buffer;
  }
  std::map<long long, State> result;
  std::istringstream in(comm.gather_text(rows));
  long long key;
  while (in >> key) {
    State s{};
    for (int d = 0; d < Dim; ++d) in >> s.x[d];
    for (int d = 0; d < Dim; ++d) in >> s.v[d];
    in >> s.rho;
    result[key] = s;
  }
  return result;
}

template <int Dim = 2>
void expect_same_on_any_number_of_ranks(const SceneConfig& scene, double stir_amplitude, int steps = 200) {
  const Communicator world;
  std::vector<double> distributed_loads, single_loads;
  const auto distributed = run<Dim>(scene, world, stir_amplitude, steps, distributed_loads);
  if (world.rank() != 0) return;
  SceneConfig one_process = scene;  // same physics, the whole cell in one box
  one_process.process_grid.clear();
  for (auto& c : one_process.cuts) c.clear();
  const auto single = run<Dim>(one_process, Communicator(MPI_COMM_SELF), stir_amplitude, steps, single_loads);
  ASSERT_EQ(distributed_loads.size(), single_loads.size());
  double load_scale = 0, load_difference = 0;
  for (size_t i = 0; i < single_loads.size(); ++i) {
    load_scale = std::max(load_scale, std::abs(single_loads[i]));
    load_difference = std::max(load_difference, std::abs(single_loads[i] - distributed_loads[i]));
  }
  if (scene.has_solid() || scene.walls != WallType::None) {
    ASSERT_GT(load_scale, 0);
  }
  EXPECT_LE(load_difference, 1e-10 * load_scale) << "loads on the surfaces";
  ASSERT_EQ(distributed.size(), single.size());
  double v_scale = 0;
  for (const auto& [id, s] : single)
    for (int d = 0; d < Dim; ++d) v_scale = std::max(v_scale, std::abs(s.v[d]));
  ASSERT_GT(v_scale, 0);
  double worst[3] = {0, 0, 0};
  for (const auto& [id, s] : single) {
    const auto it = distributed.find(id);
    ASSERT_NE(it, distributed.end()) << "particle " << id << " missing";
    const State& t = it->second;
    for (int d = 0; d < Dim; ++d) {
      double dx = s.x[d] - t.x[d];
      if (scene.periodic[d]) dx -= scene.cell_size[d] * std::round(dx / scene.cell_size[d]);
      worst[0] = std::max(worst[0], std::abs(dx) / scene.cell_size[d]);
      worst[1] = std::max(worst[1], std::abs(s.v[d] - t.v[d]) / v_scale);
    }
    worst[2] = std::max(worst[2], std::abs(s.rho - t.rho) / scene.density);
  }
  EXPECT_LT(worst[0], 1e-10) << "positions";
  EXPECT_LT(worst[1], 1e-10) << "velocities";
  EXPECT_LT(worst[2], 1e-10) << "densities";
  std::printf("%d ranks: largest relative differences: x %.2e, v %.2e, rho %.2e\n", world.size(), worst[0], worst[1],
              worst[2]);
}

TEST(MpiEquivalence, PeriodicBoxWithoutGrains) {
  SceneConfig scene = testing::periodic_box(2, 24);
  scene.resummation_interval = 50;
  expect_same_on_any_number_of_ranks(scene, 0.05);
}

TEST(MpiEquivalence, Channel) {
  SceneConfig scene = testing::channel(20);
  scene.body_force = {2e-4, 0, 0};
  scene.upper_wall_velocity = 1e-5;
  // Run far enough into the start-up that the flow has moved.
  scene.time_step = 2e-4;
  expect_same_on_any_number_of_ranks(scene, 0.0);
}

// 3D: RCB boxes of a cube with a sphere across its eight corners and one
// inside, driven by a body force along a diagonal (every direction's halo
// carries momentum), fixed particles with the wall pressure from the fluid
// (the defaults), and the same with moving particles.
TEST(MpiEquivalence, SpheresAcrossTheCornersOfACube) {
  SceneConfig scene = testing::periodic_box(3, 14);
  scene.grains = {Grain{{0.02, 0.97, 0.01}, 0.3, "corner sphere"}, Grain{{0.55, 0.5, 0.45}, 0.15, "inner sphere"}};
  scene.body_force = {0.02, 0.01, -0.015};
  expect_same_on_any_number_of_ranks<3>(scene, 0.0, 100);
  scene.particle_motion = ParticleMotion::Lagrangian;
  scene.wall_pressure = WallPressure::Continuity;
  scene.neighbour_skin = 0.2;
  expect_same_on_any_number_of_ranks<3>(scene, 0.0, 100);
}

// Grains that move (physics/RigidGrains.hpp): every process advances every
// grain from loads summed over the processes, and places its own boundary
// particles, which move between processes with their grain's index.
TEST(MpiEquivalence, GrainsThatMove) {
  SceneConfig scene = testing::periodic_box(2, 30);
  scene.grains = {Grain{{0.03, 0.96, 0}, 0.2, "corner grain"}, Grain{{0.55, 0.45, 0}, 0.12, "inner grain"}};
  scene.body_force = {0.02, 0.01, 0};
  scene.particle_motion = ParticleMotion::Lagrangian;
  scene.grain_motion = GrainMotion::Free;
  scene.grain_density = 3.0;
  scene.gravity = {0.0, -0.01, 0};
  expect_same_on_any_number_of_ranks(scene, 0.0);
}

TEST(MpiEquivalence, GrainAcrossThePeriodicCorner) {
  SceneConfig scene = testing::periodic_box(2, 30);
  scene.grains = {Grain{{0.03, 0.96, 0}, 0.2, "corner grain"}};
  scene.body_force = {0.02, 0.01, 0};
  scene.shifting_coefficient = 2.0;
  expect_same_on_any_number_of_ranks(scene, 0.0);
}

}  // namespace
}  // namespace poresph

namespace poresph {
namespace {

// A process grid whose first boxes are thinner than the support 3h + skin:
// their halos reach past the neighbouring box, and ghosts come from further.
TEST(MpiEquivalence, BoxesThinnerThanTheSupport) {
  SceneConfig scene = testing::periodic_box(2, 24);  // support 3h + skin = 0.133
  const int ranks = Communicator().size();
  scene.grid_decomposition = true;
  scene.process_grid = {ranks, 1};
  scene.cuts[0] = {0.0};
  for (int r = 1; r < ranks; ++r) scene.cuts[0].push_back(0.06 * r);  // boxes 0.06 wide
  scene.cuts[0].push_back(1.0);
  scene.cuts[1] = {0.0, 1.0};
  expect_same_on_any_number_of_ranks(scene, 0.05);
}

// Rows "id value" from every process, on rank 0 as one map by id.
template <class Value>
std::map<long long, Value> gathered_by_id(const Communicator& comm, const std::string& rows) {
  std::map<long long, Value> result;
  std::istringstream in(comm.gather_text(rows));
  long long key;
  Value value;
  while (in >> key >> value) result[key] = value;
  return result;
}

// The fluid's regions (solver/FluidRegions.hpp) on the pocket cell (the
// channel and its sealed pocket): each particle in the same region on any
// number of processes as on one; and the steady solve, one border a region,
// to the same k within its tolerance.
std::map<long long, int> pocket_regions(const SceneConfig& scene, const Communicator& comm, double& k) {
  Simulation<2, Kokkos::Serial> sim(scene, Kokkos::Serial(), comm);
  sim.compute_rates();
  const auto regions = find_fluid_regions(sim);
  const auto& P = sim.particles();
  const auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.id);
  const auto of = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), regions.of);
  std::string rows;
  for (int i = 0; i < P.owned; ++i) rows += std::to_string(id(i)) + " " + std::to_string(of(i)) + "\n";
  const auto result = gathered_by_id<int>(comm, rows);
  SteadyOptions options;
  options.tolerance = 1e-8;
  SteadySolver<2, Kokkos::Serial> solver(sim, Kokkos::Serial(), options, nullptr, nullptr);
  const auto report = solver.solve();
  EXPECT_TRUE(report.converged) << comm.size() << " processes";
  EXPECT_EQ(report.fluid_regions, 2);
  k = scene.kinematic_viscosity * sim.superficial_velocity()[0] / scene.body_force[0];
  return result;
}

TEST(MpiEquivalence, FluidRegionsAndSteadySolveOfPockets) {
  const SceneConfig scene = testing::pocket_cell(false);
  const Communicator world;
  double k_distributed = 0, k_single = 0;
  const auto distributed = pocket_regions(scene, world, k_distributed);
  if (world.rank() != 0) return;
  const auto single = pocket_regions(scene, Communicator(MPI_COMM_SELF), k_single);
  EXPECT_EQ(distributed, single);
  EXPECT_NEAR(k_distributed / k_single, 1.0, 1e-6);
  std::printf("%d ranks: k %.9e, one rank: %.9e\n", world.size(), k_distributed, k_single);
}

// The points per axis of a 2D scene's lattice.
std::array<int, 2> lattice_of(const SceneConfig& scene) {
  const double dx = scene.particle_spacing;
  return {static_cast<int>(std::lround(scene.cell_size[0] / dx)),
          static_cast<int>(std::lround(scene.cell_size[1] / dx))};
}

// A vector to precondition: smooth, and rough by id (the same on any number of processes).
template <class Particles, class Values>
void fill_test_vector(const Particles& P, const Values& fluid, const Values& r) {
  for (int i = 0; i < P.owned; ++i) {
    const double rough = 1e-3 * static_cast<double>(P.id(i) % 17);
    r(i) = fluid(i) * (std::sin(7.0 * P.x(i, 0)) + std::cos(3.0 * P.x(i, 1)) + rough);
  }
}

// Each fluid particle's value of z, by id, gathered on rank 0.
template <class Particles, class Values>
std::map<long long, double> fluid_values(const Particles& P, const Values& fluid, const Values& z,
                                         const Communicator& comm) {
  std::string rows;
  char row[64];
  for (int i = 0; i < P.owned; ++i)
    if (fluid(i) > 0) rows += (std::snprintf(row, sizeof row, "%lld %.17g\n", P.id(i), z(i)), row);
  return gathered_by_id<double>(comm, rows);
}

// The largest of one rank's values, and the largest difference of the distributed ones from them.
std::pair<double, double> largest_and_worst(const std::map<long long, double>& distributed,
                                            const std::map<long long, double>& single) {
  double largest = 0, worst = 0;
  for (const auto& [id, value] : single) largest = std::max(largest, std::abs(value));
  for (const auto& [id, value] : single) worst = std::max(worst, std::abs(distributed.at(id) - value));
  return {largest, worst};
}

// Restricted additive Schwarz with its coarse level
// (solver/SchwarzPreconditioner.hpp) on D G, probed from the distributed
// products: each process probes its own rows, gathers the entries of the
// blocks it solves, and sums the coarse operator with the others. Applied
// to the same vector, each particle's value is the one rank's to round-off
// (measured: 4e-13 of the largest on 3 ranks); and the steady solve with it
// gives the same k within 1e-5 (measured: 7e-7 on 3 ranks).
std::map<long long, double> schwarz_applied(const SceneConfig& scene, const Communicator& comm, double& k) {
  using System = SteadySystem<2, Kokkos::Serial>;
  Simulation<2, Kokkos::Serial> sim(scene, Kokkos::Serial(), comm);
  System system(sim, Kokkos::Serial());
  const auto& P = sim.particles();
  const int owned = P.owned;
  using View = System::View;
  const View fluid = system.fluid_mask();
  View r("r", owned), z("z", owned), velocity("velocity", owned * 2);
  fill_test_vector(P, fluid, r);
  auto dg = [&](const View& in, const View& out) {
    system.apply(nullptr, &in, velocity, View(), System::Accuracy::Forward, System::RateTerms::Pressure);
    system.apply(&velocity, nullptr, View(), out, System::Accuracy::Forward, System::RateTerms::Continuity);
  };
  SchwarzPreconditioner<2, Kokkos::Serial> schwarz(Kokkos::Serial(), comm, P.x, fluid, owned, lattice_of(scene),
                                                   scene.particle_spacing, 8, 2, 12, 1e-4, dg);
  EXPECT_EQ(schwarz.unmatched(), 0);
  EXPECT_TRUE(schwarz.two_level());
  schwarz.apply(r, z);
  const auto values = fluid_values(P, fluid, z, comm);
  SteadyOptions options;
  options.dg_preconditioner = DgPreconditioner::Schwarz;
  const auto report = SteadySolver<2, Kokkos::Serial>(sim, Kokkos::Serial(), options, nullptr, nullptr).solve();
  EXPECT_TRUE(report.converged) << comm.size() << " processes";
  k = sim.superficial_velocity()[0];
  return values;
}

TEST(MpiEquivalence, SchwarzSharedOutAmongTheProcesses) {
  const SceneConfig scene = testing::pocket_cell(true);
  const Communicator world;
  double k_distributed = 0, k_single = 0;
  const auto distributed = schwarz_applied(scene, world, k_distributed);
  if (world.rank() != 0) return;
  const auto single = schwarz_applied(scene, Communicator(MPI_COMM_SELF), k_single);
  ASSERT_EQ(distributed.size(), single.size());
  const auto [largest, worst] = largest_and_worst(distributed, single);
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(worst, 1e-10 * largest) << world.size() << " processes";
  EXPECT_NEAR(k_distributed / k_single, 1.0, 1e-5);
  std::printf("%d ranks: largest difference %.2e of %.2e; k %.9e, one rank %.9e\n", world.size(), worst, largest,
              k_distributed, k_single);
}

// The wide lattice preconditioner (solver/LatticePreconditioner.hpp) shares
// its sub-lattices' cycles out among the processes and gathers the pattern
// weights' coarse corrections and the results: applied to the same vector,
// each particle's value is the one rank's, to round-off.
std::map<long long, double> preconditioned(const SceneConfig& scene, const Communicator& comm) {
  Simulation<2, Kokkos::Serial> sim(scene, Kokkos::Serial(), comm);
  const auto& P = sim.particles();
  const int owned = P.owned;
  using View = Kokkos::View<double*, Kokkos::HostSpace>;
  View fluid("fluid", owned), r("r", owned), z("z", owned);
  for (int i = 0; i < owned; ++i) fluid(i) = P.kind(i) == kFluid ? 1.0 : 0.0;
  fill_test_vector(P, fluid, r);
  LatticePreconditioner<2, Kokkos::Serial> wide(Kokkos::Serial(), comm, P.x, fluid, owned, lattice_of(scene),
                                                scene.particle_spacing, 2);
  wide.set_pattern_weights({1.0, 0.8, 0.6, 0.4});
  wide.apply(r, z);
  return fluid_values(P, fluid, z, comm);
}

TEST(MpiEquivalence, WideLatticePreconditionerSharedOutAmongTheProcesses) {
  SceneConfig scene = testing::periodic_box(2, 40);
  scene.grains = grains_from_list({0.5, 0.5, 0.2}, 2);
  const Communicator world;
  const auto distributed = preconditioned(scene, world);
  if (world.rank() != 0) return;
  const auto single = preconditioned(scene, Communicator(MPI_COMM_SELF));
  ASSERT_EQ(distributed.size(), single.size());
  const auto [largest, worst] = largest_and_worst(distributed, single);
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(worst, 1e-13 * largest) << world.size() << " processes";
}

}  // namespace
}  // namespace poresph
