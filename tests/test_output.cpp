// Output that survives: HDF5 field files read back equal, an interrupted
// write leaves no file under the final name, a restart from a checkpoint
// continues bit for bit, and a NaN stops the run with a readable checkpoint
// of the last good state. CTest runs this on 1 and 2 MPI ranks.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>

#include "app/Run.hpp"
#include "app/Simulation.hpp"
#include "geometry/Grains.hpp"
#include "io/Hdf5File.hpp"
#include "io/Summary.hpp"
#include "SharedDirectory.hpp"

#include <nlohmann/json.hpp>

namespace poresph {
namespace {

using testing::world_rank;
using testing::world_size;

// A directory shared by all ranks of this run, empty.
std::string fresh_directory(const std::string& name) { return testing::fresh_shared_directory("output", name); }

TEST(Hdf5File, RowsAndBlocksReadBackEqual) {
  const std::string path = fresh_directory("roundtrip") + "/fields.h5";
  const int rank = world_rank(), size = world_size();
  // Rank r holds r + 3 rows, so that the offsets differ between ranks.
  const int rows = rank + 3;
  long long first = 0;
  for (int r = 0; r < rank; ++r) first += r + 3;
  std::vector<double> vectors(rows * 3);
  std::vector<int> kinds(rows);
  std::vector<long long> ids(rows);
  for (int i = 0; i < rows; ++i) {
    for (int c = 0; c < 3; ++c) vectors[i * 3 + c] = std::sin(1.0 + (first + i) * 3 + c);
    kinds[i] = static_cast<int>((first + i) % 3);
    ids[i] = 1000000000000LL + first + i;
  }
  // The grid: 4 x 2 per rank, stacked along the slow direction.
  std::vector<double> block(4 * 2);
  for (int k = 0; k < 8; ++k) block[k] = rank * 8 + k + 0.5;
  write_hdf5_atomically(path, MPI_COMM_WORLD, [&](Hdf5File& file) {
    file.set_attribute("time", 1.25);
    file.set_attribute("step", 42LL);
    file.set_attribute("note", std::string("round trip"));
    file.set_attribute("empty", std::vector<double>{});
    EXPECT_EQ(file.write_rows("vectors", vectors.data(), rows, 3), first);
    file.write_rows("kind", kinds.data(), rows, 0);
    file.write_rows("id", ids.data(), rows, 0);
    file.write_block("grid", {2LL * size, 4}, {2LL * rank, 0}, {2, 4}, block.data());
  });
  Hdf5File file(path, Hdf5File::Mode::Read, MPI_COMM_WORLD);
  EXPECT_EQ(file.double_attribute("time"), 1.25);
  EXPECT_EQ(file.integer_attribute("step"), 42);
  EXPECT_EQ(file.string_attribute("note"), "round trip");
  EXPECT_TRUE(file.double_array_attribute("empty").empty());
  long long total = 0;
  for (int r = 0; r < size; ++r) total += r + 3;
  EXPECT_EQ(file.shape("vectors"), (std::vector<long long>{total, 3}));
  // Every rank reads all rows back, its own and the others'.
  const auto all_vectors = file.read_rows<double>("vectors", 0, total);
  const auto all_kinds = file.read_rows<int>("kind", 0, total);
  const auto all_ids = file.read_rows<long long>("id", 0, total);
  for (long long i = 0; i < total; ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(all_vectors[i * 3 + c], std::sin(1.0 + i * 3 + c));
    EXPECT_EQ(all_kinds[i], i % 3);
    EXPECT_EQ(all_ids[i], 1000000000000LL + i);
  }
  const auto grid = file.read_rows<double>("grid", 0, 2LL * size);
  for (int k = 0; k < 8 * size; ++k) EXPECT_EQ(grid[k], k + 0.5);
}

TEST(Hdf5File, InterruptedWriteLeavesNoFileUnderTheFinalName) {
  const std::string dir = fresh_directory("interrupted");
  const std::string path = dir + "/fields.h5";
  const double value = 7.0;
  // A complete file first, then a write that dies half way.
  write_hdf5_atomically(path, MPI_COMM_WORLD, [&](Hdf5File& file) { file.write_rows("a", &value, 1, 0); });
  EXPECT_THROW(write_hdf5_atomically(path, MPI_COMM_WORLD,
                                     [&](Hdf5File& file) {
                                       file.write_rows("b", &value, 1, 0);
                                       throw std::runtime_error("crash while writing");
                                     }),
               std::runtime_error);
  MPI_Barrier(MPI_COMM_WORLD);
  Hdf5File file(path, Hdf5File::Mode::Read, MPI_COMM_WORLD);  // the earlier, complete file
  EXPECT_TRUE(file.has("a"));
  EXPECT_FALSE(file.has("b"));
  // And with no earlier file there is nothing under the final name at all.
  const std::string other = dir + "/other.h5";
  EXPECT_THROW(write_hdf5_atomically(other, MPI_COMM_WORLD,
                                     [&](Hdf5File&) { throw std::runtime_error("crash before writing"); }),
               std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(other));
}

// A grain across the periodic corner and a body force strong enough that
// particles move over several neighbour-list rebuilds within 200 steps.
SceneConfig moving_grain_cell() {
  SceneConfig s;
  s.name = "moving-grain-cell";
  s.dimension = 2;
  s.cell_size = {1.0, 1.0, 0};
  s.density = 1.0;
  s.kinematic_viscosity = 0.05;
  s.body_force = {0.5, 0.2, 0};
  s.velocity_scale = 0.5;
  s.particle_spacing = 1.0 / 24;
  s.smoothing_length_ratio = 1.0;
  s.resummation_interval = 30;
  s.shifting_coefficient = 2.0;
  s.grains = grains_from_list({0.0, 0.0, 0.22}, 2);
  s.end_time = 10.0;
  s.progress = ProgressMode::Never;
  s.particle_motion = ParticleMotion::Lagrangian;
  return s;
}

RunReport run_to(SceneConfig scene, long long steps, const std::string& dir, const std::string& restart = "",
                 long long inject_nan = -1) {
  scene.max_steps = steps;
  RunOptions options;
  options.output_dir = dir;
  options.progress_on_terminal = false;
  options.restart_file = restart;
  options.inject_nan_at_step = inject_nan;
  options.parameters_xml = "<ParameterList/>";
  return run_scene(scene, options);
}

// Every owned field of a checkpoint, by particle id.
std::map<long long, std::vector<double>> checkpoint_state(const std::string& path) {
  Hdf5File file(path, Hdf5File::Mode::Read, MPI_COMM_WORLD);
  const long long n = file.shape("id")[0];
  const auto ids = file.read_rows<long long>("id", 0, n);
  std::map<long long, std::vector<double>> state;
  for (const char* name : {"x", "v", "rho", "dvdt", "drhodt", "x_start", "v_start", "rho_start"}) {
    if (std::string(name) == "x_start" && !file.has(name)) continue;  // fixed particles keep none
    const auto values = file.read_rows<double>(name, 0, n);
    const size_t columns = values.size() / n;
    for (long long i = 0; i < n; ++i)
      for (size_t c = 0; c < columns; ++c) state[ids[i]].push_back(values[i * columns + c]);
  }
  return state;
}

void expect_restart_bit_for_bit(const SceneConfig& scene, const std::string& name) {
  const std::string whole = fresh_directory(name + "-whole"), halves = fresh_directory(name + "-halves");
  const auto uninterrupted = run_to(scene, 200, whole);
  if (scene.particle_motion == ParticleMotion::Lagrangian) {
    ASSERT_GT(uninterrupted.neighbour_rebuilds, 3) << "the scene should move through several list rebuilds";
  }
  run_to(scene, 100, halves);
  const auto resumed = run_to(scene, 200, halves, halves + "/checkpoint.h5");
  EXPECT_EQ(resumed.restarted_from_step, 100);
  EXPECT_EQ(resumed.steps, 200);
  const auto a = checkpoint_state(whole + "/checkpoint.h5");
  const auto b = checkpoint_state(halves + "/checkpoint.h5");
  ASSERT_EQ(a.size(), b.size());
  long long differing = 0;
  for (const auto& [id, values] : a) differing += b.at(id) != values;  // exact equality of every value
  EXPECT_EQ(differing, 0);
  EXPECT_EQ(uninterrupted.permeability[0][0], resumed.permeability[0][0]);
}

TEST(Checkpoint, RestartContinuesBitForBit) { expect_restart_bit_for_bit(moving_grain_cell(), "moving"); }
TEST(Checkpoint, RestartOfFixedParticlesContinuesBitForBit) {
  auto scene = moving_grain_cell();
  scene.particle_motion = ParticleMotion::Fixed;  // the default: wall pressure from the fluid, convection
  expect_restart_bit_for_bit(scene, "fixed");
}

TEST(Checkpoint, NaNStopsTheRunWithAReadableCheckpointOfTheLastGoodState) {
  const auto scene = moving_grain_cell();
  const std::string dir = fresh_directory("nan");
  std::string message;
  try {
    run_to(scene, 200, dir, "", 50);
  } catch (const SimulationFailure& failure) {
    message = failure.what();
  }
  EXPECT_NE(message.find("step 50,"), std::string::npos) << message;
  EXPECT_NE(message.find("NaN or Inf"), std::string::npos) << message;
  EXPECT_NE(message.find("particle "), std::string::npos) << message;
  EXPECT_NE(message.find("checkpoint.h5"), std::string::npos) << message;
  {
    Hdf5File file(dir + "/checkpoint.h5", Hdf5File::Mode::Read, MPI_COMM_WORLD);
    EXPECT_EQ(file.integer_attribute("step"), 49);  // the last good state
    EXPECT_EQ(file.integer_attribute("rates_valid"), 0);
  }
  const auto state = checkpoint_state(dir + "/checkpoint.h5");
  long long non_finite = 0;
  for (const auto& [id, values] : state)
    for (double value : values) non_finite += !std::isfinite(value);
  EXPECT_EQ(non_finite, 0);
  // The run goes on from it.
  const auto resumed = run_to(scene, 60, dir, dir + "/checkpoint.h5");
  EXPECT_EQ(resumed.restarted_from_step, 49);
  EXPECT_EQ(resumed.stopped_by, "max_steps");
  EXPECT_EQ(static_cast<long long>(state.size()), resumed.fluid_particles + resumed.boundary_particles);
}

TEST(Checkpoint, FailureIsRecordedInTheSummary) {
  const std::string dir = fresh_directory("nan-summary");
  EXPECT_THROW(run_to(moving_grain_cell(), 20, dir, "", 10), SimulationFailure);
  MPI_Barrier(MPI_COMM_WORLD);
  std::ifstream summary(dir + "/summary.json");
  const auto json = nlohmann::json::parse(summary);  // read back as scripts read it
  EXPECT_EQ(json.at("stopped_by"), "failure");
  EXPECT_NE(json.at("failure").get<std::string>().find("NaN or Inf"), std::string::npos) << json.dump(2);
  EXPECT_EQ(json.at("steps"), 9);  // the last good step
}

// summary.json reads back as written: strings with control characters and
// quotes, numbers to the last bit, NaN as null, keys in their order; bytes
// that are not UTF-8 (a file name in another encoding) become U+FFFD rather
// than an unreadable file.
TEST(Summary, ReadsBackAsWritten) {
  JsonObject inner;
  inner.add("kxx", 0.1).add("kyx", -1.2345678901234567e-300);
  const std::string awkward = std::string("tab\there, \"quoted\", back\\slash, bell\x07, nul") + '\0' + "end";
  JsonObject json;
  json.add("scene", awkward)
      .add("steps", 123456789012345LL)
      .add("steady", true)
      .add("nan", std::numeric_limits<double>::quiet_NaN())
      .add("permeability", inner)
      .add("warnings", std::vector<std::string>{"line one\nline two", "\xff\xfe not UTF-8"});
  const auto back = nlohmann::ordered_json::parse(json.str());
  EXPECT_EQ(back.at("scene").get<std::string>(), awkward);
  EXPECT_EQ(back.at("steps").get<long long>(), 123456789012345LL);
  EXPECT_EQ(back.at("steady"), true);
  EXPECT_TRUE(back.at("nan").is_null());
  EXPECT_EQ(back.at("permeability").at("kxx").get<double>(), 0.1);
  EXPECT_EQ(back.at("permeability").at("kyx").get<double>(), -1.2345678901234567e-300);
  EXPECT_EQ(back.at("warnings").at(0).get<std::string>(), "line one\nline two");
  EXPECT_EQ(back.at("warnings").at(1).get<std::string>(), "\xef\xbf\xbd\xef\xbf\xbd not UTF-8");
  std::vector<std::string> keys;
  for (const auto& item : back.items()) keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"scene", "steps", "steady", "nan", "permeability", "warnings"}));
}

// Each cause, and the order in which they are named.
TEST(Health, EachCauseIsRecognised) {
  const HealthLimits limits{1000.0, 0.1, 2.0, 50.0};
  const double x[2] = {0.1, 0.2}, still[2] = {0.0, 0.0}, slow[2] = {1.0, 1.0}, fast[2] = {2.0, 0.1};
  const double calm[2] = {1.0, -1.0}, violent[2] = {0.0, 60.0};
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(health_problem<2>(x, slow, calm, 1050.0, 0.0, true, limits), -1);
  EXPECT_EQ(health_problem<2>(x, slow, calm, 1101.0, 0.0, true, limits), kDensityVariation);
  EXPECT_EQ(health_problem<2>(x, slow, calm, 899.0, 0.0, true, limits), kDensityVariation);
  EXPECT_EQ(health_problem<2>(x, fast, calm, 1000.0, 0.0, true, limits), kSpeedLimit);
  EXPECT_EQ(health_problem<2>(x, still, violent, 1000.0, 0.0, true, limits), kAccelerationLimit);
  const double nan_x[2] = {nan, 0.0}, inf_v[2] = {0.0, inf};
  EXPECT_EQ(health_problem<2>(nan_x, slow, calm, 1000.0, 0.0, true, limits), kNonFinite);
  EXPECT_EQ(health_problem<2>(x, inf_v, calm, 1000.0, 0.0, true, limits), kNonFinite);
  EXPECT_EQ(health_problem<2>(x, slow, calm, 1000.0, nan, true, limits), kNonFinite);
  EXPECT_EQ(health_problem<2>(x, fast, calm, 2000.0, 0.0, true, limits), kDensityVariation);  // first cause
  // Boundary particles move as prescribed: only non-finite values count.
  EXPECT_EQ(health_problem<2>(x, fast, violent, 2000.0, 0.0, false, limits), -1);
  EXPECT_EQ(health_problem<2>(nan_x, still, calm, 1000.0, 0.0, false, limits), kNonFinite);
}

// The branch-free test of the fast path agrees with the causes: on every
// combination of the values above, fluid or not, and at each limit exactly.
TEST(Health, TheFastPathAgreesWithTheCauses) {
  const HealthLimits limits{1000.0, 0.1, 2.0, 50.0};
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const double values[] = {0.0, 1.0, -1.0, 2.0, 50.0, 60.0, nan, inf, -inf};
  const double densities[] = {1000.0, 1100.0, 1101.0, 899.0, 900.0, nan, inf, 0.0};
  int agreed = 0;
  for (double x : values)
    for (double v : values)
      for (double a : values)
        for (double rho : densities)
          for (double drhodt : {0.0, nan, -inf})
            for (bool fluid : {true, false}) {
              const double xs[2] = {0.5, x}, vs[2] = {v, 0.5}, as[2] = {a, -a};
              const bool expected = health_problem<2>(xs, vs, as, rho, drhodt, fluid, limits) < 0;
              EXPECT_EQ(healthy<2>(xs, vs, as, rho, drhodt, fluid, limits), expected)
                  << x << " " << v << " " << a << " " << rho << " " << drhodt << " " << fluid;
              agreed += expected;
            }
  EXPECT_GT(agreed, 100);  // healthy and unhealthy cases both
}

}  // namespace
}  // namespace poresph
