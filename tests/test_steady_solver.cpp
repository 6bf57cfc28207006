// The steady solver (solver/): its Jacobian products, the diagonal it
// probes, its Krylov method, and the steady state it finds against the
// time loop's.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "Scenes.hpp"
#include "TestSpaces.hpp"
#include "app/Simulation.hpp"
#include "geometry/Grains.hpp"
#include "solver/Fgmres.hpp"
#include "solver/FluidRegions.hpp"
#include "solver/LatticeMultigrid.hpp"
#include "solver/LatticePreconditioner.hpp"
#include "solver/LatticeSharpening.hpp"
#include "solver/SchwarzPreconditioner.hpp"
#include "solver/SteadySolver.hpp"
#include "solver/SteadySystem.hpp"

namespace poresph {
namespace {

template <class Space>
class SteadySolverTest : public ::testing::Test {};
TYPED_TEST_SUITE(SteadySolverTest, testing::ExecutionSpaces);

// A periodic cell of 20 x 20 fixed particles around one disc, driven along x.
SceneConfig disc_cell(bool convection, int points = 20) {
  SceneConfig s = testing::periodic_box(2, points);
  s.grains = grains_from_list({0.5, 0.5, 0.25}, 2);
  s.body_force = {1e-3, 0, 0};
  s.kinematic_viscosity = 0.01;
  s.sound_speed = 0;
  s.particle_motion = ParticleMotion::Fixed;
  s.convection = convection;
  return s;
}

template <class Space>
using View = typename SteadySystem<2, Space>::View;

template <class Space>
View<Space> random_vector(int n, unsigned seed, const View<Space>& mask, int per) {
  View<Space> w("w", n);
  auto h = Kokkos::create_mirror_view(w);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), mask);
  std::srand(seed);
  for (int i = 0; i < n; ++i) h(i) = m(i / per) * (std::rand() / double(RAND_MAX) - 0.5);
  Kokkos::deep_copy(w, h);
  return w;
}

template <class Space>
double difference(const View<Space>& a, const View<Space>& b) {
  auto ha = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a);
  auto hb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b);
  double diff = 0, size = 0;
  for (size_t i = 0; i < ha.extent(0); ++i) diff = std::max(diff, std::abs(ha(i) - hb(i))), size = std::max(size, std::abs(hb(i)));
  return size > 0 ? diff / size : diff;
}

// J (a + b) = J a + J b and J (3 a) = 3 J a: the products are of a linear
// operator, with and without convection (central differences are exact for
// its quadratic term).
TYPED_TEST(SteadySolverTest, ProductsAreLinear) {
  using Space = TypeParam;
  for (bool convection : {false, true}) {
    Simulation<2, Space> sim(disc_cell(convection));
    SteadySystem<2, Space> system(sim, Space());
    const int n = system.owned();
    const auto a_v = random_vector<Space>(2 * n, 1, system.fluid_mask(), 2);
    const auto a_q = random_vector<Space>(n, 2, system.fluid_mask(), 1);
    const auto b_v = random_vector<Space>(2 * n, 3, system.fluid_mask(), 2);
    const auto b_q = random_vector<Space>(n, 4, system.fluid_mask(), 1);
    View<Space> ja_v("ja_v", 2 * n), ja_q("ja_q", n), jb_v("jb_v", 2 * n), jb_q("jb_q", n), js_v("js_v", 2 * n),
        js_q("js_q", n);
    system.apply(&a_v, &a_q, ja_v, ja_q);
    system.apply(&b_v, &b_q, jb_v, jb_q);
    const auto& ops = system.vectors();
    View<Space> s_v("s_v", 2 * n), s_q("s_q", n);
    ops.copy(a_v, s_v), ops.copy(a_q, s_q);
    ops.update(1.0, b_v, 1.0, s_v), ops.update(1.0, b_q, 1.0, s_q);
    system.apply(&s_v, &s_q, js_v, js_q);
    ops.update(1.0, ja_v, 1.0, jb_v), ops.update(1.0, ja_q, 1.0, jb_q);
    EXPECT_LT(difference<Space>(js_v, jb_v), 1e-6) << "convection " << convection;
    EXPECT_LT(difference<Space>(js_q, jb_q), 1e-6) << "convection " << convection;
  }
}

// The preconditioner's products of one term are the Jacobian's blocks: the
// pressure term alone (G) gives the velocity rows of a density change,
// continuity alone (D) the density rows of a velocity change, with the
// grains' boundary particles (their wall pressure, their velocity) as in
// the whole rates. On lattice rows they are the simulation's exact linear
// products (physics/LatticeProducts.hpp), one partial evaluation each, and
// so is the velocity block (A) where no convection enters; the
// state is taken away from rest (densities 2 % apart, a flow), where the
// pressure term's p / rho^2 has a slope other than c^2 / rho^2, and the
// whole rates' products are central differences, so that what is left of
// their difference is the differences' own error. The forward differences
// of one-term pair loops (the path of lists that are not lattice rows) are
// compared with the forward differences of the whole rates, which have the
// same first-order error.
template <int Dim, class Space>
void expect_products_of_one_term_are_the_blocks(const SceneConfig& scene) {
  using System = SteadySystem<Dim, Space>;
  using V = typename System::View;
  Simulation<Dim, Space> sim(scene);
  auto P = sim.particles();
  const int owned = P.owned;
  static const std::string label = "test::away_from_rest";
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<Space>(0, owned), KOKKOS_LAMBDA(int i) {
        if (P.kind(i) != kFluid) return;
        P.rho(i) *= 1.0 + 0.01 * Kokkos::Experimental::sin(0.7 * i);
        for (int d = 0; d < Dim; ++d) P.v(i, d) = 1e-3 * Kokkos::Experimental::cos(0.3 * i + d);
      });
  Kokkos::fence();
  System system(sim, Space());
  ASSERT_TRUE(system.linear_products()) << "a fixed lattice on one process has lattice rows";
  const int n = system.owned();
  const auto w_v = random_vector<Space>(Dim * n, 5, system.fluid_mask(), Dim);
  const auto w_q = random_vector<Space>(n, 6, system.fluid_mask(), 1);
  V full_v("full_v", Dim * n), full_q("full_q", n), g_v("g_v", Dim * n), d_q("d_q", n), other_v("other_v", Dim * n),
      other_q("other_q", n);
  system.apply(nullptr, &w_q, full_v, full_q);
  system.apply(nullptr, &w_q, g_v, other_q, System::Accuracy::Forward, System::RateTerms::Pressure);
  EXPECT_LT(difference<Space>(g_v, full_v), 1e-8);
  system.apply(&w_v, nullptr, full_v, full_q);
  system.apply(&w_v, nullptr, other_v, d_q, System::Accuracy::Forward, System::RateTerms::Continuity);
  EXPECT_LT(difference<Space>(d_q, full_q), 1e-8);
  // Without convection the velocity block is a stencil sum too, its density
  // rows zero; so is its Stokes part (Viscous) with it, checked below.
  const int linear_velocity = sim.linear_velocity_products(System::RateTerms::Velocity) ? 1 : 0;
  const int linear_viscous = sim.linear_velocity_products(System::RateTerms::Viscous) ? 1 : 0;
  EXPECT_EQ(linear_viscous, 1) << "one fluid on lattice rows";
  if (linear_velocity) {
    system.apply(&w_v, nullptr, other_v, other_q, System::Accuracy::Forward, System::RateTerms::Velocity);
    EXPECT_LT(difference<Space>(other_v, full_v), 1e-8);
    EXPECT_EQ(system.vectors().norm(other_q), 0.0);
  }
  V stokes_v("stokes_v", Dim * n);
  system.apply(&w_v, nullptr, stokes_v, other_q, System::Accuracy::Forward, System::RateTerms::Viscous);
  EXPECT_EQ(system.vectors().norm(other_q), 0.0);
  EXPECT_EQ(system.partial_rate_evaluations(), 3 + linear_velocity) << "one evaluation a product, no base";
  system.difference_partial_products();
  system.apply(nullptr, &w_q, full_v, full_q, System::Accuracy::Forward);
  system.apply(nullptr, &w_q, other_v, other_q, System::Accuracy::Forward, System::RateTerms::Pressure);
  EXPECT_LT(difference<Space>(other_v, full_v), 1e-6);
  system.apply(&w_v, nullptr, full_v, full_q, System::Accuracy::Forward);
  system.apply(&w_v, nullptr, other_v, other_q, System::Accuracy::Forward, System::RateTerms::Continuity);
  EXPECT_LT(difference<Space>(other_q, full_q), 1e-6);
  EXPECT_EQ(system.partial_rate_evaluations(), 7 + linear_velocity)
      << "each term's rates at the state once, and one per product";
  // The velocity block (the terms whose accelerations depend on the
  // velocities) against the whole rates' velocity rows, its density rows
  // zero: central differences of both, then forward differences of both.
  system.apply(&w_v, nullptr, full_v, full_q);
  system.apply(&w_v, nullptr, other_v, other_q, System::Accuracy::Central, System::RateTerms::Velocity);
  EXPECT_LT(difference<Space>(other_v, full_v), 1e-8);
  EXPECT_EQ(system.vectors().norm(other_q), 0.0);
  system.apply(&w_v, nullptr, full_v, full_q, System::Accuracy::Forward);
  system.apply(&w_v, nullptr, other_v, other_q, System::Accuracy::Forward, System::RateTerms::Velocity);
  EXPECT_LT(difference<Space>(other_v, full_v), 1e-6);
  EXPECT_EQ(system.partial_rate_evaluations(), 11 + linear_velocity)
      << "two a central product, one a forward one and its base";
  // The Stokes part's linear product is the pair loop's of the viscous and
  // no-slip terms alone; where the flow convects, the whole block is not.
  system.apply(&w_v, nullptr, other_v, other_q, System::Accuracy::Central, System::RateTerms::Viscous);
  EXPECT_LT(difference<Space>(stokes_v, other_v), 1e-8);
  if (scene.convection) {
    EXPECT_GT(difference<Space>(stokes_v, full_v), 1e-6);
  }
}

TYPED_TEST(SteadySolverTest, ProductsOfOneTermAreTheJacobiansBlocks) {
  expect_products_of_one_term_are_the_blocks<2, TypeParam>(disc_cell(true));
  expect_products_of_one_term_are_the_blocks<2, TypeParam>(disc_cell(false));  // A on the lattice's sites
  // A sphere in a periodic cube of 12 a side.
  SceneConfig cube = testing::periodic_box(3, 12);
  cube.grains = grains_from_list({0.5, 0.5, 0.5, 0.3}, 3);
  cube.body_force = {1e-3, 0, 0};
  cube.sound_speed = 0;
  cube.particle_motion = ParticleMotion::Fixed;
  cube.convection = true;
  expect_products_of_one_term_are_the_blocks<3, TypeParam>(cube);
}

// An output of extent 0 is not wanted: G's velocity rows and D's density
// rows come out the same to the bit without it, every row written (the
// output starts full of NaNs, which a row multiplied by its zero weight
// would keep), on the linear products and on the differences of one-term
// pair loops; with all the terms both outputs are wanted.
TYPED_TEST(SteadySolverTest, AnOutputOfExtentZeroIsNotWanted) {
  using Space = TypeParam;
  using System = SteadySystem<2, Space>;
  using V = typename System::View;
  Simulation<2, Space> sim(disc_cell(true));
  System system(sim, Space());
  ASSERT_TRUE(system.linear_products());
  const int n = system.owned();
  const auto w_v = random_vector<Space>(2 * n, 5, system.fluid_mask(), 2);
  const auto w_q = random_vector<Space>(n, 6, system.fluid_mask(), 1);
  V g_v("g_v", 2 * n), d_q("d_q", n), other_v("other_v", 2 * n), other_q("other_q", n), alone_v("alone_v", 2 * n),
      alone_q("alone_q", n);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto not_finite = [](const V& values) {
    const auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), values);
    int count = 0;
    for (size_t i = 0; i < host.extent(0); ++i) count += std::isfinite(host(i)) ? 0 : 1;
    return count;
  };
  for (const bool differenced : {false, true}) {
    if (differenced) system.difference_partial_products();
    system.apply(nullptr, &w_q, g_v, other_q, System::Accuracy::Forward, System::RateTerms::Pressure);
    Kokkos::deep_copy(alone_v, nan);
    system.apply(nullptr, &w_q, alone_v, V(), System::Accuracy::Forward, System::RateTerms::Pressure);
    EXPECT_EQ(not_finite(alone_v), 0) << "differenced " << differenced;
    EXPECT_EQ(difference<Space>(alone_v, g_v), 0.0) << "differenced " << differenced;
    system.apply(&w_v, nullptr, other_v, d_q, System::Accuracy::Forward, System::RateTerms::Continuity);
    Kokkos::deep_copy(alone_q, nan);
    system.apply(&w_v, nullptr, V(), alone_q, System::Accuracy::Forward, System::RateTerms::Continuity);
    EXPECT_EQ(not_finite(alone_q), 0) << "differenced " << differenced;
    EXPECT_EQ(difference<Space>(alone_q, d_q), 0.0) << "differenced " << differenced;
  }
  EXPECT_THROW(system.apply(&w_v, nullptr, V(), alone_q), std::logic_error);
}

// The pair loop of the pressure term alone reads no velocity and adds no
// density rate (PairTermBase::reads_velocity, adds_density): with every
// velocity NaN its accelerations are those with the velocities it had, to
// the bit, and its density rates zero. A loop that loaded the velocities
// would carry the NaN in (0 times NaN is NaN).
TYPED_TEST(SteadySolverTest, PressureLoopReadsNoVelocity) {
  using Space = TypeParam;
  using Sim = Simulation<2, Space>;
  Sim sim(disc_cell(true));
  auto P = sim.particles();
  const int owned = P.owned;
  static const std::string label = "test::uneven_density";
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<Space>(0, owned),
      KOKKOS_LAMBDA(int i) { P.rho(i) *= 1.0 + 0.01 * Kokkos::Experimental::sin(0.7 * i); });
  Kokkos::fence();
  sim.compute_rates(Sim::RateTerms::Pressure);
  auto before = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.dvdt);
  Kokkos::deep_copy(P.v, std::numeric_limits<double>::quiet_NaN());
  sim.compute_rates(Sim::RateTerms::Pressure);
  auto after = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.dvdt);
  auto drhodt = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.drhodt);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  int fluid = 0, moved = 0;
  for (int i = 0; i < owned; ++i) {
    if (kind(i) != kFluid) continue;
    ++fluid;
    for (int d = 0; d < 2; ++d) {
      ASSERT_EQ(after(i, d), before(i, d)) << "particle " << i;
      moved += after(i, d) != (d == 0 ? 1e-3 : 0.0);  // beyond the body force: the pressure acted
    }
    ASSERT_EQ(drhodt(i), 0.0) << "particle " << i;
  }
  EXPECT_GT(fluid, 0);
  EXPECT_GT(moved, fluid / 2);
}

// The probed diagonal is J's: the response of a particle's own row to its own
// velocity, exact with central differences (a leak between two points of
// one colour would show at the size of their coupling). At 23 points a
// side (prime: no block of colours fits the lattice) every fluid particle
// is checked, those at the periodic end included, and the probes are few:
// points 3 spacings apart do not interact (the kernel's gradient vanishes
// at 3h, h = dx), so 5 colours along each axis (3, and 2 left over), 50
// products, where one colour per point took 1,712 rate evaluations; at 20
// a side 4 colours (a divisor), 32. The solver's default, forward
// differences, takes one rate evaluation a product and is within 1e-4 of it.
// The probes run the velocity block's pair loop (RateTerms::Velocity), whose
// diagonal is compared with the whole rates' products below.
TYPED_TEST(SteadySolverTest, DiagonalIsTheJacobians) {
  using Space = TypeParam;
  using System = SteadySystem<2, Space>;
  for (int points : {20, 23}) {
    Simulation<2, Space> sim(disc_cell(true, points));
    System system(sim, Space());
    const int n = system.owned();
    // Products of the velocity block's pair loop (partial evaluations), none of all the terms.
    const long long whole = system.rate_evaluations();
    long long before = system.partial_rate_evaluations();
    const auto diagonal = system.velocity_diagonal(System::Accuracy::Central);
    EXPECT_EQ(system.partial_rate_evaluations() - before, 2 * (points == 20 ? 32 : 50)) << points << " a side";
    before = system.partial_rate_evaluations();
    const auto forward = system.velocity_diagonal();
    EXPECT_EQ(system.partial_rate_evaluations() - before, (points == 20 ? 32 : 50) + 1)
        << points << " a side: one a product and the block's rates at the state";
    EXPECT_EQ(system.rate_evaluations(), whole);
    EXPECT_LT(difference<Space>(forward, diagonal), 1e-4);
    auto mask = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), system.fluid_mask());
    auto diag = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), diagonal);
    int checked = 0;
    for (int i = 0; i < n; i += points == 20 ? 37 : 1) {
      if (mask(i) == 0) continue;
      for (int c = 0; c < 2; ++c) {
        View<Space> e("e", 2 * n), out_v("out_v", 2 * n), out_q("out_q", n);
        Kokkos::deep_copy(Kokkos::subview(e, i * 2 + c), 1.0);
        system.apply(&e, nullptr, out_v, out_q);
        double own = 0;
        Kokkos::deep_copy(own, Kokkos::subview(out_v, i * 2 + c));
        EXPECT_NEAR(diag(i * 2 + c), own, 1e-8 * std::abs(own)) << "particle " << i << " component " << c;
        EXPECT_LT(own, 0) << "the rates damp a particle's own velocity";
      }
      ++checked;
    }
    EXPECT_GE(checked, 6);
  }
}

// A small matrix for FGMRES's tests: out_i = row(i, in) on the host, n rows.
template <class Space, class Row>
auto host_rows_operator(int n, Row row) {
  using V = Kokkos::View<double*, typename Space::memory_space>;
  return [n, row](const V& in, const V& out) {
    auto i_h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), in);
    auto o_h = Kokkos::create_mirror_view(out);
    for (int i = 0; i < n; ++i) o_h(i) = row(i, i_h);
    Kokkos::deep_copy(out, o_h);
  };
}

// |b - A x| / |b|, A given by apply.
template <class Space, class Apply, class V>
double relative_residual(const KrylovVectors<Space>& ops, const Apply& apply, const V& b, const V& x) {
  V r("r", b.extent(0));
  apply(x, r);
  ops.update(-1.0, b, 1.0, r);
  return ops.norm(r) / ops.norm(b);
}

// The Krylov inner product, a sum in lanes over blocks (core/BlockedSum.hpp),
// is the sum at every length: below one block, at one, one past it, and
// with a block's tail; against a sum in long double, to round-off.
TYPED_TEST(SteadySolverTest, BlockedSumIsTheSumAtEveryLength) {
  using Space = TypeParam;
  using V = Kokkos::View<double*, typename Space::memory_space>;
  const KrylovVectors<Space> ops{Space(), Communicator()};
  std::mt19937 random(5);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (long long n : {1LL, 7LL, 63LL, 64LL, 65LL, 1000LL, 100003LL}) {
    V a("a", n), b("b", n);
    auto ha = Kokkos::create_mirror_view(a);
    auto hb = Kokkos::create_mirror_view(b);
    long double exact = 0, size = 0;
    for (long long i = 0; i < n; ++i) {
      ha(i) = value(random), hb(i) = value(random);
      exact += static_cast<long double>(ha(i)) * hb(i);
      size += std::fabs(static_cast<long double>(ha(i)) * hb(i));
    }
    Kokkos::deep_copy(a, ha);
    Kokkos::deep_copy(b, hb);
    EXPECT_NEAR(ops.dot(a, b), static_cast<double>(exact), 1e-14 * static_cast<double>(size)) << n << " summands";
  }
}

// FGMRES solves a small nonsymmetric system exactly, with restarts, and
// its bases grow only as far as the iterations reach.
TYPED_TEST(SteadySolverTest, FgmresSolvesASmallSystem) {
  using Space = TypeParam;
  using V = Kokkos::View<double*, typename Space::memory_space>;
  KrylovVectors<Space> ops{Space(), Communicator()};
  const int n = 40;
  // A: tridiagonal, 3 on the diagonal, -1 below, -0.5 above.
  const auto apply = host_rows_operator<Space>(n, [n](int i, const auto& in) {
    return 3 * in(i) - (i > 0 ? in(i - 1) : 0) - 0.5 * (i + 1 < n ? in(i + 1) : 0);
  });
  const auto identity = [&](const V& in, const V& out) { ops.copy(in, out); };
  V b("b", n), x("x", n);
  Kokkos::deep_copy(b, 1.0);
  KrylovOptions options;
  options.tolerance = 1e-10;
  options.restart = 7;
  const auto result = fgmres(ops, apply, identity, b, x, options);
  EXPECT_TRUE(result.converged);
  EXPECT_GT(result.iterations, options.restart);  // it restarted
  EXPECT_EQ(result.basis_vectors, 2 * options.restart + 1);
  EXPECT_LT(relative_residual(ops, apply, b, x), 1e-9);

  // A solve that needs fewer iterations than the restart holds only the
  // bases it reached: k iterations, 2 k + 1 vectors.
  options.restart = 30;
  options.tolerance = 1e-3;
  Kokkos::deep_copy(x, 0.0);
  const auto short_solve = fgmres(ops, apply, identity, b, x, options);
  EXPECT_TRUE(short_solve.converged);
  EXPECT_LT(short_solve.iterations, options.restart);
  EXPECT_EQ(short_solve.basis_vectors, 2 * short_solve.iterations + 1);
}

// A system of condition number 1e6: a spread diagonal with a nonsymmetric coupling.
template <class Space>
auto ill_conditioned_operator(int n) {
  return host_rows_operator<Space>(n, [n](int i, const auto& in) {
    return std::pow(10.0, -6.0 * i / (n - 1)) * in(i) + 1e-8 * (i > 0 ? in(i - 1) : 0);
  });
}

// FGMRES on a system of condition number 1e6 (a spread diagonal with a
// nonsymmetric coupling) without restarts, which in exact arithmetic ends
// within n iterations: the basis must stay orthogonal for it to reach a
// true residual of 1e-10 there (classical Gram-Schmidt in one pass does
// not: the residual stays above 1e-9 after the n iterations).
TYPED_TEST(SteadySolverTest, FgmresKeepsItsBasisOrthogonalOnAnIllConditionedSystem) {
  using Space = TypeParam;
  using V = Kokkos::View<double*, typename Space::memory_space>;
  KrylovVectors<Space> ops{Space(), Communicator()};
  const int n = 80;
  const auto apply = ill_conditioned_operator<Space>(n);
  V b("b", n), x("x", n);
  Kokkos::deep_copy(b, 1.0);
  KrylovOptions options;
  options.tolerance = 1e-10;
  options.restart = n;  // no restart: n iterations span the whole space
  options.max_iterations = n;
  const auto result = fgmres(ops, apply, [&](const V& in, const V& out) { ops.copy(in, out); }, b, x, options);
  EXPECT_TRUE(result.converged);
  EXPECT_LT(relative_residual(ops, apply, b, x), 1e-9);
}

// A cycle length raised during a solve takes effect at the next cycle: on
// the system above, cycles of 8 stall for 88 iterations, where one cycle
// of 8 and then one of n (the whole space) reach 1e-10.
TYPED_TEST(SteadySolverTest, FgmresLengthensItsCyclesWhenAsked) {
  using Space = TypeParam;
  using V = Kokkos::View<double*, typename Space::memory_space>;
  KrylovVectors<Space> ops{Space(), Communicator()};
  const int n = 80;
  const auto apply = ill_conditioned_operator<Space>(n);
  const auto identity = [&](const V& in, const V& out) { ops.copy(in, out); };
  V b("b", n), x("x", n);
  Kokkos::deep_copy(b, 1.0);
  KrylovOptions options;
  options.tolerance = 1e-10;
  options.restart = 8;
  options.max_iterations = 8 + n;
  const auto short_cycles = fgmres(ops, apply, identity, b, x, options);
  EXPECT_FALSE(short_cycles.converged);
  EXPECT_GT(relative_residual(ops, apply, b, x), 1e-6);

  Kokkos::deep_copy(x, 0.0);
  int cycles = 0;
  options.cycle_length = [&] { return cycles++ == 0 ? 8 : n; };
  const auto lengthened = fgmres(ops, apply, identity, b, x, options);
  EXPECT_TRUE(lengthened.converged);
  EXPECT_GT(lengthened.iterations, 8);
  EXPECT_EQ(lengthened.basis_vectors, 2 * n + 1);
  EXPECT_LT(relative_residual(ops, apply, b, x), 1e-9);
}

// The lattice multigrid as a stationary iteration on a Dirichlet Laplacian
// around a disc (periodic lattice): the residual falls by the same factor
// per V-cycle at 32, 64 and 128 points a side: it does not grow.
// The rate of stationary cycles on a Dirichlet lattice Laplacian, after
// ten cycles from x = 0 (the rate per cycle of the last nine), for the
// right-hand side mean + sin(0.37 k) on the fluid points.
template <int Dim, class Space>
double multigrid_rate(int n, const std::vector<char>& active, double mean) {
  using V = Kokkos::View<double*, typename Space::memory_space>;
  std::array<int, Dim> shape;
  shape.fill(n);
  LatticeMultigrid<Dim, Space> multigrid(Space(), shape, active);
  const long long points = static_cast<long long>(active.size());
  V b("b", points), x("x", points), r("r", points), dx("dx", points);
  auto hb = Kokkos::create_mirror_view(b);
  for (long long k = 0; k < points; ++k) hb(k) = active[k] ? mean + std::sin(0.37 * k) : 0.0;
  Kokkos::deep_copy(b, hb);
  KrylovVectors<Space> ops{Space(), Communicator()};
  const double start = ops.norm(b);
  double norm = start;
  for (int cycle = 0; cycle < 10; ++cycle) {
    multigrid.apply(x, r);
    ops.update(1.0, b, -1.0, r);
    norm = ops.norm(r);
    multigrid.cycle(r, dx);
    ops.update(1.0, dx, 1.0, x);
  }
  return std::pow(norm / start, 1.0 / 9);
}

TYPED_TEST(SteadySolverTest, LatticeMultigridConvergesAtEverySize) {
  using Space = TypeParam;
  std::vector<double> rates;
  for (int n : {32, 64, 128}) {
    std::vector<char> active(n * n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        active[i + n * j] = std::hypot(i + 0.5 - n / 2.0, j + 0.5 - n / 2.0) > 0.3 * n;
    rates.push_back(multigrid_rate<2, Space>(n, active, 0.0));
    EXPECT_LT(rates.back(), 0.5) << n << " a side";  // 0.43, 0.42, 0.43 measured
  }
  EXPECT_LT(rates.back(), rates.front() + 0.05);
}

// Around a dozen discs, on a right-hand side with a smooth part, a V-cycle
// of piecewise-constant aggregation loses rate with every level (measured
// 0.70 at 64 a side, 0.90 at 256, 0.98 at 1,024: fails here); the cycle's W
// below the finest level, with corrections over-weighted, holds it better
// (0.62, 0.74, 0.82).
TYPED_TEST(SteadySolverTest, LatticeMultigridKeepsItsRateAcrossLevels) {
  using Space = TypeParam;
  std::vector<double> rates;
  for (int n : {64, 256, 1024}) {
    // twelve discs of radius 0.12 of the cell at random centres (the same at every n)
    std::mt19937 random(3);
    std::array<std::array<double, 2>, 12> centres;
    for (auto& c : centres) c = {random() / 4294967296.0, random() / 4294967296.0};
    std::vector<char> active(static_cast<size_t>(n) * n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        bool solid = false;
        for (const auto& c : centres) {
          double ex = std::fabs((i + 0.5) / n - c[0]), ey = std::fabs((j + 0.5) / n - c[1]);
          ex = std::min(ex, 1 - ex), ey = std::min(ey, 1 - ey);
          solid = solid || std::hypot(ex, ey) < 0.12;
        }
        active[i + static_cast<size_t>(n) * j] = !solid;
      }
    rates.push_back(multigrid_rate<2, Space>(n, active, 1.0));
  }
  EXPECT_LT(rates.back(), 0.9);
  EXPECT_LT(rates.back(), rates.front() + 0.24);
}

// A V-cycle starts from zero whatever the cycle before it left: the same
// right-hand side gives the same x to the last bit after another one.
TYPED_TEST(SteadySolverTest, LatticeMultigridCycleIsAFixedOperator) {
  using Space = TypeParam;
  using V = Kokkos::View<double*, typename Space::memory_space>;
  const int n = 16;
  std::vector<char> active(n * n);
  for (int k = 0; k < n * n; ++k) active[k] = std::hypot(k % n + 0.5 - n / 2.0, k / n + 0.5 - n / 2.0) > 4;
  LatticeMultigrid<2, Space> multigrid(Space(), {n, n}, active);
  V b("b", n * n), c("c", n * n), first("first", n * n), other("other", n * n), second("second", n * n);
  auto hb = Kokkos::create_mirror_view(b);
  auto hc = Kokkos::create_mirror_view(c);
  for (int k = 0; k < n * n; ++k) hb(k) = active[k] ? std::sin(0.37 * k) : 0.0, hc(k) = active[k] ? 1.0 : 0.0;
  Kokkos::deep_copy(b, hb);
  Kokkos::deep_copy(c, hc);
  multigrid.cycle(b, first);
  multigrid.cycle(c, other);
  multigrid.cycle(b, second);
  auto h1 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), first);
  auto h2 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), second);
  for (int k = 0; k < n * n; ++k) ASSERT_EQ(h1(k), h2(k)) << k;
}

// The wide lattice preconditioner's pattern weights (stride 2, 64 x 64
// points around a disc): on sign pattern m of the lattice times a smooth
// mode, its response grows by nearly the pattern's weight, each pattern by
// its own (the post-smoothing takes back a little: 0.87 to 0.92 of the
// weight measured, and the disc mixes the patterns slightly: pattern 0,
// weight 1, grows by 1.002; a pattern sent to the wrong sub-lattices, or a
// transform that is not normalised, fails); weights of 1 change nothing.
TYPED_TEST(SteadySolverTest, PatternWeightsScaleTheSmoothPartOfEachPattern) {
  using Space = TypeParam;
  using V = Kokkos::View<double*, typename Space::memory_space>;
  const int n = 64;
  const double dx = 1.0 / n;
  Kokkos::View<double* [2], typename Space::memory_space> x("x", n * n);
  V fluid("fluid", n * n);
  auto hx = Kokkos::create_mirror_view(x);
  auto hf = Kokkos::create_mirror_view(fluid);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      hx(i + n * j, 0) = (i + 0.5) * dx, hx(i + n * j, 1) = (j + 0.5) * dx;
      hf(i + n * j) = std::hypot(i + 0.5 - n / 2.0, j + 0.5 - n / 2.0) > 0.2 * n ? 1.0 : 0.0;
    }
  Kokkos::deep_copy(x, hx);
  Kokkos::deep_copy(fluid, hf);
  LatticePreconditioner<2, Space> wide(Space(), Communicator(), x, fluid, n * n, {n, n}, dx, 2);
  ASSERT_EQ(wide.patterns(), 4);
  KrylovVectors<Space> ops{Space(), Communicator()};
  const std::vector<double> weights{1.0, 2.0, 3.0, 5.0};
  V r("r", n * n), plain("plain", n * n), weighed("weighed", n * n);
  for (int m = 0; m < 4; ++m) {
    auto hr = Kokkos::create_mirror_view(r);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int parity = ((m >> wide.pattern_bit(0)) & 1) * i + ((m >> wide.pattern_bit(1)) & 1) * j;
        hr(i + n * j) = hf(i + n * j) * (parity % 2 ? -1.0 : 1.0) * std::cos(2 * M_PI * (i + 0.5) / n);
      }
    Kokkos::deep_copy(r, hr);
    wide.set_pattern_weights({});
    wide.apply(r, plain);
    wide.set_pattern_weights({1.0, 1.0, 1.0, 1.0});
    wide.apply(r, weighed);
    ops.update(1.0, plain, -1.0, weighed);
    EXPECT_LT(ops.norm(weighed), 1e-13 * ops.norm(plain)) << "pattern " << m;
    wide.set_pattern_weights(weights);
    wide.apply(r, weighed);
    const double growth = ops.dot(r, weighed) / ops.dot(r, plain);
    EXPECT_GT(growth, 0.8 * weights[m]) << "pattern " << m;
    EXPECT_LT(growth, 1.01 * weights[m]) << "pattern " << m;
  }
}

// On a lattice of unknowns only, a Fourier mode is multiplied by
// prod_d (1 + beta sin^2(k_d / 2)); solid points stay 0 and act as zeros.
TEST(LatticeSharpening, MultipliesEachModeByItsSymbol) {
  const std::array<int, 3> shape{8, 6, 4};
  const std::array<int, 3> wave{3, 1, 2};
  const double beta = 4.0;
  const int points = shape[0] * shape[1] * shape[2];
  std::vector<float> values(points), scratch, active(points, 1.0f);
  std::vector<double> k(3), expected(points);
  double factor = 1.0;
  for (int d = 0; d < 3; ++d) {
    k[d] = 2 * M_PI * wave[d] / shape[d];
    factor *= 1.0 + beta * std::pow(std::sin(k[d] / 2), 2);
  }
  for (int c = 0; c < points; ++c) {
    const int i = c % shape[0], j = c / shape[0] % shape[1], l = c / (shape[0] * shape[1]);
    expected[c] = std::cos(k[0] * i + k[1] * j + k[2] * l + 0.3);
    values[c] = static_cast<float>(expected[c]);
  }
  sharpen_lattice<3>(values, scratch, shape, active, beta);
  for (int c = 0; c < points; ++c) EXPECT_NEAR(values[c], factor * expected[c], 2e-5 * factor) << c;
}

TEST(LatticeSharpening, HoldsSolidAtZero) {
  // Five points along x, one along y (a factor 1 there); point 2 solid.
  std::vector<float> values{1, 1, 0, 1, 1}, scratch, active{1, 1, 0, 1, 1};
  const double beta = 2.0;
  sharpen_lattice<2>(values, scratch, {5, 1}, active, beta);
  EXPECT_EQ(values[2], 0.0f);
  EXPECT_FLOAT_EQ(values[0], 1.0f);                 // both neighbours 1: the constant is kept
  EXPECT_FLOAT_EQ(values[1], 1.0f + beta / 4);      // the solid neighbour counts as 0
  EXPECT_FLOAT_EQ(values[3], 1.0f + beta / 4);
}

// The preconditioner sharpens its cycle's result on the lattice the
// particles sit on: the same as sharpening the plain result by position.
TYPED_TEST(SteadySolverTest, PreconditionerSharpensOnTheParticlesLattice) {
  using Space = TypeParam;
  using V = Kokkos::View<double*, typename Space::memory_space>;
  const int nx = 32, ny = 24;
  const double dx = 1.0 / nx;
  Kokkos::View<double* [2], typename Space::memory_space> x("x", nx * ny);
  V fluid("fluid", nx * ny), r("r", nx * ny), plain("plain", nx * ny), sharp("sharp", nx * ny);
  auto hx = Kokkos::create_mirror_view(x);
  auto hf = Kokkos::create_mirror_view(fluid);
  auto hr = Kokkos::create_mirror_view(r);
  // The particles in an order that is not the lattice's.
  for (int p = 0; p < nx * ny; ++p) {
    const int c = (7 * p) % (nx * ny), i = c % nx, j = c / nx;
    hx(p, 0) = (i + 0.5) * dx, hx(p, 1) = (j + 0.5) * dx;
    hf(p) = std::hypot(i + 0.5 - nx / 2.0, j + 0.5 - ny / 2.0) > 5 ? 1.0 : 0.0;
    hr(p) = hf(p) * std::sin(0.7 * i + 1.3 * j);
  }
  Kokkos::deep_copy(x, hx);
  Kokkos::deep_copy(fluid, hf);
  Kokkos::deep_copy(r, hr);
  LatticePreconditioner<2, Space> wide(Space(), Communicator(), x, fluid, nx * ny, {nx, ny}, dx, 2);
  wide.apply(r, plain);
  const double beta = 2.0;
  wide.set_sharpening(beta);
  wide.apply(r, sharp);
  auto hp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), plain);
  auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sharp);
  std::vector<float> lattice(nx * ny, 0.0f), scratch, active(nx * ny, 0.0f);
  auto at = [&](int p) { return static_cast<int>(hx(p, 0) / dx) + nx * static_cast<int>(hx(p, 1) / dx); };
  for (int p = 0; p < nx * ny; ++p) {
    active[at(p)] = static_cast<float>(hf(p));
    lattice[at(p)] = static_cast<float>(hp(p));
  }
  sharpen_lattice<2>(lattice, scratch, {nx, ny}, active, beta);
  double largest = 0;
  for (int p = 0; p < nx * ny; ++p) largest = std::max(largest, std::abs(hs(p)));
  ASSERT_GT(largest, 0);
  for (int p = 0; p < nx * ny; ++p) EXPECT_NEAR(hs(p), lattice[at(p)], 1e-6 * largest) << p;
}

// The steady solve to a relative residual of kTightTolerance.
constexpr double kTightTolerance = 1e-7;
template <class Space>
SteadyReport solve_tightly(Simulation<2, Space>& sim) {
  SteadyOptions options;
  options.tolerance = kTightTolerance;
  SteadySolver<2, Space> solver(sim, Space(), options, nullptr, nullptr);
  return solver.solve();
}

// k along x of the scene marched until it changes by less than 1e-8 over 200 steps.
template <class Space>
double marched_permeability(const SceneConfig& scene) {
  Simulation<2, Space> marched(scene);
  double k = 0, previous = -1;
  while (std::abs(k - previous) > 1e-8 * std::abs(k)) {
    previous = k;
    for (int s = 0; s < 200; ++s) marched.step();
    k = scene.kinematic_viscosity * marched.superficial_velocity()[0] / scene.body_force[0];
  }
  return k;
}

// The steady solve of the disc cell is the time loop's steady state: k to
// 1e-5 of the march's (marched until k changes by less than 1e-8 over 200
// steps), with and without convection; the solve's residual is below its
// tolerance and the state's own rates are zero up to the density drift.
TYPED_TEST(SteadySolverTest, SolvesToTheMarchedState) {
  using Space = TypeParam;
  for (bool convection : {false, true}) {
    const SceneConfig scene = disc_cell(convection);
    const double k_marched = marched_permeability<Space>(scene);
    Simulation<2, Space> solved(scene);
    const auto report = solve_tightly(solved);
    EXPECT_TRUE(report.converged);
    EXPECT_LE(report.residual, kTightTolerance);
    EXPECT_GE(report.nonlinear_iterations, 1);
    EXPECT_GT(report.linear_iterations, 0);
    const double k_solved = scene.kinematic_viscosity * solved.superficial_velocity()[0] / scene.body_force[0];
    EXPECT_NEAR(k_solved / k_marched, 1.0, 1e-5) << "convection " << convection << ": solved " << k_solved
                                                 << ", marched " << k_marched;
  }
}

// Lattice neighbours are the points one step away along each axis, corners included.
TEST(FluidRegions, LatticeNeighboursIncludeCornersNotTwoSteps) {
  const double dx = 0.1;
  EXPECT_TRUE(lattice_neighbours<2>(Vec<2>{dx, 0}, dx));
  EXPECT_TRUE(lattice_neighbours<2>(Vec<2>{-dx, dx}, dx));
  EXPECT_FALSE(lattice_neighbours<2>(Vec<2>{2 * dx, 0}, dx));
  EXPECT_FALSE(lattice_neighbours<2>(Vec<2>{2 * dx, dx}, dx));
  EXPECT_TRUE(lattice_neighbours<3>(Vec<3>{dx, -dx, dx}, dx));
  EXPECT_FALSE(lattice_neighbours<3>(Vec<3>{0, 2 * dx, 0}, dx));
}

// The regions: the channel, B (a wall between does not join) and A; each
// fluid particle in the region of its place, and the sizes over all fluid
// particles those of the places.
TYPED_TEST(SteadySolverTest, FluidRegionsAreThePoresJoinedByLatticeNeighbours) {
  using Space = TypeParam;
  const SceneConfig scene = testing::pocket_cell(true);
  Simulation<2, Space> sim(scene);
  sim.compute_rates();  // the pair list
  const auto regions = find_fluid_regions(sim);
  ASSERT_EQ(regions.count(), 3);
  const auto& P = sim.particles();
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  const auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  const auto of = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), regions.of);
  auto place = [&](int i) {
    const double y = x(i, 1) / scene.particle_spacing;
    return y < 6 ? 0 : y < 12 ? 1 : 2;  // the channel, B, A
  };
  int region_of_place[3] = {-1, -1, -1};
  double particles_at_place[3] = {0, 0, 0};
  for (int i = 0; i < P.owned; ++i) {
    if (kind(i) != kFluid) {
      EXPECT_EQ(of(i), -1);
      continue;
    }
    int& expected = region_of_place[place(i)];
    if (expected < 0) expected = of(i);
    EXPECT_EQ(of(i), expected) << "at " << x(i, 0) << ", " << x(i, 1);
    particles_at_place[place(i)] += 1;
  }
  for (int p = 0; p < 3; ++p) {
    ASSERT_GE(region_of_place[p], 0) << "no fluid at place " << p;
    EXPECT_EQ(regions.sizes[region_of_place[p]], particles_at_place[p]);
  }
  EXPECT_NE(region_of_place[0], region_of_place[1]);
  EXPECT_NE(region_of_place[0], region_of_place[2]);
  EXPECT_NE(region_of_place[1], region_of_place[2]);
}

// With a pocket sealed by solid (A), the solve converges to the march's
// steady state (k to 1e-5), and every region keeps its mass: a single
// border, one drift for the whole fluid, asks a sealed pocket for the
// channel's drift, which its own continuity cannot give.
TYPED_TEST(SteadySolverTest, SealedPocketKeepsItsMassAndTheMarchsK) {
  using Space = TypeParam;
  const SceneConfig scene = testing::pocket_cell(false);
  const double k_marched = marched_permeability<Space>(scene);
  Simulation<2, Space> solved(scene);
  const auto report = solve_tightly(solved);
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(report.fluid_regions, 2);
  const double k_solved = scene.kinematic_viscosity * solved.superficial_velocity()[0] / scene.body_force[0];
  EXPECT_NEAR(k_solved / k_marched, 1.0, 1e-5) << "solved " << k_solved << ", marched " << k_marched;
  // Each region's mass, against the start's (rho0 a particle).
  const auto regions = find_fluid_regions(solved);
  const auto of = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), regions.of);
  const auto rho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solved.particles().rho);
  std::vector<double> mean(regions.count(), 0.0);
  for (int i = 0; i < solved.particles().owned; ++i)
    if (of(i) >= 0) mean[of(i)] += rho(i) / regions.sizes[of(i)];
  for (double m : mean) EXPECT_NEAR(m / scene.density, 1.0, 1e-12);
}

// LSC's scaling weighs down the velocity rows next to the disc and only
// those: a fluid particle within a spacing of the surface has both rows
// weighed by 1 / (1 + its share of wall drag), clearly below 1; one beyond
// the kernel's reach (3 h) neither; a cell without grains has no such row.
TYPED_TEST(SteadySolverTest, LscWeighsTheRowsNextToWalls) {
  using Space = TypeParam;
  using Solver = SteadySolver<2, Space>;
  SteadyOptions setup_only;
  setup_only.max_nonlinear_iterations = 0;
  const SceneConfig scene = disc_cell(false);
  Simulation<2, Space> sim(scene);
  Solver solver(sim, Space(), setup_only, nullptr, nullptr);
  solver.solve();
  SteadySystem<2, Space> system(sim, Space());
  const int n = system.owned();
  auto scaling = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver.lsc_scaling());
  auto diagonal = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), system.velocity_diagonal());
  auto fluid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), system.fluid_mask());
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sim.particles().x);
  const double dx = scene.particle_spacing, reach = 3.0 * sim.derived().smoothing_length;
  int near = 0, far = 0;
  long long weighed = 0;
  for (int i = 0; i < n; ++i) {
    if (fluid(i) == 0) continue;
    const double gap = std::hypot(x(i, 0) - 0.5, x(i, 1) - 0.5) - 0.25;
    for (int c = 0; c < 2; ++c) {
      const double weight = scaling(i * 2 + c) * diagonal(i * 2 + c);
      if (gap < dx) {
        EXPECT_GT(weight, 0.3) << "particle " << i << " component " << c;
        EXPECT_LT(weight, 0.95) << "particle " << i << " component " << c;
      }
      if (gap > reach) {
        EXPECT_NEAR(weight, 1.0, 1e-6) << "particle " << i << " component " << c;
      }
      if (weight < 1.0 / (1.0 + Solver::kDragShareFloor)) ++weighed;
    }
    near += gap < dx;
    far += gap > reach;
  }
  EXPECT_GT(near, 20);
  EXPECT_GT(far, 20);
  EXPECT_EQ(weighed, solver.wall_rows());

  SceneConfig open = disc_cell(false);
  open.grains = {};
  Simulation<2, Space> open_sim(open);
  Solver open_solver(open_sim, Space(), setup_only, nullptr, nullptr);
  open_solver.solve();
  EXPECT_EQ(open_solver.wall_rows(), 0);
  SteadySystem<2, Space> open_system(open_sim, Space());
  auto open_scaling = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), open_solver.lsc_scaling());
  auto open_diagonal = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), open_system.velocity_diagonal());
  double largest_share = 0;
  for (size_t row = 0; row < open_scaling.extent(0); ++row)
    largest_share = std::max(largest_share, std::abs(1.0 - open_scaling(row) * open_diagonal(row)));
  EXPECT_LT(largest_share, 1e-9) << "a bulk row's share of wall drag is rounding";
}

// A solve of a cell of one grain (a disc, or in 3D a sphere, of radius a
// quarter of the cell) with the inner solves asked for `inner_tolerance`,
// the outer restart `restart`, the inner cap `inner_cap` at the start and
// the DG solves preconditioned by `dg`: its report, the superficial
// velocity along x, the highest inner cap the progress line showed, and
// the first linear iteration it showed the DG solves by blocks at (0: never).
struct OneGrainSolve {
  SteadyReport report;
  double flow = 0;
  int highest_inner_cap = 0;
  long long blocks_from = 0;
  int longest_restart = 0;
};

template <int Dim, class Space>
OneGrainSolve solve_one_grain(double inner_tolerance, int restart = SteadyOptions().restart,
                              int inner_cap = SteadyOptions().max_inner_iterations,
                              DgPreconditioner dg = DgPreconditioner::Lattice) {
  SceneConfig scene = Dim == 2 ? disc_cell(true) : testing::periodic_box(3, 10);
  if (Dim == 3) {
    scene.grains = grains_from_list({0.5, 0.5, 0.5, 0.25}, 3);
    scene.body_force = {1e-3, 0, 0};
    scene.sound_speed = 0;
    scene.particle_motion = ParticleMotion::Fixed;
  }
  Simulation<Dim, Space> sim(scene);
  SteadyOptions options;
  options.inner_tolerance = inner_tolerance;
  options.restart = restart;
  options.max_inner_iterations = inner_cap;
  options.dg_preconditioner = dg;
  OneGrainSolve solve;
  auto progress = [&solve](const SteadyProgress& p) {
    solve.highest_inner_cap = std::max(solve.highest_inner_cap, p.inner_cap);
    solve.longest_restart = std::max(solve.longest_restart, p.restart);
    if (p.dg_by_blocks && solve.blocks_from == 0) solve.blocks_from = p.linear_iterations;
  };
  solve.report = SteadySolver<Dim, Space>(sim, Space(), options, nullptr, progress).solve();
  solve.flow = sim.superficial_velocity()[0];
  return solve;
}

// Solver/Inner Tolerance = 0 asks the inner solves for 0.05 in 2D and 0.01
// in 3D: the same iterations and k to the bit as that tolerance given, and
// other inner iterations than the other dimension's.
template <int Dim, class Space>
void expect_inner_tolerance_by_dimension(double expected, double other) {
  const auto by_dimension = solve_one_grain<Dim, Space>(0.0);
  const auto given = solve_one_grain<Dim, Space>(expected);
  const auto not_this = solve_one_grain<Dim, Space>(other);
  EXPECT_TRUE(by_dimension.report.converged) << Dim << "D";
  EXPECT_EQ(by_dimension.report.linear_iterations, given.report.linear_iterations) << Dim << "D";
  EXPECT_EQ(by_dimension.report.inner_iterations, given.report.inner_iterations) << Dim << "D";
  EXPECT_EQ(by_dimension.flow, given.flow) << Dim << "D";
  EXPECT_NE(by_dimension.report.inner_iterations, not_this.report.inner_iterations) << Dim << "D";
}

TYPED_TEST(SteadySolverTest, InnerToleranceZeroIsTheDimensionsDefault) {
  expect_inner_tolerance_by_dimension<2, TypeParam>(0.05, 0.01);
  expect_inner_tolerance_by_dimension<3, TypeParam>(0.01, 0.05);
}

// A Newton step taken only to settle k (the residual below the tolerance
// already) asks its inner solves for 0.01 at most, even where the
// tolerance is looser (2D's default, 0.05, or one given): a second solve
// from a converged state, whose one step settles, takes the same inner
// iterations and gives the same k to the bit with Solver/Inner Tolerance
// = 0 or 0.05 as with 0.01 (with the settling step at 0.05, 0 and 0.05
// give other counts than 0.01).
TYPED_TEST(SteadySolverTest, SettlingStepSolvesItsInnerSolvesTo001) {
  using Space = TypeParam;
  auto settle_again = [](double inner_tolerance) {
    Simulation<2, Space> sim(disc_cell(true));
    SteadySolver<2, Space>(sim, Space(), SteadyOptions(), nullptr, nullptr).solve();
    SteadyOptions options;
    options.inner_tolerance = inner_tolerance;
    const auto report = SteadySolver<2, Space>(sim, Space(), options, nullptr, nullptr).solve();
    return std::make_pair(report, sim.superficial_velocity()[0]);
  };
  const auto by_dimension = settle_again(0.0), tight = settle_again(0.01), loose = settle_again(0.05);
  EXPECT_TRUE(by_dimension.first.converged);
  EXPECT_EQ(by_dimension.first.nonlinear_iterations, 1);
  EXPECT_GT(by_dimension.first.inner_iterations, 0);
  EXPECT_EQ(by_dimension.first.inner_iterations, tight.first.inner_iterations);
  EXPECT_EQ(by_dimension.second, tight.second);
  EXPECT_EQ(loose.first.inner_iterations, tight.first.inner_iterations);
  EXPECT_EQ(loose.second, tight.second);
}

// A linear solve that does not halve its residual over a restart cycle
// tightens an inner tolerance looser than 0.01 (by 5, not below 0.01) for
// the rest of the solve; one that moves leaves it as asked.
TYPED_TEST(SteadySolverTest, StalledLinearSolveTightensTheInnerTolerance) {
  const auto moving = solve_one_grain<2, TypeParam>(0.0).report;
  EXPECT_TRUE(moving.converged);
  EXPECT_EQ(moving.inner_tolerance, 0.05);
  // Inner solves to 0.9 and a restart of 2: the first cycles do not halve.
  const auto stalled = solve_one_grain<2, TypeParam>(0.9, 2).report;
  EXPECT_TRUE(stalled.converged);
  EXPECT_LT(stalled.inner_tolerance, 0.9);
  EXPECT_GE(stalled.inner_tolerance, 0.01);
}

// A stall while most DG solves end at their cap raises the cap and leaves
// the inner tolerance as asked: the cap, not the tolerance, is what ends
// those solves. Inner solves capped at one iteration and a restart of 2:
// the cap rises, and the tolerance stays 0.05 (with both changed on such a
// stall it ended at 0.01).
TYPED_TEST(SteadySolverTest, StallWithCappedInnerSolvesRaisesTheCapNotTheTolerance) {
  const auto capped = solve_one_grain<2, TypeParam>(0.05, 2, 1);
  EXPECT_TRUE(capped.report.converged);
  EXPECT_GT(capped.highest_inner_cap, 1);
  EXPECT_EQ(capped.report.inner_tolerance, 0.05);
}

// Solver/DG Preconditioner = schwarz solves the same equations: to a
// residual of kTightTolerance it gives the lattice preconditioner's k to
// 1e-6, on the disc cell and on the cell of pockets (a region behind a
// thin wall, and one sealed that two blocks share, each whole in both
// blocks' extended points: singular there but for the blocks' shift).
TYPED_TEST(SteadySolverTest, SchwarzGivesTheSameKAsTheLattice) {
  using Space = TypeParam;
  for (const SceneConfig& scene : {disc_cell(true), testing::pocket_cell(true)}) {
    double k[2];
    for (int m = 0; m < 2; ++m) {
      Simulation<2, Space> sim(scene);
      SteadyOptions options;
      options.tolerance = kTightTolerance;
      options.dg_preconditioner = m == 0 ? DgPreconditioner::Lattice : DgPreconditioner::Schwarz;
      const auto report = SteadySolver<2, Space>(sim, Space(), options, nullptr, nullptr).solve();
      EXPECT_TRUE(report.converged) << "preconditioner " << m;
      k[m] = sim.superficial_velocity()[0];
    }
    EXPECT_NEAR(k[1] / k[0], 1.0, 1e-6) << "lattice " << k[0] << ", schwarz " << k[1];
  }
}

// Solver/DG Preconditioner = auto: where the DG solves stall at their cap
// (capped at one iteration, a restart of 2), the first stall switches them
// to local solves on blocks instead of raising the cap, and the solve
// converges to the lattice's k; where they do not stall (the defaults), it
// is the lattice's solve to the bit.
TYPED_TEST(SteadySolverTest, AutoSwitchesToBlocksWhereCappedDgSolvesStall) {
  using Space = TypeParam;
  const auto lattice = solve_one_grain<2, Space>(0.0, 2, 1, DgPreconditioner::Lattice);
  const auto automatic = solve_one_grain<2, Space>(0.0, 2, 1, DgPreconditioner::Auto);
  EXPECT_TRUE(lattice.report.converged);
  EXPECT_FALSE(lattice.report.dg_by_blocks);
  EXPECT_GT(lattice.highest_inner_cap, 1);
  EXPECT_TRUE(automatic.report.converged);
  EXPECT_TRUE(automatic.report.dg_by_blocks);
  EXPECT_GT(automatic.blocks_from, 0);
  EXPECT_LE(automatic.blocks_from, 4);  // the first cycle of 2 that stalls, looked at after 2 iterations
  EXPECT_NEAR(automatic.flow / lattice.flow, 1.0, 1e-3);
  const auto plain = solve_one_grain<2, Space>(0.0);
  const auto plain_auto = solve_one_grain<2, Space>(0.0, SteadyOptions().restart,
                                                    SteadyOptions().max_inner_iterations, DgPreconditioner::Auto);
  EXPECT_FALSE(plain_auto.report.dg_by_blocks);
  EXPECT_EQ(plain_auto.report.inner_iterations, plain.report.inner_iterations);
  EXPECT_EQ(plain_auto.flow, plain.flow);
}

// A linear solve that stalls gets longer outer cycles (x4 a stall, at most
// x16): on the cell of pockets with cycles of 2 and the inner tolerance at
// 0.01 (nothing inner left to tighten), with the lattice cycle and with the
// DG solves on blocks. k is the default solve's; solves that do not stall
// (the default cycles of 30, on both cells) keep their cycles.
TYPED_TEST(SteadySolverTest, StalledSolvesGetLongerOuterCycles) {
  using Space = TypeParam;
  struct Solve {
    SteadyReport report;
    double flow = 0;
    int longest_restart = 0;
  };
  auto solve = [](const SceneConfig& scene, int restart, double inner_tolerance, DgPreconditioner dg) {
    Simulation<2, Space> sim(scene);
    SteadyOptions options;
    options.restart = restart;
    options.inner_tolerance = inner_tolerance;
    options.dg_preconditioner = dg;
    Solve s;
    auto progress = [&s](const SteadyProgress& p) { s.longest_restart = std::max(s.longest_restart, p.restart); };
    s.report = SteadySolver<2, Space>(sim, Space(), options, nullptr, progress).solve();
    s.flow = sim.superficial_velocity()[0];
    return s;
  };
  const int restart = SteadyOptions().restart;
  for (const SceneConfig& scene : {disc_cell(true), testing::pocket_cell(true)}) {
    const auto plain = solve(scene, restart, 0.0, DgPreconditioner::Lattice);
    EXPECT_TRUE(plain.report.converged);
    EXPECT_EQ(plain.report.restart, restart);
    EXPECT_EQ(plain.longest_restart, restart);
  }
  const SceneConfig pockets = testing::pocket_cell(true);
  const auto plain = solve(pockets, restart, 0.0, DgPreconditioner::Lattice);
  for (const auto dg : {DgPreconditioner::Lattice, DgPreconditioner::Schwarz}) {
    const auto stalled = solve(pockets, 2, 0.01, dg);
    EXPECT_TRUE(stalled.report.converged);
    EXPECT_GE(stalled.longest_restart, 8);
    EXPECT_LE(stalled.longest_restart, 32);
    EXPECT_EQ(stalled.report.restart, stalled.longest_restart);
    EXPECT_NEAR(stalled.flow / plain.flow, 1.0, 1e-4);
  }
}

// A solve held to two linear iterations does not converge, and says so.
TYPED_TEST(SteadySolverTest, CappedSolveIsNotConverged) {
  using Space = TypeParam;
  Simulation<2, Space> sim(disc_cell(true));
  SteadyOptions options;
  options.max_linear_iterations = 2;
  options.max_nonlinear_iterations = 1;
  SteadySolver<2, Space> solver(sim, Space(), options, nullptr, nullptr);
  const auto report = solver.solve();
  EXPECT_FALSE(report.converged);
  EXPECT_EQ(report.linear_iterations, 2);
  EXPECT_GT(report.residual, options.tolerance);
  EXPECT_TRUE(std::isfinite(report.residual));
}

// A stop asked for during the solve abandons it at once, state kept: the
// stop is asked after every inner iteration too, so the third asking comes
// in the first outer iteration's first inner solve (its third iteration),
// and the solve ends with that outer iteration (it ended after the third
// outer iteration when only outer iterations asked).
TYPED_TEST(SteadySolverTest, StopAbandonsTheSolve) {
  using Space = TypeParam;
  Simulation<2, Space> sim(disc_cell(true));
  int asked = 0;
  SteadySolver<2, Space> solver(sim, Space(), SteadyOptions(), [&]() { return ++asked >= 3; }, nullptr);
  const auto report = solver.solve();
  EXPECT_TRUE(report.interrupted);
  EXPECT_FALSE(report.converged);
  EXPECT_EQ(report.linear_iterations, 1);
  EXPECT_GE(report.inner_iterations, 3);
  EXPECT_LE(report.inner_iterations, 5);
}


// lu_solve undoes LAPACK's getrf with its row interchanges.
TEST(SchwarzPreconditioner, LuSolveUndoesGetrf) {
  const int n = 4;
  // Column-major; a zero leading entry forces a pivot.
  std::vector<double> a{0, 2, 1, 3, 1, 0, 4, 1, 5, 1, 0, 2, 1, 3, 2, 0}, lu = a;
  std::vector<int> pivots(n);
  int info = 0;
  Teuchos::LAPACK<int, double>().GETRF(n, n, lu.data(), n, pivots.data(), &info);
  ASSERT_EQ(info, 0);
  const std::vector<double> x{1.0, -2.0, 0.5, 3.0};
  std::vector<double> w(n, 0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) w[i] += a[i + j * n] * x[j];
  lu_solve(n, lu.data(), pivots.data(), w.data());
  for (int i = 0; i < n; ++i) EXPECT_NEAR(w[i], x[i], 1e-13) << i;
}

// Two coordinates of one residue modulo colour_modulus(n, least) are at
// least `least` apart on the periodic axis of n points.
TEST(SchwarzPreconditioner, ColourModulusKeepsOneResidueApartAcrossTheWrap) {
  for (int least : {3, 13, 27})
    for (int n = 1; n <= 120; ++n) {
      const int m = colour_modulus(n, least);
      ASSERT_GE(m, std::min(n, least));
      ASSERT_LE(m, n);
      for (int a = 0; a < n; ++a)
        for (int b = a + m; b < n; b += m) EXPECT_GE(std::min(b - a, n - (b - a)), least) << n << " " << m;
    }
  EXPECT_EQ(colour_modulus(81, 27), 27);
  EXPECT_EQ(colour_modulus(100, 27), 34);
}

// An operator on the fluid points of a periodic 2D lattice (a solid disc
// cut out), coupling points up to 2 apart along each axis, not symmetric;
// `within`: couple only points of the same block of `block` points a side.
template <class Space>
struct LatticeStencil {
  using V = Kokkos::View<double*, typename Space::memory_space>;
  int nx, ny, block;
  bool within;
  std::vector<double> fluid;
  double coupling(int i, int j, int di, int dj) const {
    const int k = (i + di + nx) % nx + nx * ((j + dj + ny) % ny);
    if (fluid[k] == 0) return 0;
    if (within && ((i + di + nx) % nx / block != i / block || (j + dj + ny) % ny / block != j / block)) return 0;
    return -(1.0 + 0.3 * di + 0.1 * dj * dj) / (1 + std::abs(di) + std::abs(dj));
  }
  void operator()(const V& in, const V& out) const {
    auto hin = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), in);
    auto hout = Kokkos::create_mirror_view(out);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int k = i + nx * j;
        hout(k) = 0;
        if (fluid[k] == 0) continue;
        double sum = 12.0 * hin(k);
        for (int dj = -2; dj <= 2; ++dj)
          for (int di = -2; di <= 2; ++di)
            if (di || dj) sum += coupling(i, j, di, dj) * hin((i + di + nx) % nx + nx * ((j + dj + ny) % ny));
        hout(k) = sum;
      }
    Kokkos::deep_copy(out, hout);
  }
};

// With one block holding the whole lattice, or blocks the operator does
// not couple, the local solves are the operator's inverse: the probing
// found every entry (none unmatched) and put it where it belongs. And the
// coarse level, P^T A P over the blocks' connected parts, is exact on the
// vectors constant on each part.
TYPED_TEST(SteadySolverTest, SchwarzIsTheInverseWhereItsBlocksHoldTheOperator) {
  using Space = TypeParam;
  using V = Kokkos::View<double*, typename Space::memory_space>;
  const int nx = 24, ny = 20;
  const double dx = 1.0 / nx;
  Kokkos::View<double* [2], typename Space::memory_space> x("x", nx * ny);
  V fluid("fluid", nx * ny);
  auto hx = Kokkos::create_mirror_view(x);
  auto hf = Kokkos::create_mirror_view(fluid);
  LatticeStencil<Space> stencil{nx, ny, 4, false, std::vector<double>(nx * ny)};
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int k = i + nx * j;
      hx(k, 0) = (i + 0.5) * dx, hx(k, 1) = (j + 0.5) * dx;
      hf(k) = stencil.fluid[k] = std::hypot(i + 0.5 - 12, j + 0.5 - 10) > 4.5 ? 1.0 : 0.0;
    }
  Kokkos::deep_copy(x, hx);
  Kokkos::deep_copy(fluid, hf);
  const V p = random_vector<Space>(nx * ny, 5, fluid, 1);
  V r("r", nx * ny), z("z", nx * ny);
  KrylovVectors<Space> ops{Space(), Communicator()};
  for (bool within : {false, true}) {
    stencil.within = within;
    const int block = within ? 4 : 32;
    SchwarzPreconditioner<2, Space> schwarz(Space(), Communicator(), x, fluid, nx * ny, {nx, ny}, dx, block, 0, 2,
                                            0.0, stencil);
    EXPECT_EQ(schwarz.unmatched(), 0);
    EXPECT_EQ(schwarz.blocks(), within ? 28 : 1);  // of 6 x 5, two inside the disc
    stencil(p, r);
    schwarz.apply(r, z);
    ops.update(1.0, p, -1.0, z);
    EXPECT_LT(ops.norm(z), 1e-12 * ops.norm(p)) << (within ? "blocks of 4" : "one block");
    // The coarse level alone inverts A on the vectors constant on each
    // aggregate: P^T A P was summed from the probes.
    ASSERT_TRUE(schwarz.two_level());
    EXPECT_EQ(schwarz.aggregates(), within ? 28 : 1);
    auto hp = Kokkos::create_mirror_view(z);
    for (int k = 0, f = 0; k < nx * ny; ++k) hp(k) = hf(k) ? 1.0 + 0.37 * schwarz.aggregate()[f++] : 0.0;
    Kokkos::deep_copy(z, hp);
    stencil(z, r);
    V coarse("coarse", nx * ny);
    schwarz.solve_coarse(r, coarse);
    ops.update(1.0, z, -1.0, coarse);
    EXPECT_LT(ops.norm(coarse), 1e-12 * ops.norm(z)) << (within ? "blocks of 4" : "one block");
  }
}

}  // namespace
}  // namespace poresph
