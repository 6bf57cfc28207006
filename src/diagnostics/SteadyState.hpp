#pragma once
// Steady-state detection for a scalar such as the permeability: steady once
// the samples of the last `window` of time vary by less than
// tolerance * |latest value|.
#include <algorithm>
#include <cmath>
#include <deque>
#include <utility>
#include <vector>

namespace poresph {

class SteadyStateDetector {
 public:
  SteadyStateDetector(double window, double tolerance) : window_(window), tolerance_(tolerance) {}

  // Adds the value at `time` (times increasing); returns whether steady.
  bool add(double time, double value) {
    if (samples_.empty()) first_time_ = time;
    samples_.emplace_back(time, value);
    while (samples_.front().first < time - window_) samples_.pop_front();
    double lo = value, hi = value;
    for (const auto& s : samples_) lo = std::min(lo, s.second), hi = std::max(hi, s.second);
    relative_change_ = value != 0 ? (hi - lo) / std::abs(value) : INFINITY;
    return time - first_time_ >= window_ && relative_change_ <= tolerance_;
  }

  // (max - min) / |latest| over the current window.
  double relative_change() const { return relative_change_; }

  // The window's samples and the first time, to continue after a restart.
  double first_time() const { return first_time_; }
  const std::deque<std::pair<double, double>>& samples() const { return samples_; }
  void restore(double first_time, const std::vector<double>& times, const std::vector<double>& values) {
    samples_.clear();
    for (size_t k = 0; k < times.size(); ++k) samples_.emplace_back(times[k], values[k]);
    first_time_ = first_time;
  }

 private:
  double window_, tolerance_;
  double first_time_ = 0;
  double relative_change_ = INFINITY;
  std::deque<std::pair<double, double>> samples_;
};

}  // namespace poresph
