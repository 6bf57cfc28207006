// No data race: the same scene stepped on the Serial and on the OpenMP
// execution space (2 threads) gives the same particles after 100 steps, to
// 1e-12 relative. Serial walks a half neighbour list and OpenMP a full one
// (core/NeighbourList.hpp), so the sums are taken in another order and the
// results differ by round-off; a race would show as far more. Two OpenMP
// runs, each particle summing its own neighbours in a fixed order, agree
// bit for bit. Skipped in a build whose Kokkos has no OpenMP.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>

#include "Scenes.hpp"
#include "app/Simulation.hpp"
#include "geometry/Grains.hpp"

namespace poresph {
namespace {

struct State {
  double x[2], v[2], rho;
};

template <class Space>
std::map<long long, State> run_100_steps(const SceneConfig& scene) {
  Simulation<2, Space> sim(scene);
  testing::randomise_velocities(sim.particles(), 0.02, 5);
  for (int s = 0; s < 100; ++s) sim.step();
  const auto& P = sim.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto rho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.rho);
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.id);
  std::map<long long, State> state;
  for (int i = 0; i < P.owned; ++i) state[id(i)] = {{x(i, 0), x(i, 1)}, {v(i, 0), v(i, 1)}, rho(i)};
  return state;
}

void expect_same_on_both_backends(const SceneConfig& scene) {
#ifdef KOKKOS_ENABLE_OPENMP
  ASSERT_GE(Kokkos::OpenMP::concurrency(), 2) << "run with OMP_NUM_THREADS=2";
  const auto serial = run_100_steps<Kokkos::Serial>(scene);
  const auto openmp = run_100_steps<Kokkos::OpenMP>(scene);
  ASSERT_EQ(serial.size(), openmp.size());
  double worst = 0, speed = 0;
  for (const auto& [id, s] : serial) speed = std::max(speed, std::hypot(s.v[0], s.v[1]));
  for (const auto& [id, s] : serial) {
    const State& o = openmp.at(id);
    for (int d = 0; d < 2; ++d) {
      worst = std::max(worst, std::abs(s.x[d] - o.x[d]));  // the cell is 1 long
      worst = std::max(worst, std::abs(s.v[d] - o.v[d]) / speed);
    }
    worst = std::max(worst, std::abs(s.rho - o.rho) / s.rho);
  }
  EXPECT_LE(worst, 1e-12);
  std::cout << "largest relative difference Serial - OpenMP after 100 steps: " << worst << "\n";
  const auto again = run_100_steps<Kokkos::OpenMP>(scene);
  long long differing = 0;
  for (const auto& [id, o] : openmp) {
    const State& a = again.at(id);
    differing += a.x[0] != o.x[0] || a.x[1] != o.x[1] || a.v[0] != o.v[0] || a.v[1] != o.v[1] || a.rho != o.rho;
  }
  EXPECT_EQ(differing, 0) << "two OpenMP runs differ: a race";
#else
  (void)scene;
  GTEST_SKIP() << "this Kokkos has no OpenMP backend";
#endif
}

TEST(Backends, OpenMPEqualsSerialOnAPeriodicBox) { expect_same_on_both_backends(testing::periodic_box(2, 32)); }

TEST(Backends, OpenMPEqualsSerialOnAGrainCellWithShifting) {
  auto scene = testing::periodic_box(2, 32);
  scene.grains = grains_from_list({0.0, 0.0, 0.2, 0.5, 0.55, 0.15}, 2);
  scene.shifting_coefficient = 2.0;
  scene.resummation_interval = 20;
  scene.body_force = {0.01, 0.0, 0};
  expect_same_on_both_backends(scene);
}

}  // namespace
}  // namespace poresph
