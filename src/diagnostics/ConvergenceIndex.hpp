#pragma once
// The grid convergence index (Roache 1994; the procedure of Celik et al.,
// J. Fluids Eng. 130, 2008, as adopted by ASME V&V 20): from a quantity
// computed at three spacings h1 < h2 < h3, the observed order of
// convergence p, the Richardson-extrapolated value and a relative
// uncertainty band of the finest value, GCI = Fs e21 / (r21^p - 1). The
// factor of safety and the order in the band follow Oberkampf & Roy
// (Verification and Validation in Scientific Computing, 2010, sec. 8.7):
// Fs = 1.25 at the formal order (2) where the observed order lies within
// 10 % of it; elsewhere Fs = 3 at the observed order, but not above the
// formal one. An observed order above the formal one is the levels' errors
// cancelling before the asymptotic range, and 1.25 at it gave bands that
// missed the true k by up to 4.8 times their width (a hexagonal array at
// p = 3.3, body-centred and simple cubic arrays at p = 3.9). Where the
// differences change sign (oscillatory convergence) or p leaves
// [kMinOrder, kMaxOrder], the levels are not in the asymptotic range: the
// result says so and falls back to Roache's rule, the formal order with
// Fs = 3, applied to the larger of the last two changes, and the finest
// value as the estimate. With two spacings the order cannot be observed:
// the same rule, applied to the one change there is.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace poresph {

struct ConvergenceEstimate {
  double extrapolated = NAN;  // the Richardson value (the finest value where not asymptotic)
  double order = NAN;         // observed (NaN with two spacings or where not asymptotic)
  double uncertainty = NAN;   // relative, of the finest value
  bool asymptotic = false;    // three spacings, monotone, order within range
  std::string problem;        // why not, for the warning; empty if asymptotic
};

// Sane range of an observed order for a method of formal order 1 to 2.
constexpr double kMinOrder = 0.5, kMaxOrder = 4.0;
constexpr double kAssumedOrder = 2.0;  // the formal order: with two spacings, and the band's most
constexpr double kSafetyFactor = 1.25, kSafetyFactorFallback = 3.0;
// How near the formal order an observed one must be for the factor 1.25.
constexpr double kNearFormalOrder = 0.1;

// The observed order from three values (Celik et al. 2008, eqs. 3-5): the
// fixed point of p = |ln|e32 / e21| + q(p)| / ln r21, q(p) = ln((r21^p - s) /
// (r32^p - s)), s = sign(e32 / e21). Needs e21 != 0 and e32 != 0.
inline double observed_order(double r21, double r32, double e21, double e32) {
  const double s = e32 / e21 > 0 ? 1.0 : -1.0;
  const double ratio = std::abs(e32 / e21);
  double p = std::abs(std::log(ratio)) / std::log(r21);
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double q = std::log((std::pow(r21, p) - s) / (std::pow(r32, p) - s));
    const double next = std::abs(std::log(ratio) + q) / std::log(r21);
    if (!std::isfinite(next)) return NAN;
    if (std::abs(next - p) < 1e-12 * std::max(1.0, p)) return next;
    p = next;
  }
  return p;
}

// spacings and values from the coarsest to the finest (2 or 3 of them; with
// more, the finest three are used).
inline ConvergenceEstimate convergence_estimate(std::vector<double> spacings, std::vector<double> values) {
  ConvergenceEstimate e;
  const size_t n = values.size();
  if (n < 2 || spacings.size() != n) {
    e.problem = "fewer than two levels";
    return e;
  }
  const double phi1 = values[n - 1], phi2 = values[n - 2];
  const double h1 = spacings[n - 1], h2 = spacings[n - 2];
  const double r21 = h2 / h1;
  const double e21 = phi2 - phi1;  // Celik's e21 = phi2 - phi1
  if (phi1 == 0) {
    e.problem = "the finest value is zero";
    return e;
  }
  const double relative21 = std::abs(e21 / phi1);
  if (n == 2) {
    // Two levels: an assumed order, and Roache's factor of safety 3.
    e.extrapolated = phi1 + (phi1 - phi2) / (std::pow(r21, kAssumedOrder) - 1);
    e.uncertainty = kSafetyFactorFallback * relative21 / (std::pow(r21, kAssumedOrder) - 1);
    e.problem = "two levels: the order of convergence cannot be observed (2 assumed, factor of safety 3)";
    return e;
  }
  const double phi3 = values[n - 3], h3 = spacings[n - 3];
  const double r32 = h3 / h2, e32 = phi3 - phi2;
  // Not asymptotic: Roache's rule on the larger of the last two changes, and
  // the finest value as the best estimate.
  auto fall_back = [&](const std::string& why) {
    e.extrapolated = phi1;
    e.uncertainty = kSafetyFactorFallback * std::max(std::abs(e21), std::abs(e32)) / std::abs(phi1) /
                    (std::pow(r21, kAssumedOrder) - 1);
    e.problem = why + " (Roache's rule instead: order 2, factor of safety 3)";
    return e;
  };
  if (e21 == 0 && e32 == 0) {
    e.extrapolated = phi1, e.uncertainty = 0, e.asymptotic = true;
    return e;
  }
  if (e21 == 0 || e32 == 0) return fall_back("two successive levels gave the same value");
  if (e32 / e21 < 0) return fall_back("the values oscillate from level to level");
  const double p = observed_order(r21, r32, e21, e32);
  if (!std::isfinite(p) || p < kMinOrder || p > kMaxOrder) {
    e.order = p;
    char text[160];
    std::snprintf(text, sizeof text, "the observed order %.2f is outside [%.1f, %.1f]", p, kMinOrder, kMaxOrder);
    return fall_back(text);
  }
  const double rp = std::pow(r21, p);
  e.order = p;
  e.extrapolated = (rp * phi1 - phi2) / (rp - 1);
  const bool near_formal = std::abs(p - kAssumedOrder) <= kNearFormalOrder * kAssumedOrder;
  const double band_order = near_formal ? kAssumedOrder : std::min(p, kAssumedOrder);
  e.uncertainty = (near_formal ? kSafetyFactor : kSafetyFactorFallback) * relative21 /
                  (std::pow(r21, band_order) - 1);
  e.asymptotic = true;
  return e;
}

}  // namespace poresph
