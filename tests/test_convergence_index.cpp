// The grid convergence index arithmetic (diagnostics/ConvergenceIndex.hpp)
// against values worked out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "diagnostics/ConvergenceIndex.hpp"

namespace poresph {
namespace {

TEST(ConvergenceIndex, SecondOrderSequenceByHand) {
  // phi = 1 + h^2 at h = 0.04, 0.02, 0.01: 1.0016, 1.0004, 1.0001. e21 = 3e-4,
  // e32 = 1.2e-3, p = ln 4 / ln 2 = 2, phi_ext = (4 phi1 - phi2) / 3 = 1,
  // GCI = 1.25 (3e-4 / 1.0001) / 3.
  const auto e = convergence_estimate({0.04, 0.02, 0.01}, {1.0016, 1.0004, 1.0001});
  EXPECT_TRUE(e.asymptotic) << e.problem;
  EXPECT_NEAR(e.order, 2.0, 1e-9);
  EXPECT_NEAR(e.extrapolated, 1.0, 1e-12);
  EXPECT_NEAR(e.uncertainty, 1.25 * (3e-4 / 1.0001) / 3, 1e-12);
}

TEST(ConvergenceIndex, UnequalRatiosRecoverThePowerLaw) {
  // phi = 3 - 0.5 h^1.5 at h = 3, 2, 1.2 (r32 = 1.5, r21 = 1.667): the q(p)
  // term of the iteration matters, and the limit 3 is recovered exactly.
  auto phi = [](double h) { return 3 - 0.5 * std::pow(h, 1.5); };
  const auto e = convergence_estimate({3, 2, 1.2}, {phi(3), phi(2), phi(1.2)});
  EXPECT_TRUE(e.asymptotic) << e.problem;
  EXPECT_NEAR(e.order, 1.5, 1e-9);
  EXPECT_NEAR(e.extrapolated, 3.0, 1e-9);
  // Order 1.5, not within 10 % of the formal 2: the factor of safety 3, at the observed order.
  const double rp = std::pow(2 / 1.2, 1.5);
  EXPECT_NEAR(e.uncertainty, 3 * std::abs((phi(2) - phi(1.2)) / phi(1.2)) / (rp - 1), 1e-12);
}

TEST(ConvergenceIndex, AnOrderAboveTheFormalOneWidensTheBand) {
  // phi = 1 + h^3.3: the levels' own order is 3.3, the method's 2. The
  // Richardson value at 3.3 is the limit, but the band takes the factor 3
  // at order 2: at 1.25 and 3.3 it was 5.4 times narrower, and on a
  // hexagonal array of discs the true k lay 4.8 band widths away.
  auto phi = [](double h) { return 1 + std::pow(h, 3.3); };
  const auto e = convergence_estimate({0.45, 0.3, 0.2}, {phi(0.45), phi(0.3), phi(0.2)});
  EXPECT_TRUE(e.asymptotic) << e.problem;
  EXPECT_NEAR(e.order, 3.3, 1e-9);
  EXPECT_NEAR(e.extrapolated, 1.0, 1e-9);
  const double change = (phi(0.3) - phi(0.2)) / phi(0.2);
  EXPECT_NEAR(e.uncertainty, 3 * change / (1.5 * 1.5 - 1), 1e-12);
  EXPECT_GT(e.uncertainty, 5 * 1.25 * change / (std::pow(1.5, 3.3) - 1));
}

TEST(ConvergenceIndex, AnOrderNearTheFormalOneKeepsTheFactorOneQuarter) {
  // phi = 1 + h^2.15, within 10 % of order 2: Fs = 1.25 at the formal order.
  auto phi = [](double h) { return 1 + std::pow(h, 2.15); };
  const auto e = convergence_estimate({0.4, 0.2, 0.1}, {phi(0.4), phi(0.2), phi(0.1)});
  EXPECT_TRUE(e.asymptotic) << e.problem;
  EXPECT_NEAR(e.order, 2.15, 1e-9);
  EXPECT_NEAR(e.uncertainty, 1.25 * ((phi(0.2) - phi(0.1)) / phi(0.1)) / 3, 1e-12);
}

TEST(ConvergenceIndex, OscillationFallsBackToRoachesRule) {
  // 1.00, 1.02, 0.99 from coarse to fine: the changes +0.02 and -0.03 differ
  // in sign. Band: 3 max(0.03, 0.02) / 0.99 / (2^2 - 1); estimate: the finest.
  const auto e = convergence_estimate({0.04, 0.02, 0.01}, {1.00, 1.02, 0.99});
  EXPECT_FALSE(e.asymptotic);
  EXPECT_NE(e.problem.find("oscillate"), std::string::npos) << e.problem;
  EXPECT_EQ(e.extrapolated, 0.99);
  EXPECT_NEAR(e.uncertainty, 3 * 0.03 / 0.99 / 3, 1e-12);
}

TEST(ConvergenceIndex, AnOrderOutOfRangeIsNotTrusted) {
  // phi = 1 + h^6: observed order 6, beyond what the method can have.
  auto phi = [](double h) { return 1 + std::pow(h, 6); };
  const auto e = convergence_estimate({0.8, 0.4, 0.2}, {phi(0.8), phi(0.4), phi(0.2)});
  EXPECT_FALSE(e.asymptotic);
  EXPECT_NEAR(e.order, 6.0, 1e-9);
  EXPECT_NE(e.problem.find("outside"), std::string::npos) << e.problem;
  EXPECT_EQ(e.extrapolated, phi(0.2));
  const double largest_change = phi(0.8) - phi(0.4);
  EXPECT_NEAR(e.uncertainty, 3 * largest_change / phi(0.2) / 3, 1e-12);
}

TEST(ConvergenceIndex, TwoLevelsAssumeSecondOrderWithAFactorOfThree) {
  const auto e = convergence_estimate({0.02, 0.01}, {1.0004, 1.0001});
  EXPECT_FALSE(e.asymptotic);
  EXPECT_TRUE(std::isnan(e.order));
  EXPECT_NEAR(e.extrapolated, 1.0, 1e-12);
  EXPECT_NEAR(e.uncertainty, 3 * (3e-4 / 1.0001) / 3, 1e-12);
  EXPECT_NE(e.problem.find("two levels"), std::string::npos);
}

TEST(ConvergenceIndex, OneLevelGivesNoEstimate) {
  const auto e = convergence_estimate({0.01}, {1.0});
  EXPECT_TRUE(std::isnan(e.uncertainty));
  EXPECT_FALSE(e.asymptotic);
}

}  // namespace
}  // namespace poresph
