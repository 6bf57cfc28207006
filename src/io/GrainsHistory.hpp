#pragma once
// grains_history.csv: moving grains' state over a run (physics/RigidGrains.hpp),
// one row a grain every check interval and at the end: time, centre,
// velocity, spin (angular velocity; about z in 2D), the angle turned (2D),
// and the fluid's force and torque on it.
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "diagnostics/Observer.hpp"
#include "diagnostics/StageSetting.hpp"

namespace poresph {

template <int Dim, class Sim>
class GrainsHistory : public Observer<Sim> {
 public:
  GrainsHistory(const Sim& sim, const std::string& path, long long interval) : interval_(interval) {
    if (sim.communicator().rank() != 0) return;
    file_.open(path);
    if (!file_) throw std::runtime_error("cannot write " + path);
    constexpr int kSpin = Dim == 2 ? 1 : 3;
    file_ << "step,time,grain";
    for (int d = 0; d < Dim; ++d) file_ << ",centre_" << "xyz"[d];
    for (int d = 0; d < Dim; ++d) file_ << ",velocity_" << "xyz"[d];
    if (kSpin == 1) file_ << ",spin,turned";
    else
      for (int k = 0; k < kSpin; ++k) file_ << ",spin_" << "xyz"[k];
    for (int d = 0; d < Dim; ++d) file_ << ",force_" << "xyz"[d];
    if (kSpin == 1) file_ << ",torque";
    else
      for (int k = 0; k < kSpin; ++k) file_ << ",torque_" << "xyz"[k];
    file_ << "\n";
    write(sim);
  }

  static std::unique_ptr<Observer<Sim>> make(const StageSetting<Sim>& s) {
    if (!s.sim.rigid_grains().moving()) return nullptr;
    return std::make_unique<GrainsHistory>(s.sim, s.output_dir + "/grains_history" + s.suffix + ".csv",
                                           s.check_interval > 0 ? s.check_interval : 100);
  }
  bool writes() const override { return true; }

  void after_step(Sim& sim) override {
    if (sim.steps() % interval_ == 0) write(sim);
  }
  void at_end(Sim& sim) override {
    if (sim.steps() % interval_ != 0) write(sim);
    if (file_.is_open()) file_.flush();
  }

 private:
  void write(const Sim& sim) {
    if (!file_.is_open()) return;
    constexpr int kSpin = Dim == 2 ? 1 : 3;
    const auto& bodies = sim.rigid_grains().bodies();
    char buffer[64];
    auto put = [&](double value) {
      std::snprintf(buffer, sizeof buffer, ",%.12g", value);
      file_ << buffer;
    };
    for (size_t g = 0; g < bodies.size(); ++g) {
      const auto& b = bodies[g];
      file_ << sim.steps();
      put(sim.time());
      file_ << "," << g;
      for (int d = 0; d < Dim; ++d) put(b.centre[d]);
      for (int d = 0; d < Dim; ++d) put(b.velocity[d]);
      for (int k = 0; k < kSpin; ++k) put(b.spin[k]);
      if (kSpin == 1) put(b.turned[0]);
      for (int d = 0; d < Dim; ++d) put(b.fluid_force[d]);
      for (int k = 0; k < kSpin; ++k) put(b.fluid_torque[k]);
      file_ << "\n";
    }
  }

  long long interval_;
  std::ofstream file_;
};

}  // namespace poresph
