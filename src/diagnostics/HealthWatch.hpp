#pragma once
// The state of the fluid over a run, sampled at the checks: the largest
// density variation of a fluid particle and drift of the mean density,
// fluid particles found inside grains (0 in a correct run) and the deepest,
// and the fluid particles put back on a grain surface (moving particles
// only). What summary.json reports of them is the worst over the run, its
// earlier levels and what a checkpoint had seen before a restart.
#include <algorithm>
#include <cmath>
#include <memory>

#include "diagnostics/Observer.hpp"
#include "diagnostics/StageSetting.hpp"

namespace poresph {

// HealthRecord, what it has seen: diagnostics/Observer.hpp.
template <class Sim>
class HealthWatch : public Observer<Sim> {
 public:
  // earlier: what the run had seen before this level (or before the restart).
  HealthWatch(const Sim& sim, const HealthRecord& earlier, long long check_interval)
      : sim_(sim), earlier_(earlier), record_(earlier), scheduled_(earlier), interval_(check_interval),
        spacing_(sim.scene().particle_spacing) {}

  // Every stage has one.
  static std::unique_ptr<Observer<Sim>> make(const StageSetting<Sim>& s) {
    return std::make_unique<HealthWatch>(s.sim, s.earlier_health, s.check_interval);
  }

  void after_step(Sim& sim) override {
    if (sim.steps() % interval_ != 0) return;
    check();
    scheduled_ = record_;
  }
  void at_end(Sim&) override { check(); }

  void check() {
    const auto density = sim_.density_statistics();
    record_.max_density_variation = std::max(record_.max_density_variation, density.max_variation);
    record_.max_density_drift = std::max(record_.max_density_drift, std::abs(density.mean_drift));
    const auto inside = sim_.fluid_inside_grains();
    record_.particles_inside_grains = std::max(record_.particles_inside_grains, inside.particles);
    record_.max_grain_penetration = std::max(record_.max_grain_penetration, inside.max_depth / spacing_);
  }

  // The worst so far, the simulation's own surface corrections included.
  HealthRecord record() const {
    HealthRecord r = record_;
    const auto corrected = sim_.grain_surface_corrections();
    r.grain_surface_corrections = earlier_.grain_surface_corrections + corrected.particles;
    r.max_corrected_depth = std::max(earlier_.max_corrected_depth, corrected.max_depth / spacing_);
    return r;
  }

  void report(StageObservations& o) const override { o.health = record(); }

  // The checks as of the last scheduled one (the end of a run adds one that
  // a run continued past the end does not make), and the corrections so far.
  void save(RunState& s) const override {
    HealthRecord r = record();
    r.max_density_variation = scheduled_.max_density_variation;
    r.max_density_drift = scheduled_.max_density_drift;
    r.particles_inside_grains = scheduled_.particles_inside_grains;
    r.max_grain_penetration = scheduled_.max_grain_penetration;
    s.max_density_variation = r.max_density_variation;
    s.max_density_drift = r.max_density_drift;
    s.particles_inside_grains = static_cast<double>(r.particles_inside_grains);
    s.max_grain_penetration = r.max_grain_penetration;
    s.grain_surface_corrections = static_cast<double>(r.grain_surface_corrections);
    s.max_corrected_depth = r.max_corrected_depth;
  }

 private:
  const Sim& sim_;
  HealthRecord earlier_, record_, scheduled_;
  long long interval_;
  double spacing_;
};

}  // namespace poresph
