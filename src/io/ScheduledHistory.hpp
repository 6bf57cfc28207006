#pragma once
// A history file written every check interval and at the end of a run
// (io/PhasesHistory.hpp, io/GrainsHistory.hpp): the schedule and the row
// counts a checkpoint keeps. A derived history writes its rows in write(),
// adding to rows_, and saves scheduled_rows_ in its own RunState field: an
// end-of-run row is not one a run continued past that end writes.
#include "diagnostics/Observer.hpp"
#include "io/HistoryFile.hpp"

namespace poresph {

template <class Sim>
class ScheduledHistory : public Observer<Sim> {
 public:
  bool writes() const override { return true; }
  void after_step(Sim& sim) override {
    if (sim.steps() % interval_ != 0) return;
    write(sim);
    scheduled_rows_ = rows_;
  }
  void at_end(Sim& sim) override {
    if (sim.steps() % interval_ != 0) write(sim);
  }

 protected:
  // rows_before: the rows a restart in the run's own directory keeps.
  ScheduledHistory(long long interval, long long rows_before)
      : interval_(interval), rows_(rows_before), scheduled_rows_(rows_before) {}
  virtual void write(const Sim& sim) = 0;

  long long interval_;
  long long rows_, scheduled_rows_;  // data rows written, and as of the last scheduled write
  HistoryFile file_;
};

}  // namespace poresph
