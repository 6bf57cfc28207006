// The shipped channel scenes (input/poiseuille.xml, input/couette.xml), run
// as a user runs them, against the start-up series solutions: every sample
// time and the steady state within 1 % of v_max.
#include <gtest/gtest.h>

#include "RunInput.hpp"

namespace poresph {
namespace {

using testing::run_input;

void expect_series_agreement(const RunReport& report) {
  ASSERT_TRUE(report.channel);
  // The three start-up times of Morris et al. (1997) and the end (steady state, t = 10 L^2/(pi^2 nu)).
  ASSERT_EQ(report.profile_samples.size(), 4u);
  const double expected_times[] = {0.0225, 0.045, 0.1125, 1.0};
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(report.profile_samples[k].time, expected_times[k], 1e-9);
    EXPECT_LT(report.profile_samples[k].error, 0.01) << "t = " << report.profile_samples[k].time;
    EXPECT_GT(report.profile_samples[k].error, 0.0);
  }
  EXPECT_LT(report.max_density_variation, 0.01);
  EXPECT_EQ(report.fluid_particles, 40 * 20);
}

TEST(ChannelFlow, PoiseuilleStartUpMatchesTheSeries) { expect_series_agreement(run_input("poiseuille.xml")); }
TEST(ChannelFlow, CouetteStartUpMatchesTheSeries) { expect_series_agreement(run_input("couette.xml")); }

}  // namespace
}  // namespace poresph
