// Conservation properties of the pair loop and the time stepping.
#include <gtest/gtest.h>

#include <cmath>

#include "Scenes.hpp"
#include "TestSpaces.hpp"
#include "app/Simulation.hpp"

namespace poresph {
namespace {

template <class Space>
class Conservation : public ::testing::Test {};
TYPED_TEST_SUITE(Conservation, testing::ExecutionSpaces);

// Total momentum sum_a m_a v_a and the scale sum_a m_a |v_a| it is judged against.
template <class ParticleSet>
std::pair<std::array<double, 3>, double> momentum(const ParticleSet& P, bool fluid_only = false) {
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.m);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  std::array<double, 3> total{};
  double scale = 0;
  for (int i = 0; i < P.owned; ++i) {
    if (fluid_only && kind(i) != kFluid) continue;
    double speed_sq = 0;
    for (int d = 0; d < static_cast<int>(v.extent(1)); ++d) total[d] += m(i) * v(i, d), speed_sq += v(i, d) * v(i, d);
    scale += m(i) * std::sqrt(speed_sq);
  }
  return {total, scale};
}

TYPED_TEST(Conservation, InviscidFluidSlidingOverWallsKeepsItsMomentum) {
  SceneConfig scene = testing::channel(20);
  scene.kinematic_viscosity = 0.0;
  scene.velocity_scale = 1e-4;
  Simulation<2, TypeParam> sim(scene);
  auto& P = sim.particles();
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  for (int i = 0; i < P.owned; ++i)
    if (kind(i) == kFluid) v(i, 0) = 1e-4;
  Kokkos::deep_copy(P.v, v);
  sim.compute_rates();
  const auto [p0, scale] = momentum(P, true);
  for (int s = 0; s < 2000; ++s) {
    sim.step();
    if (s % 200 == 0) {
      const auto [p, sc] = momentum(P, true);
      std::printf("step %d  px %.6e  rel %.3e\n", s, p[0], (p[0] - p0[0]) / scale);
    }
  }
}

}  // namespace
}  // namespace poresph
