#pragma once
// The permeability of a run driven along one axis, sampled every
// check_interval steps and at the end (diagnostics/PermeabilityMonitor.hpp),
// written to permeability_history*.csv (rank 0), and the steady-state stop.
#include <memory>
#include <sstream>
#include <string>

#include "diagnostics/Observer.hpp"
#include "diagnostics/PermeabilityMonitor.hpp"
#include "diagnostics/StageSetting.hpp"
#include "io/HistoryFile.hpp"

namespace poresph {

template <int Dim, class Sim>
class PermeabilityProbe : public Observer<Sim> {
 public:
  // csv_path: the history file; continuing: a restart in the run's own
  // directory (keeps the rows the checkpoint counts); restored: the
  // steady-state detector's samples from the checkpoint (or none).
  PermeabilityProbe(const Sim& sim, PermeabilityMonitor<Dim> monitor, int axis, long long check_interval,
                    bool stop_when_steady, const std::string& csv_path, bool continuing, long long rows_before,
                    const RunState* restored)
      : monitor_(std::move(monitor)), axis_(axis), interval_(check_interval), stop_when_steady_(stop_when_steady),
        rows_(rows_before), scheduled_rows_(rows_before), scheduled_(monitor_.detector()) {
    if (restored) {
      monitor_.detector().restore(restored->steady_first_time, restored->steady_times, restored->steady_values);
      monitor_.detector().restore_verdict(restored->steady_verdict);
    }
    scheduled_ = monitor_.detector();
    if (sim.communicator().rank() == 0) {
      std::ostringstream header;
      PermeabilityMonitor<Dim>::write_header(header, axis);
      history_.open(csv_path, header.str(), continuing, rows_before);
      history_.file().precision(10);
    }
  }

  // Whether a stage has one: a viscous scene driven along one axis that the
  // cell is open along (periodic): across a channel's walls no flow passes.
  static bool measures(const SceneConfig& scene, int force_axis) {
    return force_axis >= 0 && scene.periodic[force_axis] && scene.kinematic_viscosity > 0;
  }
  // A warm start excites the slowest acoustic mode: judged over its period.
  static std::unique_ptr<Observer<Sim>> make(const StageSetting<Sim>& s) {
    const SceneConfig& scene = s.scene;
    if (!measures(scene, s.force_axis)) return nullptr;
    PermeabilityMonitor<Dim> monitor(s.force_axis, scene.kinematic_viscosity, driving_force(scene),
                                     s.porosity, s.acoustic_time, scene.steady_window, scene.steady_tolerance,
                                     s.warm_started);
    return std::make_unique<PermeabilityProbe>(
        s.sim, std::move(monitor), s.force_axis, s.check_interval, scene.steady_tolerance > 0,
        s.output_dir + "/permeability_history" + s.suffix + ".csv", s.continuing,
        s.continuing ? static_cast<long long>(s.restored->history_rows) : 0, s.restored);
  }

  void after_step(Sim& sim) override {
    if (sim.steps() % interval_ != 0) return;
    sample(sim);
    scheduled_rows_ = rows_;
    scheduled_ = monitor_.detector();
  }
  bool wants_stop() const override { return stop_when_steady_ && monitor_.steady(); }
  void at_end(Sim& sim) override { sample(sim); }
  // As of the last scheduled check: the sample the end of a run adds is not
  // one a run continued past that end takes, and must not weigh in its test.
  void save(RunState& state) const override {
    scheduled_.save(state.steady_times, state.steady_values);
    state.steady_first_time = scheduled_.first_time();
    state.steady_verdict = scheduled_.save_verdict();
    state.history_rows = static_cast<double>(scheduled_rows_);
  }

  // k as of the last check (none yet: nothing).
  void report(StageObservations& o) const override {
    if (!monitor_.measured()) return;
    o.has_permeability = true;
    for (int i = 0; i < Dim; ++i) o.k[i] = monitor_.permeability(i), o.u[i] = monitor_.superficial_velocity()[i];
    o.steady = monitor_.steady();
    o.relative_change = monitor_.detector().relative_change();
    o.remaining_change = monitor_.detector().remaining_change();
  }
  void status(ProgressStatus& s) const override {
    if (!monitor_.measured()) return;
    s.has_permeability = true;
    s.permeability = monitor_.permeability(axis_);
    s.remaining_change = monitor_.detector().remaining_change();
    if (stop_when_steady_) s.steady_time = monitor_.detector().predicted_steady_time();
  }

 private:
  // A check at a step already checked (the end of a run on a checking step)
  // samples k again but writes no second row.
  void sample(Sim& sim) {
    const bool new_row = sim.steps() != last_check_;
    monitor_.sample(sim.steps(), sim.time(), sim.superficial_velocity(), new_row ? history_.stream() : nullptr);
    history_.check();
    rows_ += new_row;
    last_check_ = sim.steps();
  }

  PermeabilityMonitor<Dim> monitor_;
  int axis_;
  long long interval_;
  bool stop_when_steady_;
  HistoryFile history_;
  long long rows_, scheduled_rows_;  // all rows, and those of the scheduled checks (what a checkpoint counts)
  SteadyStateDetector scheduled_;     // the detector as of the last scheduled check
  long long last_check_ = -1;
};

}  // namespace poresph
