#pragma once
// What watches a run's time loop (app/LevelRun.hpp): after every step each
// observer does its part (a probe samples, a writer writes, a checkpoint is
// taken), one may ask the loop to stop (the steady-state stop), each says
// what it has done at the end, and each saves where it stands into a
// checkpoint so that a restart goes on from there. Sim is the simulation
// type (app/Simulation.hpp), a parameter so that the observers depend on
// what they use of it, not on the app layer.
#include "io/RunState.hpp"

namespace poresph {

template <class Sim>
class Observer {
 public:
  virtual ~Observer() = default;
  // After every step of the loop.
  virtual void after_step(Sim& sim) { (void)sim; }
  // Whether the loop may stop after this step.
  virtual bool wants_stop() const { return false; }
  // After the loop, when it ended by itself (End Time, Max Steps, steady).
  virtual void at_end(Sim& sim) { (void)sim; }
  // Where it stands, for a checkpoint.
  virtual void save(RunState& state) const { (void)state; }
};

}  // namespace poresph
