#pragma once
// Start-up channel flows (Morris et al. 1997): at each requested time, and
// at the end, v_x of every fluid particle against the series solution at the
// particles' own time (diagnostics/ChannelFlow.hpp); the largest error goes
// to summary.json, the points to profiles.csv (rank 0) for plots.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/Particles.hpp"
#include "diagnostics/ChannelFlow.hpp"
#include "diagnostics/Observer.hpp"
#include "diagnostics/StageSetting.hpp"
#include "io/HistoryFile.hpp"

namespace poresph {

// max |v_x - series| / v_max over the fluid particles of `sim` now, and
// their rows "sample_time,time,y,v_x,series" (this process's).
template <class Sim>
double channel_profile_error(const Sim& sim, const ChannelFlow& reference, double sample_time, std::string& rows) {
  const auto& P = sim.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  const double t = sim.time(), scale = reference.steady_peak();
  double worst = 0.0;
  char buffer[160];
  for (int i = 0; i < P.owned; ++i) {
    if (kind(i) != kFluid) continue;
    const double series = reference.velocity(x(i, 1), t);
    worst = std::max(worst, std::abs(v(i, 0) - series) / scale);
    std::snprintf(buffer, sizeof buffer, "%.10g,%.10g,%.10g,%.10g,%.10g\n", sample_time, t, x(i, 1), v(i, 0), series);
    rows += buffer;
  }
  return worst;
}

template <class Sim>
class ChannelProbe : public Observer<Sim> {
 public:
  // csv_path: profiles.csv, written by rank 0; continuing: a restart in the
  // run's own directory, which keeps the rows its checkpoint counts.
  // restored: the checkpoint's state, whose samples the summary goes on with.
  ChannelProbe(const Sim& sim, const ChannelFlow& reference, std::vector<double> sample_times,
               const std::string& csv_path, bool continuing, long long rows_before, const RunState* restored)
      : reference_(reference), times_(std::move(sample_times)), rows_(rows_before), scheduled_rows_(rows_before) {
    if (restored)
      for (size_t k = 0; k + 3 <= restored->profile_samples.size(); k += 3) {
        const double* v = &restored->profile_samples[k];
        samples_.push_back({v[0], v[1], v[2]});
        largest_ = std::max(largest_, v[2]);
      }
    scheduled_samples_ = samples_.size();
    std::sort(times_.begin(), times_.end());
    const double dt = sim.time_step();
    while (next_ < times_.size() && sim.time() >= times_[next_] - 0.5 * dt) ++next_;
    if (sim.communicator().rank() == 0) {
      csv_.open(csv_path, "sample_time,time,y,v_x,v_x_series\n", continuing, rows_before);
      csv_.file().precision(10);
    }
  }

  // A channel's stage on the scene's own force, marched: a steady solve has
  // no start-up flow to compare (it reports k), and the series is of one
  // fluid (two: PhaseProbe), of an empty channel driven along x or by its
  // walls: grains, an image or a force across the walls make another flow,
  // and no flow at all gives nothing to compare. Only the finest level's
  // profiles go into the summary.
  static std::unique_ptr<Observer<Sim>> make(const StageSetting<Sim>& s) {
    const SceneConfig& scene = s.scene;
    if (scene.walls != WallType::Channel || s.stage_axis > 0 || scene.steady_solver || scene.has_phases())
      return nullptr;
    const bool driven = scene.body_force[0] != 0 || scene.lower_wall_velocity != 0 || scene.upper_wall_velocity != 0;
    if (!scene.empty_channel() || !driven) return nullptr;
    auto probe = std::make_unique<ChannelProbe>(
        s.sim, ChannelFlow{scene.cell_size[1], scene.kinematic_viscosity, scene.body_force[0],
                           scene.lower_wall_velocity, scene.upper_wall_velocity},
        scene.profile_sample_times, s.output_dir + "/profiles" + s.suffix + ".csv", s.continuing,
        s.continuing ? static_cast<long long>(s.restored->profile_rows) : 0, s.restored);
    probe->reports_ = s.finest;
    return probe;
  }

  // Sample at the first step at or past each requested time; the series is
  // evaluated at the particles' own time, so no interpolation enters.
  void after_step(Sim& sim) override {
    while (next_ < times_.size() && sim.time() >= times_[next_] - 0.5 * sim.time_step()) sample(sim, times_[next_++]);
    scheduled_rows_ = rows_;
    scheduled_samples_ = samples_.size();
  }
  void at_end(Sim& sim) override { sample(sim, sim.time()); }
  // The requested samples so far; the end of a run adds one of its own, which a run continued past it drops.
  void save(RunState& state) const override {
    state.profile_rows = static_cast<double>(scheduled_rows_);
    state.profile_samples.clear();
    for (size_t k = 0; k < scheduled_samples_; ++k)
      state.profile_samples.insert(state.profile_samples.end(),
                                   {samples_[k].requested_time, samples_[k].time, samples_[k].error});
  }

  void report(StageObservations& o) const override {
    if (!reports_) return;
    o.channel = true;
    o.profile_error = largest_;
    o.profile_samples = samples_;
  }

 private:
  void sample(Sim& sim, double sample_time) {
    std::string rows;
    const double e = sim.communicator().max(channel_profile_error(sim, reference_, sample_time, rows));
    const std::string all = sim.communicator().gather_text(rows);
    if (csv_.stream()) *csv_.stream() << all;
    csv_.check();
    largest_ = std::max(largest_, e);
    samples_.push_back({sample_time, sim.time(), e});
    rows_ += sim.fluid_particles();
  }

  ChannelFlow reference_;
  std::vector<double> times_;
  size_t next_ = 0;
  HistoryFile csv_;
  long long rows_, scheduled_rows_;  // all rows, and those of the scheduled samples (what a checkpoint counts)
  double largest_ = 0;
  std::vector<ProfileSample> samples_;
  size_t scheduled_samples_ = 0;
  bool reports_ = true;  // into the summary (the finest level's)
};

}  // namespace poresph
