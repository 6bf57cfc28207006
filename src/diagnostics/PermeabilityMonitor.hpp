#pragma once
// Darcy's permeability of a run driven along one axis, k_i = nu <u_i> / F
// with <u> the superficial velocity, sampled at the run's checks: it feeds
// the steady-state test (diagnostics/SteadyState.hpp) with the flow's own
// time scale, the longer of the spin-up time k / (nu porosity) and the
// acoustic crossing time, and appends each sample to
// the history CSV (rank 0 passes an open stream, the others none).
#include <algorithm>
#include <cmath>
#include <ostream>

#include "core/Vec.hpp"
#include "diagnostics/SteadyState.hpp"

namespace poresph {

template <int Dim>
class PermeabilityMonitor {
 public:
  // acoustic_time: the time a pressure wave takes to cross the cell, L / c.
  // The weakly compressible fluid's slowest pressure modes slosh on it and
  // die out over several crossings: where it is longer than the spin-up time
  // (problem III: 256 s against 17 s), it is the time scale to wait on.
  // smooth_acoustic: judge and report k averaged over one acoustic_time
  // (SteadyState.hpp), for a start that excites the acoustic modes.
  PermeabilityMonitor(int axis, double nu, double force, double porosity, double acoustic_time, double window,
                      double tolerance, bool smooth_acoustic = false)
      : axis_(axis), nu_(nu), force_(force), porosity_(porosity), acoustic_time_(acoustic_time),
        detector_(window, tolerance, Dim) {
    if (smooth_acoustic) detector_.set_smoothing(acoustic_time);
  }

  static void write_header(std::ostream& csv, int axis) {
    csv << "step,time";
    for (int i = 0; i < Dim; ++i) csv << ",k" << "xyz"[i] << "xyz"[axis];
    csv << ",relative_change,remaining_change\n";
  }

  // A check at `time` with superficial velocity u; returns whether k is steady.
  bool sample(long long step, double time, const Vec<Dim>& u, std::ostream* csv) {
    for (int i = 0; i < Dim; ++i) k_[i] = nu_ * u[i] / force_;
    superficial_velocity_ = u;
    measured_ = true;
    SteadyStateDetector::Sample column{};
    for (int i = 0; i < Dim; ++i) column[i] = k_[i];
    steady_ = detector_.add(time, column, std::max(spin_up_time(), acoustic_span()));
    if (csv) {
      *csv << step << ',' << time;
      for (int i = 0; i < Dim; ++i) *csv << ',' << k_[i];
      *csv << ',' << detector_.relative_change() << ',' << detector_.remaining_change() << '\n';
      csv->flush();  // a long run's history is readable while it runs, and survives a kill
    }
    return steady_;
  }

  // k / (nu porosity) = <u> / (porosity |F|): how long the force takes to
  // bring fluid at rest to the mean pore velocity; 0 before the flow moves.
  double spin_up_time() const {
    const double k = k_[axis_];
    return k > 0 && nu_ > 0 && porosity_ > 0 ? k / (nu_ * porosity_) : 0.0;
  }

  // The shortest span between the values the steady test compares for the
  // acoustic modes: their period L / c; two thirds of it between means over
  // L / c (a warm start), which have averaged those modes out already.
  // Measured on the ladders of docs/speed_vs_error.md: with two thirds every
  // warm level stops within 0.1 % of its long-run k; with one half, a level
  // of the square array c = 0.5 stopped 0.15 % short.
  double acoustic_span() const { return smoothed() ? kSmoothedAcousticSpan * acoustic_time_ : acoustic_time_; }

  bool measured() const { return measured_; }
  bool steady() const { return steady_; }
  // k as judged: the last sample, or its mean over the smoothing time.
  double permeability(int i) const { return smoothed() ? detector_.judged_value()[i] : k_[i]; }
  Vec<Dim> superficial_velocity() const {
    if (!smoothed()) return superficial_velocity_;
    const auto k = detector_.judged_value();
    Vec<Dim> u = Vec<Dim>::zero();
    for (int i = 0; i < Dim; ++i) u[i] = k[i] * force_ / nu_;
    return u;
  }
  bool smoothed() const { return detector_.smoothing() > 0; }
  SteadyStateDetector& detector() { return detector_; }
  const SteadyStateDetector& detector() const { return detector_; }

 private:
  static constexpr double kSmoothedAcousticSpan = 2.0 / 3.0;
  int axis_;
  double nu_, force_, porosity_, acoustic_time_;
  SteadyStateDetector detector_;
  Vec<Dim> k_ = Vec<Dim>::zero(), superficial_velocity_ = Vec<Dim>::zero();
  bool measured_ = false, steady_ = false;
};

}  // namespace poresph
