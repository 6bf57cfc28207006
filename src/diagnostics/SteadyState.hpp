#pragma once
// When is a driven flow steady? The permeability approaches its limit like
// the slowest mode of the flow, k(t) = k_inf - A e^{-t/tau}, with tau about
// the spin-up time k / (nu porosity): the time the body force takes to
// bring fluid at rest to the mean pore velocity. A window shorter than that
// sees a slowly rising k as flat (docs/validation.md measured stops 1.7 %
// early that way), so the values compared here are a span apart that is
// never shorter than the flow's own time scale, and the limit is predicted
// from three of them (Aitken's extrapolation of a geometric sequence):
// with d1 = k(t - span) - k(t - 2 span) and d2 = k(t) - k(t - span), the
// ratio q = d2 / d1 = e^{-span/tau}, and what k has still to change is
// d2 q / (1 - q). Steady once that and the range of the values over the
// last span are both within the tolerance (the range, not only the three
// values: an oscillation whose period is near the span would alias to a
// flat line). A sample is a vector (the column of the
// permeability tensor being driven): every component is followed, each
// relative to the vector's length, so that a small off-diagonal component
// still moving keeps the run going only if it matters.
// With a smoothing time T (set_smoothing), every value above is the mean
// of the samples over the T before it: over T = L / c, the period of the
// weakly compressible fluid's slowest acoustic mode, that mode and its
// harmonics average out, and what is left is the approach of the flow
// itself. A warm-started level of a resolution ladder uses it: its
// interpolated start excites that mode, which otherwise holds the stop
// for several periods after k has settled (docs/method.md). The mean is
// computed from the kept samples, so that a restart, which keeps them,
// continues exactly; T = 0 (the default) is the plain test.
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <utility>
#include <vector>

namespace poresph {

class SteadyStateDetector {
 public:
  static constexpr int kMaxComponents = 3;
  using Sample = std::array<double, kMaxComponents>;

  // window: the shortest span (s) between compared values; tolerance:
  // relative; components: how many values a sample has.
  SteadyStateDetector(double window, double tolerance, int components = 1)
      : window_(window), tolerance_(tolerance), components_(components) {}

  // Judge the mean of the samples over `seconds` before each time (0: the samples themselves).
  void set_smoothing(double seconds) { smoothing_ = seconds > 0 ? seconds : 0.0; }
  double smoothing() const { return smoothing_; }

  // Adds the sample at `time` (times increasing) with the flow's time scale
  // now (0 if unknown: the window alone sets the span); returns whether steady.
  // A sample at or before the last one's time is the same state seen again
  // (a run ending on a checking step): it changes nothing, where a repeat
  // would weigh that state twice in the mean and could flip the verdict.
  bool add(double time, const Sample& value, double time_scale = 0) {
    if (!samples_.empty() && time <= samples_.back().first)
      return remaining_change_ <= tolerance_ && relative_change_ <= tolerance_;
    if (samples_.empty()) first_time_ = time;
    samples_.emplace_back(time, value);
    span_ = std::max(window_, time_scale);
    // Keep three spans and one sample before them, for the interpolation,
    // and the smoothing time before those, for their means.
    while (samples_.size() > 2 && samples_[1].first < time - 3 * span_ - smoothing_) samples_.pop_front();
    relative_change_ = remaining_change_ = kUnknown;
    fitted_time_scale_ = kUnknown;
    double length = 0;
    for (int i = 0; i < components_; ++i) length += value[i] * value[i];
    length = std::sqrt(length);
    if (!(span_ > 0) || time - first_time_ < 2 * span_ + smoothing_ || length == 0) return false;
    const Sample k1 = value_at(time - 2 * span_), k2 = value_at(time - span_);
    Sample lo = k2, hi = k2;  // over the last span: a swing between the three values shows here
    for (size_t s = 0; s < samples_.size(); ++s)
      if (samples_[s].first >= time - span_) {
        const Sample k = mean_before(s);
        for (int i = 0; i < components_; ++i) lo[i] = std::min(lo[i], k[i]), hi[i] = std::max(hi[i], k[i]);
      }
    const Sample value_now = mean_before(samples_.size() - 1);
    relative_change_ = remaining_change_ = 0;
    fitted_time_scale_ = 0;
    for (int i = 0; i < components_; ++i) {
      const double d1 = k2[i] - k1[i], d2 = value_now[i] - k2[i], swing = hi[i] - lo[i];
      relative_change_ = std::max(relative_change_, swing / length);
      const double largest = std::max({std::abs(d1), std::abs(d2), swing});
      const double q = d1 != 0 ? d2 / d1 : 0;
      double remaining = kUnknown;
      if (largest <= kNoise * tolerance_ * length) {
        remaining = largest / length;  // settled to round-off: no trend left to fit
      } else if (q > 0 && q < 1 && swing <= kMonotone * std::abs(d2)) {  // monotone over the last span
        remaining = std::abs(d2) * q / (1 - q) / length;
        fitted_time_scale_ = std::max(fitted_time_scale_, -span_ / std::log(q));
      } else if (q <= 0 || swing > std::abs(d2)) {
        remaining = largest / length;  // oscillating about the limit: at most the last swing away
        fitted_time_scale_ = kUnknown;
      }  // q >= 1: not converging (yet): nothing can be predicted
      if (!std::isfinite(remaining)) fitted_time_scale_ = kUnknown;
      remaining_change_ = std::max(remaining_change_, remaining);
    }
    return remaining_change_ <= tolerance_ && relative_change_ <= tolerance_;
  }
  bool add(double time, double value, double time_scale = 0) { return add(time, Sample{value, 0, 0}, time_scale); }

  // The value judged at the last sample: the sample itself, or with a
  // smoothing time the mean of the samples over it (zeros before any sample).
  Sample judged_value() const { return samples_.empty() ? Sample{} : mean_before(samples_.size() - 1); }

  // Largest range of a component over the last span, relative to |k(t)|;
  // infinite until two spans have passed.
  double relative_change() const { return relative_change_; }
  // The predicted largest |k_i,inf - k_i(t)| / |k(t)|; infinite while it cannot be predicted.
  double remaining_change() const { return remaining_change_; }
  // The span of the last comparison: max(window, the flow's time scale).
  double span() const { return span_; }
  // When the fitted approach brings the remaining change down to the
  // tolerance (now, if it is there); NaN while no approach can be fitted.
  double predicted_steady_time() const {
    const double now = samples_.empty() ? 0 : samples_.back().first;
    if (remaining_change_ <= tolerance_) return now;
    if (!std::isfinite(fitted_time_scale_) || !std::isfinite(remaining_change_))
      return std::numeric_limits<double>::quiet_NaN();
    return now + fitted_time_scale_ * std::log(remaining_change_ / tolerance_);
  }

  // The samples kept (values flattened, `components` a sample) and the
  // first time, to continue after a restart.
  double first_time() const { return first_time_; }
  void save(std::vector<double>& times, std::vector<double>& values) const {
    for (const auto& [t, k] : samples_) {
      times.push_back(t);
      values.insert(values.end(), k.begin(), k.begin() + components_);
    }
  }
  // The verdict on the last sample (relative and remaining change, fitted
  // time scale, span): a sample at that time again gives it back, so a
  // restart at that step reports what the run reported there.
  std::vector<double> save_verdict() const {
    return {relative_change_, remaining_change_, fitted_time_scale_, span_};
  }
  void restore_verdict(const std::vector<double>& verdict) {
    if (verdict.size() != 4) return;
    relative_change_ = verdict[0], remaining_change_ = verdict[1], fitted_time_scale_ = verdict[2], span_ = verdict[3];
  }
  void restore(double first_time, const std::vector<double>& times, const std::vector<double>& values) {
    samples_.clear();
    for (size_t s = 0; s < times.size() && (s + 1) * components_ <= values.size(); ++s) {
      Sample k{};
      for (int i = 0; i < components_; ++i) k[i] = values[s * components_ + i];
      samples_.emplace_back(times[s], k);
    }
    first_time_ = first_time;
  }

 private:
  static constexpr double kUnknown = std::numeric_limits<double>::infinity();
  // Changes below this fraction of the tolerance are taken as settled.
  static constexpr double kNoise = 1e-3;
  // A range over the last span up to this multiple of its net change still
  // counts as a monotone approach (small wiggles ride on it).
  static constexpr double kMonotone = 1.1;

  // Sample s itself, or with a smoothing time T the mean of the samples in
  // (t_s - T, t_s] (all kept: the window reaches T before three spans).
  Sample mean_before(size_t s) const {
    if (smoothing_ == 0) return samples_[s].second;
    Sample sum{};
    int count = 0;
    for (size_t r = s + 1; r-- > 0 && samples_[r].first > samples_[s].first - smoothing_;) {
      for (int i = 0; i < components_; ++i) sum[i] += samples_[r].second[i];
      ++count;
    }
    for (int i = 0; i < components_; ++i) sum[i] /= count;
    return sum;
  }

  // Linear interpolation between the kept samples' judged values (t lies within them).
  Sample value_at(double t) const {
    auto after = std::lower_bound(samples_.begin(), samples_.end(), t,
                                  [](const std::pair<double, Sample>& s, double v) { return s.first < v; });
    if (after == samples_.begin()) return mean_before(0);
    if (after == samples_.end()) return mean_before(samples_.size() - 1);
    const size_t a = static_cast<size_t>(after - samples_.begin());
    const Sample k_before = mean_before(a - 1), k_after = mean_before(a);
    const double w = (t - samples_[a - 1].first) / (samples_[a].first - samples_[a - 1].first);
    Sample k{};
    for (int i = 0; i < components_; ++i) k[i] = k_before[i] + w * (k_after[i] - k_before[i]);
    return k;
  }

  double window_, tolerance_;
  double smoothing_ = 0;
  int components_;
  double first_time_ = 0, span_ = 0;
  double relative_change_ = kUnknown, remaining_change_ = kUnknown, fitted_time_scale_ = kUnknown;
  std::deque<std::pair<double, Sample>> samples_;
};

}  // namespace poresph
