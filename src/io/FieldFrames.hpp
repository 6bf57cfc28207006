#pragma once
// Field files every Output/Field Interval of simulated time, and at the
// start and end of a run (io/FieldWriter.hpp), as an observer of the time
// loop. A restart goes on with the frames its checkpoint lists, and writes
// the next one where the run would have written it had it not stopped. A
// steady solve (Solver/Method = steady) has one frame, its solved state:
// it takes no step, so its start (fluid at rest) would share the solved
// state's step and file.
#include <cmath>
#include <memory>
#include <string>

#include "diagnostics/Observer.hpp"
#include "diagnostics/StageSetting.hpp"
#include "io/FieldWriter.hpp"

namespace poresph {

template <int Dim, class Sim>
class FieldFrames : public Observer<Sim> {
 public:
  // restored: the checkpoint's state when the run continues from one;
  // continuing: in its own directory (the earlier frames are still there).
  FieldFrames(Sim& sim, const std::string& output_dir, const std::string& suffix, const RunState* restored,
              bool continuing)
      : writer_(sim.scene(), output_dir, suffix), interval_(sim.scene().field_interval),
        solved_(sim.scene().steady_solver) {
    if (continuing) {
      writer_.add_earlier_frames(restored->frame_steps, restored->frame_times,
                                 sim.fluid_particles() + sim.boundary_particles());
      // The descriptions may name frames written after the checkpoint, which are gone now.
      if (sim.communicator().rank() == 0) writer_.describe();
    } else if (interval_ > 0 && !restored && !solved_) {
      writer_.write(sim);
    }
    scheduled_ = writer_.frame_steps().size();
    if (interval_ > 0)
      next_time_ = restored && restored->field_interval == interval_
                       ? restored->next_field_time
                       : (std::floor(sim.time() / interval_ + 0.5) + 1) * interval_;
  }

  // Every stage has one (Output/Field Interval = 0 writes nothing).
  static std::unique_ptr<Observer<Sim>> make(const StageSetting<Sim>& s) {
    return std::make_unique<FieldFrames>(s.sim, s.output_dir, s.suffix, s.restored, s.continuing);
  }
  bool writes() const override { return true; }

  void after_step(Sim& sim) override {
    if (sim.time() < next_time_ - 0.5 * sim.time_step()) return;
    writer_.write(sim);
    scheduled_ = writer_.frame_steps().size();
    next_time_ += interval_;
  }
  void at_end(Sim& sim) override {
    if (interval_ > 0 && (solved_ || writer_.frame_steps().empty() || writer_.frame_steps().back() != sim.steps()))
      writer_.write(sim);
  }
  // The frames on the schedule: the end of a run adds one of its own, which
  // a run continued past it drops.
  void save(RunState& state) const override {
    state.frame_steps.assign(writer_.frame_steps().begin(), writer_.frame_steps().begin() + scheduled_);
    state.frame_times.assign(writer_.frame_times().begin(), writer_.frame_times().begin() + scheduled_);
    state.field_interval = interval_;
    state.next_field_time = next_time_;
  }

 private:
  FieldWriter<Dim> writer_;
  double interval_;
  bool solved_;  // a steady solve's stage
  size_t scheduled_ = 0;
  double next_time_ = INFINITY;
};

}  // namespace poresph
