#include "app/Run.hpp"

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "app/SceneCheck.hpp"
#include "app/Simulation.hpp"
#include "core/ExecutionSpaces.hpp"
#include "diagnostics/ChannelFlow.hpp"
#include "diagnostics/PermeabilityMonitor.hpp"
#include "geometry/Grains.hpp"
#include "io/Checkpoint.hpp"
#include "io/FieldWriter.hpp"
#include "io/HistoryFile.hpp"
#include "io/OutputDirectory.hpp"
#include "io/ProgressLine.hpp"
#include "parallel/Communicator.hpp"

namespace poresph {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Compares v_x of every fluid particle with the series solution at the
// particles' current time; appends the points to `csv` (rank 0) for plots.
template <int Dim, class ExecSpace>
double channel_profile_error(const Simulation<Dim, ExecSpace>& sim, const ChannelFlow& reference, double sample_time,
                             std::ofstream& csv) {
  const auto& P = sim.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  const double t = sim.time(), scale = reference.steady_peak();
  double worst = 0.0;
  std::string rows;
  char buffer[160];
  for (int i = 0; i < P.owned; ++i) {
    if (kind(i) != kFluid) continue;
    const double series = reference.velocity(x(i, 1), t);
    worst = std::max(worst, std::abs(v(i, 0) - series) / scale);
    std::snprintf(buffer, sizeof buffer, "%.10g,%.10g,%.10g,%.10g,%.10g\n", sample_time, t, x(i, 1), v(i, 0), series);
    rows += buffer;
  }
  const std::string all = sim.communicator().gather_text(rows);
  if (csv.is_open()) csv << all;
  return sim.communicator().max(worst);
}

// The owned particles' state as CSV, for plots: one row a particle.
template <int Dim, class ExecSpace>
void write_particles_csv(const Simulation<Dim, ExecSpace>& sim, const std::string& path) {
  const auto& P = sim.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto rho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.rho);
  auto p = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.p);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.id);
  const auto& scene = sim.scene();
  std::string header = "id,kind";
  for (int d = 0; d < Dim; ++d) header += std::string(",") + "xyz"[d];
  for (int d = 0; d < Dim; ++d) header += std::string(",v") + "xyz"[d];
  header += ",rho,p\n";
  std::string text;
  char buffer[64];
  for (int i = 0; i < P.owned; ++i) {
    text += std::to_string(id(i)) + "," + std::to_string(kind(i));
    for (int d = 0; d < Dim; ++d) {
      // Positions stay unwrapped between neighbour-list rebuilds: wrap for output.
      double xd = x(i, d);
      if (scene.periodic[d]) xd -= scene.cell_size[d] * std::floor(xd / scene.cell_size[d]);
      std::snprintf(buffer, sizeof buffer, ",%.10g", xd);
      text += buffer;
    }
    for (int d = 0; d < Dim; ++d) std::snprintf(buffer, sizeof buffer, ",%.10g", v(i, d)), text += buffer;
    std::snprintf(buffer, sizeof buffer, ",%.12g,%.10g\n", rho(i), p(i));
    text += buffer;
  }
  const std::string all = sim.communicator().gather_text(text);
  if (sim.communicator().rank() == 0) write_file_atomically(path, header + all);
}

// The one axis a body force points along, or -1 if it has several components.
int force_axis(const SceneConfig& scene) {
  int axis = -1;
  for (int d = 0; d < scene.dimension; ++d) {
    if (scene.body_force[d] == 0) continue;
    if (axis >= 0) return -1;
    axis = d;
  }
  return axis;
}

// Set by the SIGINT/SIGTERM handler, read by the time loop.
volatile std::sig_atomic_t stop_signal = 0;

extern "C" void request_stop(int signal_number) { stop_signal = signal_number; }

// One run of the scene as given (drive_axis < 0) or with |F| along drive_axis.
template <int Dim, class ExecSpace>
void run_once(SceneConfig scene, int drive_axis, const RunOptions& options, RunReport& report,
              const CheckpointInfo* resume_from, const std::function<void()>& claim_output,
              const std::string& fingerprint, bool in_place) {
  double force_norm = 0;
  for (int d = 0; d < Dim; ++d) force_norm += scene.body_force[d] * scene.body_force[d];
  force_norm = std::sqrt(force_norm);
  if (drive_axis >= 0) {
    scene.body_force = {0, 0, 0};
    scene.body_force[drive_axis] = force_norm;
  }
  const int axis = force_axis(scene);

  const auto setup_start = Clock::now();
  const Communicator world;
  using Sim = Simulation<Dim, ExecSpace>;
  Sim sim(scene, ExecSpace(), world, resume_from ? Sim::Start::Empty : Sim::Start::Lattice,
          resume_from ? checkpoint_boxes<Dim>(*resume_from, world.size()) : std::vector<Box<Dim>>{});
  if (resume_from) {
    load_checkpoint<Dim>(sim, options.restart_file, *resume_from);
    report.restarted_from_step = sim.steps();
  }
  report.setup_seconds += seconds_since(setup_start);
  // A signal during set-up stops the run before it writes anything.
  if (sim.communicator().any(stop_signal != 0)) {
    const int signal_number = sim.communicator().max(static_cast<int>(stop_signal));
    throw RunInterrupted("stopped by " + std::string(signal_number == SIGINT ? "SIGINT" : "SIGTERM") +
                             " during set-up, before the first step",
                         signal_number);
  }
  claim_output();
  const bool root = sim.communicator().rank() == 0;
  const double dt = sim.time_step();
  // A run continued in its own directory goes on with its files: the
  // history rows and field frames up to the checkpoint, none after it.
  const bool continuing = resume_from && in_place;
  const std::string suffix = drive_axis >= 0 ? std::string("_") + "xyz"[drive_axis] : "";
  if (continuing && root) remove_other_frames(options.output_dir, suffix, resume_from->state.frame_steps);

  // Channel start-up profiles (body force along x or moving walls).
  const bool channel = scene.walls == WallType::Channel && drive_axis <= 0;
  const ChannelFlow reference{scene.cell_size[1], scene.kinematic_viscosity, scene.body_force[0],
                              scene.lower_wall_velocity, scene.upper_wall_velocity};
  std::vector<double> samples = scene.profile_sample_times;
  std::sort(samples.begin(), samples.end());
  size_t next_sample = 0;
  while (next_sample < samples.size() && sim.time() >= samples[next_sample] - 0.5 * dt) ++next_sample;
  HistoryFile profile_csv;
  // Rows of the history files so far, counted on every process for the checkpoint.
  long long profile_rows = continuing ? static_cast<long long>(resume_from->state.profile_rows) : 0;
  if (channel && root) {
    profile_csv.open(options.output_dir + "/profiles.csv", "sample_time,time,y,v_x,v_x_series\n", continuing,
                     profile_rows);
    profile_csv.file().precision(10);
  }
  auto sample_profile = [&](double sample_time) {
    const double e = channel_profile_error(sim, reference, sample_time, profile_csv.file());
    profile_csv.check();
    report.profile_error = std::max(report.profile_error, e);
    report.profile_samples.push_back({sample_time, sim.time(), e});
    profile_rows += sim.fluid_particles();
  };

  // Permeability along the driving axis, checked every few steps; the
  // steady-state test compares values at least the flow's spin-up time apart.
  const bool measure_k = axis >= 0 && scene.kinematic_viscosity > 0;
  double largest_side = 0;
  for (int d = 0; d < Dim; ++d) largest_side = std::max(largest_side, scene.cell_size[d]);
  PermeabilityMonitor<Dim> monitor(axis, scene.kinematic_viscosity, force_norm, report.porosity,
                                   largest_side / sim.derived().sound_speed, scene.steady_window,
                                   scene.steady_tolerance);
  if (resume_from)
    monitor.detector().restore(resume_from->state.steady_first_time, resume_from->state.steady_times,
                               resume_from->state.steady_values);
  // Often enough to follow the shortest window or spin-up time (which is at
  // most L^2 / (8 nu), the Poiseuille bound of the velocity scale), rarely
  // enough to cost nothing.
  const double shortest_scale = scene.steady_window > 0 ? scene.steady_window : sim.derived().length_scale *
                                                                                    sim.derived().length_scale /
                                                                                    (8 * scene.kinematic_viscosity);
  // Clamped as a double: a long time scale over a short step would overflow the conversion.
  const long long check_interval =
      static_cast<long long>(std::clamp(std::floor(shortest_scale / (20 * dt)), 1.0, 100.0));
  HistoryFile history;
  long long history_rows = continuing ? static_cast<long long>(resume_from->state.history_rows) : 0;
  if (measure_k && root) {
    std::ostringstream header;
    PermeabilityMonitor<Dim>::write_header(header, axis);
    history.open(options.output_dir + "/permeability_history" + suffix + ".csv", header.str(), continuing,
                 history_rows);
    history.file().precision(10);
  }
  long long last_check = -1;  // the step of the last check, which the end of the run does not repeat in the history
  // The rows of the scheduled checks and samples: what a checkpoint counts. The
  // end of a run adds a row of its own that a run continued past it drops.
  long long scheduled_history_rows = history_rows, scheduled_profile_rows = profile_rows;
  auto check = [&]() {
    const auto density = sim.density_statistics();
    report.max_density_variation = std::max(report.max_density_variation, density.max_variation);
    report.max_density_drift = std::max(report.max_density_drift, std::abs(density.mean_drift));
    const auto inside = sim.fluid_inside_grains();
    report.particles_inside_grains = std::max(report.particles_inside_grains, inside.particles);
    report.max_grain_penetration =
        std::max(report.max_grain_penetration, inside.max_depth / scene.particle_spacing);
    if (!measure_k) return;
    // A check at a step already checked (the end of a run on a checking step)
    // samples k again, as before, but writes no second row.
    const bool new_row = sim.steps() != last_check;
    monitor.sample(sim.steps(), sim.time(), sim.superficial_velocity(), new_row ? history.stream() : nullptr);
    history.check();
    history_rows += new_row;
    last_check = sim.steps();
  };

  // Fluid put back on grain surfaces: the report's count from earlier runs
  // of the scene plus this process's, and the deepest (in spacings).
  auto corrections_so_far = [&]() {
    const auto corrected = sim.grain_surface_corrections();
    return std::make_pair(report.grain_surface_corrections + corrected.particles,
                          std::max(report.max_corrected_depth, corrected.max_depth / scene.particle_spacing));
  };

  // Field files, and checkpoints with what a restart needs to go on.
  FieldWriter<Dim> fields(scene, options.output_dir, suffix);
  const bool write_fields = scene.field_interval > 0;
  if (continuing)
    fields.add_earlier_frames(resume_from->state.frame_steps, resume_from->state.frame_times,
                              sim.fluid_particles() + sim.boundary_particles());
  else if (write_fields && !resume_from)
    fields.write(sim);
  // Frames on the schedule: what a checkpoint lists (the end of a run adds one
  // of its own, which a run continued past it drops).
  size_t scheduled_frames = fields.frame_steps().size();
  // The next frame is due where the run would have written it had it not
  // stopped: the saved time (under the same interval), not one rounded from
  // the checkpoint's time, which skipped a frame.
  double next_field_time = INFINITY;
  if (write_fields)
    next_field_time = resume_from && resume_from->state.field_interval == scene.field_interval
                          ? resume_from->state.next_field_time
                          : (std::floor(sim.time() / scene.field_interval + 0.5) + 1) * scene.field_interval;
  const std::string checkpoint_path = options.output_dir + "/checkpoint.h5";
  auto checkpoint = [&](bool rates_valid) {
    RunState state;
    state.drive_axis = drive_axis;
    for (int j = 0; j < Dim; ++j) {
      if (!report.driven[j] || j == axis) continue;
      state.completed_columns.push_back(j);
      for (int i = 0; i < Dim; ++i) state.completed_columns.push_back(report.permeability[i][j]);
      state.completed_columns.push_back(report.steady);
    }
    monitor.detector().save(state.steady_times, state.steady_values);
    state.steady_first_time = monitor.detector().first_time();
    state.frame_steps.assign(fields.frame_steps().begin(), fields.frame_steps().begin() + scheduled_frames);
    state.frame_times.assign(fields.frame_times().begin(), fields.frame_times().begin() + scheduled_frames);
    state.field_interval = scene.field_interval;
    state.next_field_time = next_field_time;
    state.history_rows = static_cast<double>(scheduled_history_rows);
    state.profile_rows = static_cast<double>(scheduled_profile_rows);
    state.max_density_variation = report.max_density_variation;
    state.max_density_drift = report.max_density_drift;
    state.particles_inside_grains = static_cast<double>(report.particles_inside_grains);
    state.max_grain_penetration = report.max_grain_penetration;
    const auto [corrections, deepest] = corrections_so_far();
    state.grain_surface_corrections = static_cast<double>(corrections);
    state.max_corrected_depth = deepest;
    write_checkpoint<Dim>(sim, checkpoint_path, state, options.parameters_xml, fingerprint, rates_valid);
  };

  const bool show_progress = root && (scene.progress == ProgressMode::Always ||
                                     (scene.progress == ProgressMode::Auto && options.progress_on_terminal));
  ProgressLine progress(show_progress);
  const char* label = drive_axis == 0 ? "[F along x] " : drive_axis == 1 ? "[F along y] " : drive_axis == 2 ? "[F along z] " : "";
  // Steps are counted, not times summed: the run ends on the step nearest End Time.
  // Checked (SceneCheck.hpp): a count that wrapped would end the run after one step.
  const long long last_step = poresph::last_step(scene.end_time, dt, scene.max_steps);
  const long long steps_to_end = steps_to_end_time(scene.end_time, dt);
  const bool stop_when_steady = measure_k && scene.steady_tolerance > 0;
  // A signal is seen by one process; all stop together at the next agreement.
  constexpr long long kSignalCheckInterval = 10;
  const long long first_step = sim.steps();
  const auto loop_start = Clock::now();
  // What summary.json says of this run, however it ends: at the end, at a
  // steady k, by a signal or by a failure (k as of the last check).
  auto record = [&](const std::string& stopped_by, double loop_seconds) {
    const auto& derived = sim.derived();
    report.stopped_by = stopped_by;
    report.dimension = Dim;
    report.fluid_particles = sim.fluid_particles();
    report.boundary_particles = sim.boundary_particles();
    report.steps += sim.steps();
    report.timed_steps += sim.steps() - first_step;
    report.simulated_time += sim.time();
    report.time_step = dt;
    report.smoothing_length = derived.smoothing_length;
    report.sound_speed = derived.sound_speed;
    report.wall_seconds += loop_seconds;  // the time loop only
    report.ranks = sim.communicator().size();
    report.threads = ExecSpace::concurrency();
    report.backend = backend_name<ExecSpace>();
    report.neighbour_rebuilds += sim.neighbour_rebuilds();
    report.neighbours_per_particle = sim.neighbours_per_particle();
    report.channel = report.channel || channel;
    std::tie(report.grain_surface_corrections, report.max_corrected_depth) = corrections_so_far();
    if (measure_k && monitor.measured()) {
      const bool first = !report.has_permeability;
      report.has_permeability = true;
      report.driven[axis] = true;
      for (int i = 0; i < Dim; ++i) {
        report.permeability[i][axis] = monitor.permeability(i);
        if (first) report.superficial_velocity[i] = monitor.superficial_velocity()[i];
      }
      report.steady = (first || report.steady) && monitor.steady();
      const auto& detector = monitor.detector();
      report.steady_relative_change = std::max(report.steady_relative_change, detector.relative_change());
      report.steady_remaining_change = std::max(report.steady_remaining_change, detector.remaining_change());
    }
  };
  try {
    while (sim.steps() < last_step) {
      if (sim.steps() + 1 == options.inject_nan_at_step) sim.poison_next_step();
      sim.step();
      // Sample at the first step at or past each requested time; the series is
      // evaluated at the particles' own time, so no interpolation enters.
      while (channel && next_sample < samples.size() && sim.time() >= samples[next_sample] - 0.5 * dt)
        sample_profile(samples[next_sample++]);
      scheduled_profile_rows = profile_rows;
      if (sim.steps() % check_interval == 0) {
        check();
        scheduled_history_rows = history_rows;
        if (stop_when_steady && monitor.steady()) break;
      }
      if (sim.time() >= next_field_time - 0.5 * dt) {
        fields.write(sim);
        scheduled_frames = fields.frame_steps().size();
        next_field_time += scene.field_interval;
      }
      if (scene.checkpoint_interval > 0 && sim.steps() % scene.checkpoint_interval == 0) checkpoint(true);
      // Also at the last step, so that a signal in its final few steps is not lost.
      if ((sim.steps() % kSignalCheckInterval == 0 || sim.steps() == last_step) &&
          sim.communicator().any(stop_signal != 0)) {
        const int signal_number = sim.communicator().max(static_cast<int>(stop_signal));
        progress.finish();
        checkpoint(true);
        record("signal", seconds_since(loop_start));
        throw RunInterrupted("stopped by " + std::string(signal_number == SIGINT ? "SIGINT" : "SIGTERM") +
                                 " at step " + std::to_string(sim.steps()) + ", t = " + std::to_string(sim.time()) +
                                 " s; the state is in " + checkpoint_path,
                             signal_number);
      }
      if (show_progress) {
        ProgressStatus status;
        status.step = sim.steps();
        status.time = sim.time();
        status.fraction_of_end = static_cast<double>(sim.steps()) / last_step;
        if (measure_k && monitor.measured()) {
          status.has_permeability = true;
          status.permeability = monitor.permeability(axis);
          status.remaining_change = monitor.detector().remaining_change();
          if (stop_when_steady) status.steady_time = monitor.detector().predicted_steady_time();
        }
        progress.update(label, status);
      }
    }
  } catch (const SimulationFailure& failure) {
    progress.finish();
    sim.rewind_failed_step();
    std::string saved = "; the last good state (step " + std::to_string(sim.steps()) + ") is in " + checkpoint_path;
    try {
      checkpoint(false);
    } catch (const std::exception& error) {  // the failure is still the news; the lost checkpoint is said too
      saved = "; the last good state (step " + std::to_string(sim.steps()) + ") could not be saved: " + error.what();
    }
    record("failure", seconds_since(loop_start));
    report.failure = std::string(failure.what()) + saved;
    throw SimulationFailure(report.failure, failure.step, failure.time);
  } catch (const RunInterrupted&) {
    throw;
  } catch (const std::exception& error) {  // a file that could not be written: summary.json says so
    progress.finish();
    record("error", seconds_since(loop_start));
    report.failure = error.what();
    throw;
  }
  const double loop_seconds = seconds_since(loop_start);
  progress.finish();
  check();
  if (channel) sample_profile(sim.time());
  // Recorded before the last files are written: if one of them fails, summary.json still describes the run.
  record(stop_when_steady && monitor.steady() ? "steady_state" : sim.steps() >= steps_to_end ? "end_time" : "max_steps",
         loop_seconds);
  if (scene.write_final_particles) write_particles_csv(sim, options.output_dir + "/particles" + suffix + ".csv");
  if (write_fields && fields.frame_steps().back() != sim.steps()) fields.write(sim);
  if (scene.final_checkpoint) checkpoint(true);
}

template <int Dim, class ExecSpace>
RunReport run(const SceneConfig& scene, const RunOptions& options) {
  RunReport report;
  report.scene = scene.name;
  report.warnings = scene.warnings;
  report.setup_seconds = options.setup_seconds_before;
  bool output_claimed = false;
  const std::function<void()> claim_output = [&]() {
    if (output_claimed) return;
    if (options.prepare_output) options.prepare_output();
    output_claimed = true;
  };
  report.has_grains = !scene.grains.empty();
  report.porosity = porosity(scene.grains, scene);
  // What defines the physics, recorded in every checkpoint and compared with a restart's.
  const auto derived = derive_parameters(scene);
  const std::string fingerprint = physics_fingerprint(scene, derived.time_step, derived.sound_speed);
  std::optional<CheckpointInfo> resume_from;
  bool in_place = false;
  if (!options.restart_file.empty()) {
    resume_from = read_checkpoint_info(options.restart_file, MPI_COMM_WORLD);
    check_checkpoint_matches(*resume_from, options.restart_file, fingerprint);
    std::error_code error;
    in_place = std::filesystem::equivalent(std::filesystem::absolute(options.restart_file).parent_path(),
                                           options.output_dir, error);
    const auto& st = resume_from->state;
    report.max_density_variation = st.max_density_variation;
    report.max_density_drift = st.max_density_drift;
    report.particles_inside_grains = static_cast<long long>(st.particles_inside_grains);
    report.max_grain_penetration = st.max_grain_penetration;
    report.grain_surface_corrections = static_cast<long long>(st.grain_surface_corrections);
    report.max_corrected_depth = st.max_corrected_depth;
    // Columns of the tensor already finished before the checkpoint.
    for (size_t k = 0; k + Dim + 2 <= st.completed_columns.size(); k += Dim + 2) {
      const int j = static_cast<int>(st.completed_columns[k]);
      report.has_permeability = report.driven[j] = true;
      for (int i = 0; i < Dim; ++i) report.permeability[i][j] = st.completed_columns[k + 1 + i];
      report.steady = st.completed_columns[k + Dim + 1] != 0;
    }
  }
  const CheckpointInfo* pending = resume_from ? &*resume_from : nullptr;
  auto run_axis = [&](int axis) {
    if (pending && pending->state.drive_axis != axis) return;  // finished before the checkpoint
    run_once<Dim, ExecSpace>(scene, axis, options, report, pending, claim_output, fingerprint, in_place);
    pending = nullptr;
  };
  auto write_summary = [&]() {
    report.particle_steps_per_second =
        report.wall_seconds > 0
            ? (report.fluid_particles + report.boundary_particles) * report.timed_steps / report.wall_seconds
            : 0.0;
    if (report.has_grains && report.has_permeability) {
      double speed = 0, diameter = 0;
      for (int d = 0; d < Dim; ++d) speed += report.superficial_velocity[d] * report.superficial_velocity[d];
      for (const auto& g : scene.grains) diameter += 2 * g.radius / scene.grains.size();
      report.reynolds_number = std::sqrt(speed) / report.porosity * diameter / scene.kinematic_viscosity;
    }
    if (Communicator().rank() == 0) write_summary_file(options.output_dir + "/summary.json", report.to_json().str() + "\n");
  };
  // summary.json at every ending once the directory is claimed, a failed write
  // included; what stopped the run stays the message, with the summary's own
  // failure added to it.
  auto summary_problem = [&]() -> std::string {
    try {
      write_summary();
      return "";
    } catch (const std::exception& error) {
      return std::string("; ") + error.what();
    }
  };
  try {
    // The fingerprint's Permeability/Tensor line guarantees that the checkpoint's axis fits.
    if (scene.permeability_tensor) {
      for (int axis = 0; axis < Dim; ++axis) run_axis(axis);
    } else {
      run_axis(-1);
    }
  } catch (const SimulationFailure& failure) {
    // What was measured up to the failure, and the failure itself.
    throw SimulationFailure(failure.what() + summary_problem(), failure.step, failure.time);
  } catch (const RunInterrupted& interrupted) {
    // Interrupted during the first set-up: nothing was written, nor is now.
    if (!output_claimed)
      throw RunInterrupted(std::string(interrupted.what()) + "; nothing was written", interrupted.signal_number);
    throw RunInterrupted(interrupted.what() + summary_problem(), interrupted.signal_number);
  } catch (const std::exception& error) {
    if (!output_claimed) throw;  // refused during set-up: nothing is written
    if (report.stopped_by.empty()) report.stopped_by = "error";
    if (report.failure.empty()) report.failure = error.what();
    throw std::runtime_error(error.what() + summary_problem());
  }
  write_summary();
  return report;
}

}  // namespace

void install_stop_signal_handlers() {
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
}

int stop_signal_received() { return Communicator().max(static_cast<int>(stop_signal)); }

JsonObject RunReport::to_json() const {
  JsonObject json;
  json.add("scene", scene)
      .add("dimension", dimension)
      .add("fluid_particles", fluid_particles)
      .add("boundary_particles", boundary_particles)
      .add("steps", steps)
      .add("simulated_time", simulated_time)
      .add("poresph_version", std::string(PORESPH_VERSION))
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
      .add("max_density_variation", max_density_variation)
      .add("max_density_drift", max_density_drift)
      .add("neighbour_rebuilds", neighbour_rebuilds)
      .add("neighbours_per_particle", neighbours_per_particle);
  if (channel) {
    std::vector<JsonObject> samples;
    for (const auto& s : profile_samples)
      samples.push_back(JsonObject().add("sample_time", s.requested_time).add("time", s.time).add("error", s.error));
    json.add("profile_error", profile_error).add("profile_samples", samples);
  }
  if (has_permeability) {
    const char* axis = "xyz";
    JsonObject k, u;
    for (int j = 0; j < dimension; ++j)
      if (driven[j])
        for (int i = 0; i < dimension; ++i) k.add(std::string("k") + axis[i] + axis[j], permeability[i][j]);
    for (int i = 0; i < dimension; ++i) u.add(std::string(1, axis[i]), superficial_velocity[i]);
    json.add("permeability", k)
        .add("superficial_velocity", u)
        .add("steady", steady)
        .add("steady_relative_change", steady_relative_change)
        .add("steady_remaining_change", steady_remaining_change);
  }
  if (!failure.empty()) json.add("failure", failure);
  json.add("warnings", warnings);
  if (restarted_from_step >= 0) json.add("restarted_from_step", restarted_from_step);
  json.add("porosity", porosity);
  if (has_grains) {
    json.add("particles_inside_grains", particles_inside_grains)
        .add("max_grain_penetration", max_grain_penetration)
        .add("grain_surface_corrections", grain_surface_corrections)
        .add("max_corrected_depth", max_corrected_depth);
    if (has_permeability) json.add("reynolds_number", reynolds_number);
  }
  return json;
}

template <class Space>
RunReport run_on(const SceneConfig& scene, const RunOptions& options) {
  return scene.dimension == 2 ? run<2, Space>(scene, options) : run<3, Space>(scene, options);
}

std::string backend_for(const SceneConfig& scene) {
#ifdef KOKKOS_ENABLE_OPENMP
  if (scene.backend == Backend::OpenMP) return backend_name<Kokkos::OpenMP>();
#endif
  if (scene.backend == Backend::Serial) return backend_name<Kokkos::Serial>();
  return backend_name<Kokkos::DefaultHostExecutionSpace>();
}

int threads_for(const SceneConfig& scene) {
#ifdef KOKKOS_ENABLE_OPENMP
  if (scene.backend == Backend::OpenMP) return Kokkos::OpenMP::concurrency();
#endif
  if (scene.backend == Backend::Serial) return 1;
  return Kokkos::DefaultHostExecutionSpace::concurrency();
}

RunReport run_scene(const SceneConfig& scene, const RunOptions& options) {
  RunReport report;
  if (scene.backend == Backend::Serial) {
    report = run_on<Kokkos::Serial>(scene, options);
  } else if (scene.backend == Backend::OpenMP) {
#ifdef KOKKOS_ENABLE_OPENMP
    report = run_on<Kokkos::OpenMP>(scene, options);
#else
    throw std::invalid_argument(
        "Run/Backend = openmp, but this build's Kokkos has no OpenMP backend (Debian's is Serial only); "
        "build one with scripts/build-trilinos-openmp.sh and configure with cmake --preset openmp");
#endif
  } else {
    report = run_on<Kokkos::DefaultHostExecutionSpace>(scene, options);
  }
  return report;
}

}  // namespace poresph
