#include "app/Run.hpp"

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>

#include "app/Simulation.hpp"
#include "core/ExecutionSpaces.hpp"
#include "diagnostics/ChannelFlow.hpp"

namespace poresph {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// "step 1200  t = 1.2e-02 s  40.0 %  ETA 3 s", rewritten in place at most
// four times a second; nothing at all when disabled (logs stay quiet).
class ProgressLine {
 public:
  explicit ProgressLine(bool enabled) : enabled_(enabled), start_(Clock::now()), last_(start_) {}
  void update(long long step, double time, double fraction) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last_).count() < 0.25) return;
    last_ = now;
    const double elapsed = seconds_since(start_);
    const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0.0;
    std::printf("\rstep %lld  t = %.4e s  %5.1f %%  ETA %.0f s   ", step, time, 100 * fraction, eta);
    std::fflush(stdout);
    printed_ = true;
  }
  void finish() {
    if (printed_) std::printf("\n");
  }

 private:
  bool enabled_, printed_ = false;
  Clock::time_point start_, last_;
};

// Compares v_x of every fluid particle with the series solution at the
// particles' current time; appends the points to `csv` for plots.
template <int Dim, class ExecSpace>
double channel_profile_error(const Simulation<Dim, ExecSpace>& sim, const ChannelFlow& reference, double sample_time,
                             std::ofstream& csv) {
  const auto& P = sim.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  const double t = sim.time(), scale = reference.steady_peak();
  double worst = 0.0;
  for (int i = 0; i < P.owned; ++i) {
    if (kind(i) != kFluid) continue;
    const double series = reference.velocity(x(i, 1), t);
    worst = std::max(worst, std::abs(v(i, 0) - series) / scale);
    csv << sample_time << ',' << t << ',' << x(i, 1) << ',' << v(i, 0) << ',' << series << '\n';
  }
  return worst;
}

template <int Dim, class ExecSpace>
RunReport run(const SceneConfig& scene, const RunOptions& options) {
  const auto setup_start = Clock::now();
  Simulation<Dim, ExecSpace> sim(scene);
  const double setup_seconds = seconds_since(setup_start);
  const double dt = sim.time_step();

  const bool channel = scene.walls == WallType::Channel;
  const ChannelFlow reference{scene.cell_size[1], scene.kinematic_viscosity, scene.body_force[0],
                              scene.lower_wall_velocity, scene.upper_wall_velocity};
  std::vector<double> samples = scene.profile_sample_times;
  std::sort(samples.begin(), samples.end());
  size_t next_sample = 0;
  RunReport report;
  std::ofstream profile_csv;
  if (channel) {
    profile_csv.open(options.output_dir + "/profiles.csv");
    profile_csv.precision(10);
    profile_csv << "sample_time,time,y,v_x,v_x_series\n";
  }
  auto sample_profile = [&](double sample_time) {
    const double e = channel_profile_error(sim, reference, sample_time, profile_csv);
    report.profile_error = std::max(report.profile_error, e);
    report.profile_samples.push_back({sample_time, sim.time(), e});
  };

  bool show_progress = scene.progress == ProgressMode::Always ||
                       (scene.progress == ProgressMode::Auto && options.progress_on_terminal);
  ProgressLine progress(show_progress);
  // Steps are counted, not times summed: the run ends on the step nearest End Time.
  const long long steps_to_end = std::max(1LL, static_cast<long long>(std::llround(scene.end_time / dt)));
  const long long last_step = scene.max_steps > 0 ? std::min(steps_to_end, scene.max_steps) : steps_to_end;
  const auto loop_start = Clock::now();
  while (sim.steps() < last_step) {
    sim.step();
    // Sample at the first step at or past each requested time; the series is
    // evaluated at the particles' own time, so no interpolation enters.
    while (channel && next_sample < samples.size() && sim.time() >= samples[next_sample] - 0.5 * dt)
      sample_profile(samples[next_sample++]);
    progress.update(sim.steps(), sim.time(), static_cast<double>(sim.steps()) / last_step);
  }
  const double loop_seconds = seconds_since(loop_start);
  progress.finish();
  if (channel) sample_profile(sim.time());

  const auto& derived = sim.derived();
  report.scene = scene.name;
  report.dimension = Dim;
  report.fluid_particles = sim.fluid_particles();
  report.boundary_particles = sim.boundary_particles();
  report.steps = sim.steps();
  report.simulated_time = sim.time();
  report.stopped_by = sim.steps() >= steps_to_end ? "end_time" : "max_steps";
  report.time_step = dt;
  report.smoothing_length = derived.smoothing_length;
  report.sound_speed = derived.sound_speed;
  report.wall_seconds = loop_seconds;
  report.setup_seconds = setup_seconds;
  const double particle_steps = static_cast<double>(sim.particles().owned) * sim.steps();
  report.particle_steps_per_second = loop_seconds > 0 ? particle_steps / loop_seconds : 0.0;
  report.ranks = 1;
  report.threads = ExecSpace::concurrency();
  report.backend = backend_name<ExecSpace>();
  report.max_density_variation = sim.max_density_variation();
  report.channel = channel;
  return report;
}

}  // namespace

JsonObject RunReport::to_json() const {
  JsonObject json;
  json.add("scene", scene)
      .add("dimension", dimension)
      .add("fluid_particles", fluid_particles)
      .add("boundary_particles", boundary_particles)
      .add("steps", steps)
      .add("simulated_time", simulated_time)
      .add("stopped_by", stopped_by)
      .add("time_step", time_step)
      .add("smoothing_length", smoothing_length)
      .add("sound_speed", sound_speed)
      .add("wall_seconds", wall_seconds)
      .add("setup_seconds", setup_seconds)
      .add("particle_steps_per_second", particle_steps_per_second)
      .add("ranks", ranks)
      .add("threads", threads)
      .add("backend", backend)
      .add("max_density_variation", max_density_variation);
  if (channel) {
    std::vector<JsonObject> samples;
    for (const auto& s : profile_samples)
      samples.push_back(JsonObject().add("sample_time", s.requested_time).add("time", s.time).add("error", s.error));
    json.add("profile_error", profile_error).add("profile_samples", samples);
  }
  return json;
}

RunReport run_scene(const SceneConfig& scene, const RunOptions& options) {
  using Space = Kokkos::DefaultHostExecutionSpace;
  const RunReport report = scene.dimension == 2 ? run<2, Space>(scene, options) : run<3, Space>(scene, options);
  write_file_atomically(options.output_dir + "/summary.json", report.to_json().str() + "\n");
  return report;
}

}  // namespace poresph
