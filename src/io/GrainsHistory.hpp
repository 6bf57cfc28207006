#pragma once
// grains_history.csv: moving grains' state over a run (physics/RigidGrains.hpp),
// one row a grain every check interval and at the end: time, centre,
// velocity, spin (angular velocity; about z in 2D), the angle turned (2D),
// the fluid's force and torque on it, the contacts' force and torque on it
// and their count. Every write is checked (io/HistoryFile.hpp); a restart
// in the run's own directory keeps the rows its checkpoint counts and goes
// on from there.
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "diagnostics/Observer.hpp"
#include "diagnostics/StageSetting.hpp"
#include "core/Vec.hpp"
#include "io/ScheduledHistory.hpp"

namespace poresph {

template <int Dim, class Sim>
class GrainsHistory : public ScheduledHistory<Sim> {
 public:
  // continuing: a restart in the run's own directory, which keeps the
  // first `rows_before` rows (the ones its checkpoint counts).
  GrainsHistory(const Sim& sim, const std::string& path, long long interval, bool continuing, long long rows_before)
      : ScheduledHistory<Sim>(interval, rows_before) {
    if (sim.communicator().rank() != 0) return;
    constexpr int kSpin = spin_components<Dim>();
    std::string header = "step,time,grain";
    for (int d = 0; d < Dim; ++d) header += std::string(",centre_") + "xyz"[d];
    for (int d = 0; d < Dim; ++d) header += std::string(",velocity_") + "xyz"[d];
    if (kSpin == 1) header += ",spin,turned";
    else
      for (int k = 0; k < kSpin; ++k) header += std::string(",spin_") + "xyz"[k];
    for (int d = 0; d < Dim; ++d) header += std::string(",force_") + "xyz"[d];
    if (kSpin == 1) header += ",torque";
    else
      for (int k = 0; k < kSpin; ++k) header += std::string(",torque_") + "xyz"[k];
    for (int d = 0; d < Dim; ++d) header += std::string(",contact_force_") + "xyz"[d];
    if (kSpin == 1) header += ",contact_torque";
    else
      for (int k = 0; k < kSpin; ++k) header += std::string(",contact_torque_") + "xyz"[k];
    header += ",contacts";
    this->file_.open(path, header + "\n", continuing, rows_before);
    if (!continuing) write(sim);
  }

  static std::unique_ptr<Observer<Sim>> make(const StageSetting<Sim>& s) {
    if (!s.sim.rigid_grains().moving()) return nullptr;
    return std::make_unique<GrainsHistory>(
        s.sim, s.output_dir + "/grains_history" + s.suffix + ".csv", s.check_interval > 0 ? s.check_interval : 100,
        s.continuing, s.continuing ? static_cast<long long>(s.restored->grains_history_rows) : 0);
  }
  // As of the last scheduled row (ScheduledHistory).
  void save(RunState& state) const override { state.grains_history_rows = static_cast<double>(this->scheduled_rows_); }

 private:
  void write(const Sim& sim) override {
    std::ofstream* out = this->file_.stream();
    if (!out) return;
    constexpr int kSpin = spin_components<Dim>();
    const auto& bodies = sim.rigid_grains().bodies();
    char buffer[64];
    auto put = [&](double value) {
      std::snprintf(buffer, sizeof buffer, ",%.12g", value);
      *out << buffer;
    };
    for (size_t g = 0; g < bodies.size(); ++g) {
      const auto& b = bodies[g];
      *out << sim.steps();
      put(sim.time());
      *out << "," << g;
      for (int d = 0; d < Dim; ++d) put(b.centre[d]);
      for (int d = 0; d < Dim; ++d) put(b.velocity[d]);
      for (int k = 0; k < kSpin; ++k) put(b.spin[k]);
      if (kSpin == 1) put(b.turned[0]);
      for (int d = 0; d < Dim; ++d) put(b.fluid_force[d]);
      for (int k = 0; k < kSpin; ++k) put(b.fluid_torque[k]);
      for (int d = 0; d < Dim; ++d) put(b.contact_force[d]);
      for (int k = 0; k < kSpin; ++k) put(b.contact_torque[k]);
      *out << "," << b.contacts;
      *out << "\n";
      ++this->rows_;
    }
    this->file_.check();
  }
};

}  // namespace poresph
