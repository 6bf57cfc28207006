#pragma once
// balance_history.csv: the load balance of moving particles on 2 or more
// processes (Simulation::balance, Parallel/Rebalance Threshold), one row
// every Parallel/Rebalance Interval steps: the wall time a step, each
// process's working time a step (its wall time less its time in collective
// operations; the slowest and the mean), their ratio (the imbalance),
// whether the cell was then divided
// anew, the fewest and most particles a process owned, the time lost to the
// imbalance since the last division and what the last division cost.
// Written whether or not the run rebalances, so that runs with and without
// compare.
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include "diagnostics/Observer.hpp"
#include "diagnostics/StageSetting.hpp"
#include "io/HistoryFile.hpp"

namespace poresph {

template <class Sim>
class BalanceHistory : public Observer<Sim> {
 public:
  BalanceHistory(const Sim& sim, const std::string& path, bool continuing, long long rows_before)
      : rows_(rows_before) {
    if (sim.communicator().rank() != 0) return;
    file_.open(path,
               "step,time,seconds_per_step,compute_seconds_max,compute_seconds_mean,imbalance,rebalanced,"
               "particles_min,particles_max,lost_seconds,division_seconds\n",
               continuing, rows_before);
  }

  static std::unique_ptr<Observer<Sim>> make(const StageSetting<Sim>& s) {
    if (!s.sim.measures_balance()) return nullptr;
    return std::make_unique<BalanceHistory>(s.sim, s.output_dir + "/balance_history" + s.suffix + ".csv",
                                            s.continuing,
                                            s.continuing ? static_cast<long long>(s.restored->balance_history_rows) : 0);
  }
  bool writes() const override { return true; }

  void after_step(Sim& sim) override {
    const auto& b = sim.balance();
    if (b.step != sim.steps()) return;
    ++rows_;
    std::ofstream* out = file_.stream();
    if (!out) return;
    char line[320];
    std::snprintf(line, sizeof line, "%lld,%.12g,%.6g,%.6g,%.6g,%.9g,%d,%lld,%lld,%.17g,%.17g\n", sim.steps(),
                  sim.time(), b.seconds_per_step, b.compute_max, b.compute_mean, b.imbalance, b.rebalanced ? 1 : 0,
                  b.particles_min, b.particles_max, b.lost_seconds, b.division_seconds);
    *out << line;
    file_.check();
  }
  void save(RunState& state) const override { state.balance_history_rows = static_cast<double>(rows_); }

 private:
  long long rows_;
  HistoryFile file_;
};

}  // namespace poresph
