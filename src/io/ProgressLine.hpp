#pragma once
// The progress line of a run on a terminal, rewritten in place at most four
// times a second; nothing at all when disabled (logs stay quiet). A run that
// stops at a steady permeability shows k, what it is predicted still to
// change, and the wall time to the predicted steady stop: a percentage of
// End Time would say 0.3 % for a run that is nearly done.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include "diagnostics/Observer.hpp"
#include "diagnostics/StageSetting.hpp"

namespace poresph {

// Seconds still to go for a quantity that fell from `from` (at `from_seconds`)
// to `now` (at `now_seconds`) to fall on to `target` at the same geometric
// rate; 0 once it is there, NaN while it has not fallen (no rate yet). A
// steady solve's Newton step: its residual estimate since a recent anchor
// (RecentAnchor), so that a step that crawls shows a time that grows, not
// the 0 of a residual already below the solve's tolerance.
inline double geometric_eta(double from, double from_seconds, double now, double now_seconds, double target) {
  if (now <= target) return 0.0;
  if (!(now < from) || !(now_seconds > from_seconds) || !(target > 0)) return std::nan("");
  return std::log(now / target) * (now_seconds - from_seconds) / std::log(from / now);
}

// Where a falling quantity stood a while ago, for geometric_eta's rate:
// the older of two anchors that move on every `window` seconds, so that
// the rate spans the last one to two windows, not the whole fall, and a
// crawl shows as one.
struct RecentAnchor {
  double window = 20.0;
  double value = 0, seconds = 0;         // the older anchor: the rate is taken from here
  double next_value = 0, next_seconds = 0;

  void restart(double v, double t) { value = next_value = v, seconds = next_seconds = t; }
  void update(double v, double t) {
    if (t - next_seconds < window) return;
    value = next_value, seconds = next_seconds;
    next_value = v, next_seconds = t;
  }
};

class ProgressLine {
 public:
  using Clock = std::chrono::steady_clock;
  explicit ProgressLine(bool enabled) : enabled_(enabled), start_(Clock::now()), last_(start_) {}

  void update(const std::string& label, const ProgressStatus& s) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last_).count() < 0.25) return;
    last_ = now;
    if (!started_) start_time_ = s.time, start_ = now, started_ = true;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    char text[256];
    int n = std::snprintf(text, sizeof text, "\r%sstep %lld  t = %.4e s", label.c_str(), s.step, s.time);
    if (s.has_permeability) {
      n += std::snprintf(text + n, sizeof text - n, "  k = %.5e m^2", s.permeability);
      if (std::isfinite(s.remaining_change))
        n += std::snprintf(text + n, sizeof text - n, "  to go %.2g %%", 100 * s.remaining_change);
    }
    const double simulated = s.time - start_time_;
    if (std::isfinite(s.steady_time) && simulated > 0) {
      const double eta = (s.steady_time - s.time) * elapsed / simulated;
      n += std::snprintf(text + n, sizeof text - n, "  ETA %.0f s to steady", eta > 0 ? eta : 0.0);
    } else {
      const double done = s.fraction_of_end;
      const double eta = done > 0 ? elapsed * (1 - done) / done : 0.0;
      n += std::snprintf(text + n, sizeof text - n, "  %5.1f %% of End Time  ETA %.0f s", 100 * done, eta);
    }
    std::printf("%s   ", text);
    std::fflush(stdout);
    printed_ = true;
  }

  // A line of the caller's own (a steady solve's iterations), at the same pace.
  void update_text(const std::string& label, const std::string& text) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last_).count() < 0.25) return;
    last_ = now;
    std::printf("\r%s%s   ", label.c_str(), text.c_str());
    std::fflush(stdout);
    printed_ = true;
  }

  void finish() {
    if (printed_) std::printf("\n");
    printed_ = false;
  }

 private:
  bool enabled_, printed_ = false, started_ = false;
  Clock::time_point start_, last_;
  double start_time_ = 0;
};

// The progress line as an observer of the time loop; status() says where
// the run stands (the permeability probe's k and predicted stop).
template <class Sim>
class ProgressObserver : public Observer<Sim> {
 public:
  ProgressObserver(bool enabled, std::string label, long long last_step, std::function<ProgressStatus()> status)
      : line_(enabled), enabled_(enabled), label_(std::move(label)), last_step_(last_step), status_(std::move(status)) {}

  // Every stage has one (shown or not: Run/Progress).
  static std::unique_ptr<Observer<Sim>> make(const StageSetting<Sim>& s) {
    return std::make_unique<ProgressObserver>(s.show_progress, s.progress_label, s.last_step, s.progress_status);
  }
  bool writes() const override { return true; }

  void after_step(Sim& sim) override {
    if (!enabled_) return;
    ProgressStatus s = status_ ? status_() : ProgressStatus{};
    s.step = sim.steps();
    s.time = sim.time();
    s.fraction_of_end = static_cast<double>(sim.steps()) / last_step_;
    line_.update(label_, s);
  }
  void at_end(Sim&) override { line_.finish(); }
  // A steady solve's own line (it has no steps).
  void show(const std::string& text) override {
    if (enabled_) line_.update_text(label_, text);
  }
  // Ends the line before other output (a failure, a signal).
  void end_display() override { line_.finish(); }

 private:
  ProgressLine line_;
  bool enabled_;
  std::string label_;
  long long last_step_;
  std::function<ProgressStatus()> status_;
};

}  // namespace poresph
