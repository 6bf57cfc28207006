// Conservation: linear momentum through the whole scheme in a periodic box
// without walls or body force; angular momentum through the pair loop.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "Scenes.hpp"
#include "TestSpaces.hpp"
#include "app/Simulation.hpp"
#include "physics/Density.hpp"
#include "physics/PairRates.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {
namespace {

template <class Space>
class Conservation : public ::testing::Test {};
TYPED_TEST_SUITE(Conservation, testing::ExecutionSpaces);

struct Momentum {
  double total[3] = {0, 0, 0};
  double scale = 0;  // sum_a m_a |v_a|: what round-off is measured against
};

template <class ParticleSet>
Momentum linear_momentum(const ParticleSet& P) {
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.m);
  Momentum result;
  const int dim = static_cast<int>(v.extent(1));
  for (int i = 0; i < P.owned; ++i) {
    double speed_sq = 0;
    for (int d = 0; d < dim; ++d) result.total[d] += m(i) * v(i, d), speed_sq += v(i, d) * v(i, d);
    result.scale += m(i) * std::sqrt(speed_sq);
  }
  return result;
}

// Moving particles conserve momentum to round-off: every term of a pair is
// antisymmetric. So do fixed particles in Stokes flow; the convective term
// in its difference form (physics/PairTerms.hpp) conserves it only to the
// discretisation error, which the next test bounds.
template <int Dim, class Space>
void check_linear_momentum(int n, ParticleMotion motion = ParticleMotion::Lagrangian, bool convection = false) {
  SceneConfig scene = testing::periodic_box(Dim, n);
  scene.resummation_interval = 50;
  scene.particle_motion = motion;
  scene.convection = convection;
  Simulation<Dim, Space> sim(scene);
  testing::randomise_velocities(sim.particles(), 0.02, 7);
  sim.compute_rates();
  const Momentum before = linear_momentum(sim.particles());
  for (int s = 0; s < 200; ++s) sim.step();
  const Momentum after = linear_momentum(sim.particles());
  for (int d = 0; d < Dim; ++d)
    EXPECT_LT(std::abs(after.total[d] - before.total[d]), 1e-13 * before.scale) << "direction " << d;
  // The flow did change: the check is not comparing a frozen state.
  EXPECT_LT(after.scale, 0.99 * before.scale);
}

TYPED_TEST(Conservation, LinearMomentumIsConservedInAPeriodicBox2D) { check_linear_momentum<2, TypeParam>(32); }
TYPED_TEST(Conservation, LinearMomentumIsConservedInAPeriodicBox3D) { check_linear_momentum<3, TypeParam>(10); }
TYPED_TEST(Conservation, FixedParticlesInStokesFlowConserveMomentum) {
  check_linear_momentum<2, TypeParam>(32, ParticleMotion::Fixed, false);
  check_linear_momentum<3, TypeParam>(10, ParticleMotion::Fixed, false);
}

// Fixed particles with the convective term: sum m (v.grad)v over a periodic
// box is the integral of div(v v) - v div v, zero for a smooth flow; in a
// random velocity field of 0.02 on a unit box it stays below 2e-4 of
// sum m |v| after 200 steps (measured 3e-6 in x, 3e-5 in y).
TYPED_TEST(Conservation, FixedParticlesWithConvectionNearlyConserveMomentum) {
  SceneConfig scene = testing::periodic_box(2, 32);
  scene.particle_motion = ParticleMotion::Fixed;
  scene.convection = true;
  Simulation<2, TypeParam> sim(scene);
  testing::randomise_velocities(sim.particles(), 0.02, 7);
  sim.compute_rates();
  const Momentum before = linear_momentum(sim.particles());
  for (int s = 0; s < 200; ++s) sim.step();
  const Momentum after = linear_momentum(sim.particles());
  for (int d = 0; d < 2; ++d) EXPECT_LT(std::abs(after.total[d] - before.total[d]), 2e-4 * before.scale);
  EXPECT_LT(after.scale, 0.99 * before.scale);
}

// n free fluid particles in the unit square, each drawn by
// draw(rng, x, v, rho, m) (host values), with their pressures (c^2 = 10),
// list within the kernel's support and pair sums: what a pair-loop test
// needs besides the loop.
template <class Space>
struct FluidCluster {
  using Memory = typename Space::memory_space;
  Particles<2, Memory> P;
  typename Particles<2, Memory>::Vector::HostMirror x, v;
  typename Particles<2, Memory>::Scalar::HostMirror rho, m;
  QuinticKernel<2> kernel;
  CellList<2, Space> cells;
  NeighbourList<2, Space> neighbours;
  PairSums<2, Space> sums{pair_sum_components<2, Space>(P, PairLoopOptions{})};

  template <class Draw>
  FluidCluster(const Space& space, int n, double h, unsigned seed, Draw&& draw) : kernel(h) {
    P.reserve(n);
    P.owned = n;
    x = Kokkos::create_mirror_view(P.x), v = Kokkos::create_mirror_view(P.v);
    rho = Kokkos::create_mirror_view(P.rho), m = Kokkos::create_mirror_view(P.m);
    auto kind = Kokkos::create_mirror_view(P.kind);
    std::mt19937 rng(seed);
    for (int i = 0; i < n; ++i) {
      double xi[2], vi[2];
      draw(rng, xi, vi, rho(i), m(i));
      for (int d = 0; d < 2; ++d) x(i, d) = xi[d], v(i, d) = vi[d];
      kind(i) = kFluid;
    }
    Kokkos::deep_copy(P.x, x), Kokkos::deep_copy(P.v, v), Kokkos::deep_copy(P.rho, rho);
    Kokkos::deep_copy(P.m, m), Kokkos::deep_copy(P.kind, kind);
    update_pressure(space, P, 10.0, 0.0);
    cells.build(space, P.x, n, Vec<2>{{0, 0}}, Vec<2>{{1, 1}}, kernel.cutoff);
    neighbours.build(space, cells, P.x, n, kernel.cutoff);
    sums.reserve(n);
  }
};

// The pair loop's forces on an isolated cluster: sum m a = 0 always, and
// sum m x cross a = 0 for the central pressure force. (Morris's viscous term
// acts along v_ab, not r_ab, so it does not conserve angular momentum:
// docs/validation.md.)
TYPED_TEST(Conservation, PressureForcesConserveAngularMomentum) {
  using Space = TypeParam;
  const Space space;
  const int n = 400;
  std::uniform_real_distribution<double> u(-1, 1);
  FluidCluster<Space> cluster(space, n, 0.03, 3, [&](std::mt19937& rng, double* x, double* v, double& rho, double& m) {
    double r;
    do {
      x[0] = 0.3 * u(rng), x[1] = 0.3 * u(rng);
      r = std::hypot(x[0], x[1]);
    } while (r > 0.3);
    x[0] += 0.5, x[1] += 0.5;
    v[0] = 0.1 * u(rng), v[1] = 0.1 * u(rng);
    rho = 1.0 + 0.05 * u(rng);
    m = 1e-3 * (1 + 0.1 * u(rng));
  });
  const auto &P = cluster.P, &x = cluster.x, &m = cluster.m;
  const auto& kernel = cluster.kernel;
  const auto& neighbours = cluster.neighbours;
  const auto& sums = cluster.sums;

  for (double nu : {0.0, 0.01}) {
    compute_pair_rates(space, P, neighbours, sums, kernel, FluidProperties{nu, 0.0}, Vec<2>::zero());
    auto a = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.dvdt);
    double force[2] = {0, 0}, force_scale = 0, torque = 0, torque_scale = 0;
    for (int i = 0; i < n; ++i) {
      force[0] += m(i) * a(i, 0), force[1] += m(i) * a(i, 1);
      force_scale += m(i) * std::hypot(a(i, 0), a(i, 1));
      torque += m(i) * (x(i, 0) * a(i, 1) - x(i, 1) * a(i, 0));
      torque_scale += m(i) * std::hypot(x(i, 0), x(i, 1)) * std::hypot(a(i, 0), a(i, 1));
    }
    ASSERT_GT(force_scale, 0);
    EXPECT_LT(std::abs(force[0]), 1e-14 * force_scale) << "nu = " << nu;
    EXPECT_LT(std::abs(force[1]), 1e-14 * force_scale) << "nu = " << nu;
    if (nu == 0.0) {
      EXPECT_LT(std::abs(torque), 1e-14 * torque_scale);
    }
  }
}

// A particle of a cluster in [0.2, 0.8]^2: small random velocity, density and mass.
inline void scatter_in_square(std::mt19937& rng, double* x, double* v, double& rho, double& m) {
  std::uniform_real_distribution<double> u(0, 1);
  x[0] = 0.2 + 0.6 * u(rng), x[1] = 0.2 + 0.6 * u(rng);
  v[0] = 0.1 * (u(rng) - 0.5), v[1] = 0.1 * (u(rng) - 0.5);
  rho = 1.0 + 0.05 * u(rng);
  m = 1e-3 * (1 + 0.1 * u(rng));
}

// The pair loop forms both ends of a fluid pair at once (FluidPairWeights
// in physics/PairDriver.hpp); each particle's rates must be the sums of
// the per-end terms of physics/PairTerms.hpp over all its neighbours,
// convection included: a brute-force double loop on random particles.
TYPED_TEST(Conservation, PairLoopRatesAreTheSumsOfThePerEndTerms) {
  using Space = TypeParam;
  const Space space;
  const int n = 300;
  const double nu = 0.01;
  FluidCluster<Space> cluster(space, n, 0.05, 5, scatter_in_square);
  const auto &P = cluster.P, &x = cluster.x, &v = cluster.v, &rho = cluster.rho, &m = cluster.m;
  const auto& kernel = cluster.kernel;
  PairLoopOptions options;
  options.convection = true;
  compute_pair_rates(space, P, cluster.neighbours, cluster.sums, kernel, FluidProperties{nu, 0.0}, Vec<2>::zero(),
                     options);
  auto a = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.dvdt);
  auto drho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.drhodt);
  auto term = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.pressure_term);
  int pairs = 0;
  for (int i = 0; i < n; ++i) {
    Vec<2> acceleration = Vec<2>::zero(), scale = Vec<2>::zero();
    double density_rate = 0, density_scale = 0;
    const Vec<2> v_i{{v(i, 0), v(i, 1)}};
    for (int j = 0; j < n; ++j) {
      const Vec<2> r{{x(i, 0) - x(j, 0), x(i, 1) - x(j, 1)}};
      const double distance = std::sqrt(dot(r, r));
      if (j == i || distance >= kernel.cutoff) continue;
      ++pairs;
      const double F = kernel.derivative_over_r(distance);
      const Vec<2> v_ij = v_i - Vec<2>{{v(j, 0), v(j, 1)}};
      const double c = continuity_rate(m(j), v_ij, r, F);
      const Vec<2> terms[3] = {pressure_acceleration(m(j), term(i), term(j), r, F),
                               viscous_acceleration(m(j), nu, 1 / rho(i), 1 / rho(j), v_ij, F),
                               convective_acceleration(m(j) / rho(j), v_i, v_ij, r, F)};
      density_rate += c, density_scale += std::abs(c);
      for (const auto& t : terms)
        for (int d = 0; d < 2; ++d) acceleration[d] += t[d], scale[d] += std::abs(t[d]);
    }
    EXPECT_NEAR(drho(i), density_rate, 1e-13 * density_scale) << i;
    for (int d = 0; d < 2; ++d) EXPECT_NEAR(a(i, d), acceleration[d], 1e-13 * scale[d]) << i << " " << d;
  }
  EXPECT_GT(pairs, 10 * n);  // particles with many neighbours: the sums are not near-empty
}

// A pair term from outside physics/terms/, as a new one is written
// (docs/code.md): the mass of each particle's neighbours within the support,
// summed in a component of its own and written out by its finish. The
// driver runs it beside the core terms; each particle's sum must be the
// brute-force one, and the core terms' rates what they are without it.
template <class Space>
struct NeighbourMassTerm : PairTermBase {
  static constexpr const char* name = "neighbour_mass";
  static constexpr int components = 1;
  // Its own sum grows from pairs of fluid particles too: those take the
  // general path, one end at a time.
  static constexpr bool fluid_pair_weights = false;
  Kokkos::View<double*, typename Space::memory_space> mass;  // what finish writes

  explicit NeighbourMassTerm(const PairTermInputs<2, Space>&) {}
  template <int Own, class Sums>
  KOKKOS_FORCEINLINE_FUNCTION void add_to_end(const PairEnd<2>&, const PairEnd<2>& other, const EndGeometry<2>&,
                                              const SeenVelocity<2>&, const Shared&, Sums& sum, Vec<2>&) const {
    sum.value[Own] += other.m;
  }
  template <class Particles, class Totals>
  KOKKOS_FORCEINLINE_FUNCTION void finish(const Particles&, int a, bool, const Totals& totals) const {
    mass(a) = totals.take(0);
  }
};

TYPED_TEST(Conservation, AnotherPairTermIsOneStructInTheList) {
  using Space = TypeParam;
  const Space space;
  const int n = 300;
  FluidCluster<Space> cluster(space, n, 0.05, 7, scatter_in_square);
  const auto &P = cluster.P, &x = cluster.x, &m = cluster.m;
  const FluidProperties fluid{0.01, 0.0};
  const PairLoopOptions options;
  const NoSlipFactors<2, Space> no_slip;
  const PairTermInputs<2, Space> inputs{P, fluid, options, no_slip, false};
  const auto policy = Kokkos::RangePolicy<Space>(space, 0, n);

  using Core = PairTermList<ContinuityTerm<2, Space>, PressureTerm<2, Space>, ViscousTerm<2, Space>>;
  using WithMass = PairTermList<ContinuityTerm<2, Space>, PressureTerm<2, Space>, ViscousTerm<2, Space>,
                                NeighbourMassTerm<Space>>;
  static_assert(pair_detail::sums_of<2, Space>(WithMass{}) == 1 + 2 + 1, "d rho/dt, dv/dt and the term's own sum");
  using MassOnly = PairDriver<2, Space, NeighbourMassTerm<Space>>;
  EXPECT_EQ(MassOnly::label(), "poresph::PairRates<neighbour_mass>");

  run_pair_loop(policy, inputs, cluster.neighbours, cluster.sums, cluster.kernel, Core{});
  run_pair_finish(policy, inputs, cluster.sums, Vec<2>::zero(), Core{});
  auto core_a = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.dvdt);
  auto core_drho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.drhodt);

  PairSums<2, Space> sums{pair_detail::sums_of<2, Space>(WithMass{})};
  sums.reserve(n);
  using Driver = PairDriver<2, Space, ContinuityTerm<2, Space>, PressureTerm<2, Space>, ViscousTerm<2, Space>,
                            NeighbourMassTerm<Space>>;
  using Finish = FinishPairRates<2, Space, ContinuityTerm<2, Space>, PressureTerm<2, Space>, ViscousTerm<2, Space>,
                                 NeighbourMassTerm<Space>>;
  Driver driver(inputs, cluster.neighbours, sums, cluster.kernel);
  Finish finish(inputs, sums, Vec<2>::zero());
  const Kokkos::View<double*, typename Space::memory_space> mass_sums("neighbour_mass", n);
  driver.NeighbourMassTerm<Space>::mass = mass_sums;
  finish.NeighbourMassTerm<Space>::mass = mass_sums;
  Kokkos::parallel_for("test::pair_loop_with_mass", policy, driver);
  Kokkos::parallel_for("test::finish_with_mass", policy, finish);
  space.fence();
  auto mass = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), mass_sums);
  auto a = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.dvdt);
  auto drho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.drhodt);
  double drho_scale = 0, a_scale = 0;
  for (int i = 0; i < n; ++i) {
    drho_scale = std::max(drho_scale, std::abs(core_drho(i)));
    for (int d = 0; d < 2; ++d) a_scale = std::max(a_scale, std::abs(core_a(i, d)));
  }
  ASSERT_GT(drho_scale, 0);
  ASSERT_GT(a_scale, 0);
  for (int i = 0; i < n; ++i) {
    double expected = 0;
    for (int j = 0; j < n; ++j) {
      const double distance = std::hypot(x(i, 0) - x(j, 0), x(i, 1) - x(j, 1));
      if (j != i && distance < cluster.kernel.cutoff) expected += m(j);
    }
    EXPECT_NEAR(mass(i), expected, 1e-15 * expected) << i;
    // The core terms' rates: the same to rounding (one end at a time instead of both at once).
    EXPECT_NEAR(drho(i), core_drho(i), 1e-13 * drho_scale) << i;
    for (int d = 0; d < 2; ++d) EXPECT_NEAR(a(i, d), core_a(i, d), 1e-13 * a_scale) << i;
  }
}

}  // namespace
}  // namespace poresph

namespace poresph {
namespace {

TYPED_TEST(Conservation, ResummationOnAnUndisturbedLatticeGivesTheReferenceDensity) {
  SceneConfig scene = testing::periodic_box(2, 20);
  scene.resummation_interval = 1;
  scene.density = 1000;
  scene.particle_motion = ParticleMotion::Lagrangian;  // fixed particles never re-sum
  Simulation<2, TypeParam> sim(scene);
  sim.step();  // at rest: positions stay on the lattice, density is re-summed
  auto rho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sim.particles().rho);
  for (int i = 0; i < sim.particles().owned; ++i) EXPECT_NEAR(rho(i), 1000.0, 1.0) << i;
}

// Keeping the neighbour list over several steps (skin) must not change the
// trajectory beyond round-off compared with rebuilding it every evaluation.
TYPED_TEST(Conservation, NeighbourSkinDoesNotChangeTheTrajectory) {
  std::vector<double> positions[2];
  long long rebuilds[2];
  for (int run = 0; run < 2; ++run) {
    SceneConfig scene = testing::periodic_box(2, 24);
    scene.neighbour_skin = run == 0 ? 0.0 : 0.3;
    scene.resummation_interval = 20;
    scene.particle_motion = ParticleMotion::Lagrangian;
    Simulation<2, TypeParam> sim(scene);
    testing::randomise_velocities(sim.particles(), 0.05, 11);
    sim.compute_rates();
    for (int s = 0; s < 150; ++s) sim.step();
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sim.particles().x);
    for (int i = 0; i < sim.particles().owned; ++i)
      for (int d = 0; d < 2; ++d) positions[run].push_back(Halo<2, TypeParam>::wrap_coordinate(x(i, d), 0, 1));
    rebuilds[run] = sim.neighbour_rebuilds();
  }
  EXPECT_GT(rebuilds[0], 5 * rebuilds[1]);  // the skin did save rebuilds
  ASSERT_EQ(positions[0].size(), positions[1].size());
  for (size_t k = 0; k < positions[0].size(); ++k) EXPECT_NEAR(positions[0][k], positions[1][k], 1e-12) << k;
}

}  // namespace
}  // namespace poresph
