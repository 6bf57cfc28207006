// The smallest physics pieces against hand values: one pair's terms,
// no-slip distances, the sound-speed and time-step rules, the series solutions.
#include <gtest/gtest.h>

#include <cmath>

#include "diagnostics/ChannelFlow.hpp"
#include "physics/NoSlip.hpp"
#include "physics/PairTerms.hpp"
#include "physics/TimeStep.hpp"

namespace poresph {
namespace {

TEST(PairTerms, ContinuityRateByHand) {
  // m_b F (v_ab . r_ab) = 2 * (-3) * (1*0.5 + (-2)*0.25) = 0 ; and a non-zero case
  EXPECT_DOUBLE_EQ(continuity_rate<2>(2.0, Vec<2>{{1.0, -2.0}}, Vec<2>{{0.5, 0.25}}, -3.0), 0.0);
  EXPECT_DOUBLE_EQ(continuity_rate<2>(2.0, Vec<2>{{1.0, 2.0}}, Vec<2>{{0.5, 0.25}}, -3.0), -6.0);
}

TEST(PairTerms, PressureAccelerationByHand) {
  // -m_b (p_a/rho_a^2 + p_b/rho_b^2) F r_ab = -2 (8/4 + 9/9) (-0.5) r = 3 r
  EXPECT_DOUBLE_EQ(pressure_term(8.0, 2.0), 2.0);
  const auto a = pressure_acceleration<2>(2.0, pressure_term(8.0, 2.0), pressure_term(9.0, 3.0), Vec<2>{{1.0, -2.0}}, -0.5);
  EXPECT_DOUBLE_EQ(a[0], 3.0);
  EXPECT_DOUBLE_EQ(a[1], -6.0);
}

TEST(PairTerms, ViscousAccelerationByHand) {
  // m_b nu (rho_a + rho_b)/(rho_a rho_b) F v_ab = 2 * 0.1 * 5/6 * (-0.5) v, rho_a = 2, rho_b = 3
  const auto a = viscous_acceleration<2>(2.0, 0.1, 1.0 / 2.0, 1.0 / 3.0, Vec<2>{{6.0, 0.0}}, -0.5);
  EXPECT_NEAR(a[0], -0.5, 1e-15);
  EXPECT_EQ(a[1], 0.0);
}

TEST(PairTerms, PairForcesAreAntisymmetric) {
  // m_a * (force on a from b) = -m_b * (force on b from a), to the last bit up to one rounding.
  const double m_a = 1.3, m_b = 0.7, rho_a = 1.01, rho_b = 0.98, p_a = 2.0, p_b = 2.5, F = -0.37;
  const Vec<3> r_ab{{0.3, -0.1, 0.2}}, r_ba{{-0.3, 0.1, -0.2}};
  const Vec<3> v_ab{{0.01, 0.02, -0.03}}, v_ba{{-0.01, -0.02, 0.03}};
  const double P_a = pressure_term(p_a, rho_a), P_b = pressure_term(p_b, rho_b);
  const auto f_ab = pressure_acceleration<3>(m_b, P_a, P_b, r_ab, F) +
                    viscous_acceleration<3>(m_b, 0.01, 1 / rho_a, 1 / rho_b, v_ab, F);
  const auto f_ba = pressure_acceleration<3>(m_a, P_b, P_a, r_ba, F) +
                    viscous_acceleration<3>(m_a, 0.01, 1 / rho_b, 1 / rho_a, v_ba, F);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(m_a * f_ab[d], -m_b * f_ba[d], 1e-15);
}

// The per-unit-mass weights the pair loop forms once per pair, by hand, and
// the per-end functions as those weights times the neighbour's mass.
TEST(PairTerms, WeightsByHand) {
  const Vec<2> v{{1.0, 2.0}}, r{{0.5, 0.25}};
  EXPECT_DOUBLE_EQ(continuity_weight<2>(v, r, -3.0), -3.0);  // -3 (0.5 + 0.5)
  EXPECT_EQ(continuity_rate<2>(2.0, v, r, -3.0), 2.0 * continuity_weight<2>(v, r, -3.0));
  EXPECT_DOUBLE_EQ(pressure_weight(2.0, 1.0, -0.5), 1.5);  // -(2 + 1)(-0.5)
  const auto p = pressure_acceleration<2>(2.0, 2.0, 1.0, r, -0.5);
  for (int d = 0; d < 2; ++d) EXPECT_EQ(p[d], (2.0 * pressure_weight(2.0, 1.0, -0.5)) * r[d]);
  EXPECT_DOUBLE_EQ(viscous_weight(0.1, 0.5, 0.25, -2.0), -0.15);  // 0.1 (0.5 + 0.25)(-2)
  const auto visc = viscous_acceleration<2>(3.0, 0.1, 0.5, 0.25, v, -2.0);
  for (int d = 0; d < 2; ++d) EXPECT_EQ(visc[d], (3.0 * viscous_weight(0.1, 0.5, 0.25, -2.0)) * v[d]);
  // Two fluids: nu_a = 0.1, nu_b = 0.3, 1/rho_a = 0.5, 1/rho_b = 0.25, F = -2.
  // 4 nu_a nu_b / (rho_a nu_a + rho_b nu_b) F = 0.12 / (0.2 + 1.2) (-2)
  EXPECT_DOUBLE_EQ(harmonic_phase_viscous_weight(0.1, 0.3, 0.5, 0.25, -2.0), -0.24 / 1.4);
  // Of one fluid it is the one-fluid weight.
  EXPECT_DOUBLE_EQ(harmonic_phase_viscous_weight(0.1, 0.1, 0.5, 0.5, -2.0), viscous_weight(0.1, 0.5, 0.5, -2.0));
  EXPECT_DOUBLE_EQ(harmonic_phase_viscous_weight(0.3, 0.1, 0.25, 0.5, -2.0),
                   harmonic_phase_viscous_weight(0.1, 0.3, 0.5, 0.25, -2.0));  // the same from either end
  EXPECT_DOUBLE_EQ(convective_weight<2>(0.5, v, r, 4.0), 2.0);  // 0.5 * 4 * (0.5 + 0.5)
  const auto conv = convective_acceleration<2>(0.5, v, Vec<2>{{3.0, -1.0}}, r, 4.0);
  EXPECT_DOUBLE_EQ(conv[0], 6.0);
  EXPECT_DOUBLE_EQ(conv[1], -2.0);
  EXPECT_DOUBLE_EQ(volume_gradient_weight(0.5, -4.0), -2.0);
}

TEST(PairTerms, SurfaceTensionSharesByHand) {
  // V_b (c_b - c_a) F r_ab = 0.5 * (1 - 0.25) * (-2) * (1, -3) = (-0.75, 2.25)
  const auto n = colour_gradient_share<2>(0.5, 0.25, 1.0, Vec<2>{{1.0, -3.0}}, -2.0);
  EXPECT_DOUBLE_EQ(n[0], -0.75);
  EXPECT_DOUBLE_EQ(n[1], 2.25);
  // The same colour on both ends: nothing.
  EXPECT_EQ(colour_gradient_share<2>(0.5, 1.0, 1.0, Vec<2>{{1.0, -3.0}}, -2.0)[0], 0.0);
  // V_b F (nhat_b - nhat_a) . r_ab = 0.5 * (-2) * ((0, 1) - (1, 0)) . (2, 1) = -1 * (-2 + 1) = 1
  EXPECT_DOUBLE_EQ(normal_divergence_share<2>(0.5, Vec<2>{{1.0, 0.0}}, Vec<2>{{0.0, 1.0}}, Vec<2>{{2.0, 1.0}}, -2.0),
                   1.0);
  EXPECT_DOUBLE_EQ(curvature_from_sums(-0.3, 0.6), 0.5);
  // sigma kappa n / rho = 0.07 * 50 / 1000 * (2, -1)
  const auto a = surface_tension_acceleration<2>(0.07, 50.0, Vec<2>{{2.0, -1.0}}, 1000.0);
  EXPECT_DOUBLE_EQ(a[0], 0.007);
  EXPECT_DOUBLE_EQ(a[1], -0.0035);
}

TEST(PairTerms, EquationOfStateIsLinear) { EXPECT_DOUBLE_EQ(pressure_from_density(1000.0, 4.0), 4000.0); }

TEST(NoSlip, PlaneWallDistances) {
  // Wall y = 0, normal +y. Fluid a at y = 0.3, boundary B at y = -1.5 (depth 1.5).
  const Vec<2> r_aB{{0.7, 1.8}};
  const auto s = surface_distances<2>(kWallBoundary, Vec<2>{{0.0, 1.0}}, 1.5, r_aB);
  EXPECT_DOUBLE_EQ(s.fluid, 0.3);
  EXPECT_DOUBLE_EQ(s.boundary, 1.5);
  EXPECT_DOUBLE_EQ(no_slip_factor(s, 0.1), 1.0 + 1.5 / 0.3);
  EXPECT_DOUBLE_EQ(no_slip_factor(s, 0.5), 1.0 + 1.5 / 0.5);  // d_a bounded below
}

TEST(NoSlip, GrainDistancesUseTheTangentAtTheFootOfTheNormal) {
  // Grain centre (0,0), radius 1. Fluid a at (0, 1.2): d_a = 0.2, tangent plane y = 1.
  // B at (0.6, 0.5): offset from centre (0.6, 0.5), d_B = 1 - 0.5 = 0.5.
  const Vec<2> x_a{{0.0, 1.2}}, x_B{{0.6, 0.5}};
  const auto s = surface_distances<2>(kGrainBoundary, x_B, 1.0, x_a - x_B);
  EXPECT_NEAR(s.fluid, 0.2, 1e-15);
  EXPECT_NEAR(s.boundary, 0.5, 1e-15);
  EXPECT_NEAR(s.normal[1], 1.0, 1e-15);
}

TEST(NoSlip, GrainDistancesDoNotDependOnWhichImageOfTheGrainBIsIn) {
  // The same pair seen across a periodic boundary: r_aB and B's offset are image independent.
  const Vec<2> offset{{-0.3, 0.8}}, r_aB{{0.25, 0.4}};
  const auto s1 = surface_distances<2>(kGrainBoundary, offset, 0.9, r_aB);
  const auto s2 = surface_distances<2>(kGrainBoundary, offset, 0.9, r_aB);
  EXPECT_EQ(s1.fluid, s2.fluid);
  const Vec<2> from_centre = r_aB + offset;
  EXPECT_NEAR(s1.fluid, std::sqrt(dot(from_centre, from_centre)) - 0.9, 1e-15);
}

// A sampled surface (an image) with the fluid particle's own distance and
// normal: on a circle, the grain's distances exactly; where a's nearest
// surface faces the other way (across a throat) or a knows no distance,
// B's own tangent plane.
TEST(NoSlip, SampledSurfaceUsesTheFluidParticlesOwnFoot) {
  // The grain of the test above: centre (0,0), radius 1, a at (0, 1.2), B at (0.6, 0.5).
  const Vec<2> x_a{{0.0, 1.2}}, x_B{{0.6, 0.5}};
  const double b_depth = 1.0 - std::sqrt(0.61);
  const Vec<2> b_normal = (1.0 / std::sqrt(0.61)) * x_B;
  const Vec<2> a_normal{{0.0, 1.0}};
  const auto grain = surface_distances<2>(kGrainBoundary, x_B, 1.0, x_a - x_B);
  const auto sampled = surface_distances<2>(kSampledBoundary, b_normal, b_depth, x_a - x_B, a_normal, 0.2);
  EXPECT_NEAR(sampled.fluid, grain.fluid, 1e-15);
  EXPECT_NEAR(sampled.boundary, grain.boundary, 1e-15);
  EXPECT_NEAR(sampled.normal[1], 1.0, 1e-15);
  // Without a's distance: B's tangent plane, which puts a nearer the surface than it is.
  const auto plane = surface_distances<2>(kSampledBoundary, b_normal, b_depth, x_a - x_B);
  EXPECT_NEAR(plane.boundary, b_depth, 1e-15);
  EXPECT_NEAR(plane.fluid, dot(b_normal, x_a - x_B) - b_depth, 1e-15);
  EXPECT_LT(plane.fluid, grain.fluid);
  // a's nearest surface the other side of a throat (its normal opposes B's): B's plane.
  const auto across = surface_distances<2>(kSampledBoundary, b_normal, b_depth, x_a - x_B, -1.0 * a_normal, 0.2);
  EXPECT_NEAR(across.fluid, plane.fluid, 1e-15);
}

TEST(TimeStep, SoundSpeedRuleTakesTheLargestScale) {
  // Morris et al. (1997) Poiseuille: V = 2.5e-5, L = 1e-3, nu = 1e-6, F = 2e-4, delta = 0.01.
  const double c_sq = sound_speed_squared_from_scales(2.5e-5, 1e-3, 2e-4, 1e-6, 0.01);
  EXPECT_NEAR(c_sq, 2e-5, 1e-20);  // a L / delta dominates V^2/delta = 6.25e-8 and nu V/(delta L) = 2.5e-6
  EXPECT_DOUBLE_EQ(sound_speed_squared_from_scales(10.0, 1.0, 0.0, 0.0, 0.01), 1e4);
}

TEST(TimeStep, LimitsByHand) {
  const auto limits = time_step_limits(2.0, 4.0, 0.5, 8.0);
  EXPECT_DOUBLE_EQ(limits.acoustic, 0.125);
  EXPECT_DOUBLE_EQ(limits.viscous, 1.0);
  EXPECT_DOUBLE_EQ(limits.force, 0.125);
  EXPECT_DOUBLE_EQ(limits.smallest(), 0.125);
  EXPECT_TRUE(std::isinf(time_step_limits(1.0, 1.0, 0.0, 0.0).viscous));
}

TEST(ChannelFlow, SeriesStartAtRestAndReachTheSteadyProfile) {
  const ChannelFlow poiseuille{1e-3, 1e-6, 2e-4, 0.0, 0.0};
  EXPECT_NEAR(poiseuille.velocity(0.5e-3, 1e-9), 0.0, 1e-9);
  EXPECT_NEAR(poiseuille.velocity(0.5e-3, 100.0), 2.5e-5, 1e-15);
  EXPECT_DOUBLE_EQ(poiseuille.steady_peak(), 2.5e-5);
  const ChannelFlow couette{1e-3, 1e-6, 0.0, 0.0, 2.5e-5};
  EXPECT_NEAR(couette.velocity(0.25e-3, 100.0), 0.25 * 2.5e-5, 1e-15);
  EXPECT_NEAR(couette.velocity(0.25e-3, 1e-6), 0.0, 1e-9);
  const ChannelFlow lower{1e-3, 1e-6, 0.0, 2.5e-5, 0.0};  // the mirror image
  EXPECT_NEAR(lower.velocity(0.25e-3, 0.03), couette.velocity(0.75e-3, 0.03), 1e-15);
}

}  // namespace
}  // namespace poresph
