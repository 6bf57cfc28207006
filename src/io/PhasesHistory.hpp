#pragma once
// phases_history.csv: two fluids over a run (diagnostics/PhaseProbe.hpp),
// one row every check interval and at the end: each phase's superficial
// velocity along the driven axis and its volume-weighted mean pressure,
// and the capillary pressure, phase 1's mean pressure less phase 0's (with
// a moving interface, each phase's volume by the phase field too; with
// Phases/Force Steps, the body force along the axis). The
// measures are sums over all processes; the first writes. Every write is
// checked (io/HistoryFile.hpp); a restart in the run's own directory keeps
// the rows its checkpoint counts and goes on from there.
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include "diagnostics/Observer.hpp"
#include "diagnostics/PhaseProbe.hpp"
#include "diagnostics/StageSetting.hpp"
#include "io/ScheduledHistory.hpp"

namespace poresph {

template <class Sim>
class PhasesHistory : public ScheduledHistory<Sim> {
 public:
  PhasesHistory(const Sim& sim, const SceneConfig& scene, int axis, const std::string& path, long long interval,
                bool continuing, long long rows_before)
      : ScheduledHistory<Sim>(interval, rows_before), scene_(scene), axis_(axis) {
    std::string header = "step,time";
    for (size_t p = 0; p < scene.phases.size(); ++p)
      header += ",superficial_velocity_" + std::to_string(p) + ",mean_pressure_" + std::to_string(p);
    header += ",capillary_pressure";
    if (scene.moving_interface)
      for (size_t p = 0; p < scene.phases.size(); ++p) header += ",phase_field_volume_" + std::to_string(p);
    if (!scene.force_steps.empty()) header += ",body_force";
    header += "\n";
    if (sim.communicator().rank() == 0) this->file_.open(path, header, continuing, rows_before);
    if (!continuing) write(sim);
  }

  // A scene with phases, along the force's axis (x without one), as PhaseProbe.
  static std::unique_ptr<Observer<Sim>> make(const StageSetting<Sim>& s) {
    if (!s.scene.has_phases()) return nullptr;
    return std::make_unique<PhasesHistory>(
        s.sim, s.scene, s.force_axis >= 0 ? s.force_axis : 0, s.output_dir + "/phases_history" + s.suffix + ".csv",
        s.check_interval > 0 ? s.check_interval : 100, s.continuing,
        s.continuing ? static_cast<long long>(s.restored->phases_history_rows) : 0);
  }
  // As of the last scheduled row (ScheduledHistory).
  void save(RunState& state) const override { state.phases_history_rows = static_cast<double>(this->scheduled_rows_); }

 private:
  // On every process (the measures are collective); the first writes.
  void write(const Sim& sim) override {
    const auto measures = measure_phases(sim, scene_, axis_);
    ++this->rows_;
    std::ofstream* out = this->file_.stream();
    if (!out) return;
    char buffer[64];
    auto put = [&](double value) {
      std::snprintf(buffer, sizeof buffer, ",%.12g", value);
      *out << buffer;
    };
    *out << sim.steps();
    put(sim.time());
    for (const auto& m : measures) put(m.superficial_velocity), put(m.mean_pressure);
    put(measures[1].mean_pressure - measures[0].mean_pressure);
    for (const auto& m : measures)
      if (m.has_phase_field) put(m.phase_field_volume);
    if (!scene_.force_steps.empty()) put(sim.body_force()[axis_]);
    *out << "\n";
    this->file_.check();
  }

  const SceneConfig& scene_;  // the stage's, held as PhaseProbe holds it
  int axis_;
};

}  // namespace poresph
