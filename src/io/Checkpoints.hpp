#pragma once
// checkpoint.h5 every Output/Checkpoint Interval steps and at the end of a
// run (Output/Final Checkpoint), as an observer of the time loop. What it
// holds besides the particles is gathered from every observer by `write`,
// which the stage loop provides (app/StageLoop.hpp), and which the run also calls
// when a signal or a failure stops it.
#include <functional>
#include <memory>

#include "diagnostics/Observer.hpp"
#include "diagnostics/StageSetting.hpp"

namespace poresph {

template <class Sim>
class Checkpoints : public Observer<Sim> {
 public:
  // write(rates_valid): writes checkpoint.h5 of the run as it stands.
  Checkpoints(long long interval, bool at_end, std::function<void(bool)> write)
      : interval_(interval), at_end_(at_end), write_(std::move(write)) {}

  // Every stage has one (Output/Checkpoint Interval, Output/Final Checkpoint).
  static std::unique_ptr<Observer<Sim>> make(const StageSetting<Sim>& s) {
    return std::make_unique<Checkpoints>(s.scene.checkpoint_interval, s.scene.final_checkpoint, s.write_checkpoint);
  }
  bool writes() const override { return true; }

  void after_step(Sim& sim) override {
    if (interval_ > 0 && sim.steps() % interval_ == 0) write_(true);
  }
  void at_end(Sim&) override {
    if (at_end_) write_(true);
  }

 private:
  long long interval_;
  bool at_end_;
  std::function<void(bool)> write_;
};

}  // namespace poresph
