#pragma once
// One stage of a run (app/RunPlan.hpp): the simulation at the stage's
// spacing and force, started from the lattice, the end of the stage before
// it or a checkpoint, and the time loop that steps it and calls its
// observers (diagnostics/Observer.hpp), each in its own file and made by the
// list of app/StageObservers.hpp: the channel profile probe, the health
// watch, the permeability probe with the steady-state stop, the field files,
// the checkpoints and the progress line. What they measured comes back
// through Observer::report into the stage's record and summary.json.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <functional>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/Run.hpp"
#include "app/RunPlan.hpp"
#include "app/SceneCheck.hpp"
#include "app/Simulation.hpp"
#include "app/StageObservers.hpp"
#include "app/StageRecord.hpp"
#include "core/ExecutionSpaces.hpp"
#include "io/Checkpoint.hpp"
#include "io/OutputDirectory.hpp"
#include "io/ParticlesCsv.hpp"
#include "solver/SteadySolver.hpp"

namespace poresph {

// What the health watch has seen, as the report keeps it, both ways.
inline HealthRecord health_of(const RunReport& report) {
  return {report.max_density_variation, report.max_density_drift, report.particles_inside_grains,
          report.max_grain_penetration, report.grain_surface_corrections, report.max_corrected_depth};
}
inline void record_health(RunReport& report, const HealthRecord& health) {
  report.max_density_variation = health.max_density_variation;
  report.max_density_drift = health.max_density_drift;
  report.particles_inside_grains = health.particles_inside_grains;
  report.max_grain_penetration = health.max_grain_penetration;
  report.grain_surface_corrections = health.grain_surface_corrections;
  report.max_corrected_depth = health.max_corrected_depth;
}

// The fingerprint of a stage's physics, which its checkpoints carry.
inline std::string stage_fingerprint(const SceneConfig& scene) {
  const auto derived = derive_parameters(scene);
  return physics_fingerprint(scene, derived.time_step, derived.sound_speed);
}

// What a stage needs from the run around it.
struct StageContext {
  const RunOptions& options;
  const std::function<void()>& claim_output;  // before the first file is written
  bool in_place = false;                      // a restart continuing in its own directory
  double porosity = 1;
};

template <int Dim, class ExecSpace>
class StageLoop {
 public:
  using Sim = Simulation<Dim, ExecSpace>;
  using Clock = std::chrono::steady_clock;

  // Runs stage `index` of `stages` of `scene`; warm_from: the stage before
  // it, when this one starts from its end (released once it has served);
  // resume: a checkpoint of this stage. Adds to `report` and `records`;
  // returns the simulation at its end.
  static std::unique_ptr<Sim> run(const SceneConfig& base, const std::vector<Stage>& stages, int index,
                                  const StageContext& context, std::unique_ptr<Sim> warm_from,
                                  const CheckpointInfo* resume, std::vector<StageRecord>& records, RunReport& report) {
    StageLoop loop(base, stages, index, context, std::move(warm_from), resume, records, report);
    loop.time_loop();
    return std::move(loop.sim_);
  }

 private:
  StageLoop(const SceneConfig& base, const std::vector<Stage>& stages, int index, const StageContext& context,
            std::unique_ptr<Sim> warm_from, const CheckpointInfo* resume, std::vector<StageRecord>& records,
            RunReport& report)
      : stage_(stages[index]), index_(index), scene_(stage_scene(base, stage_)), context_(context),
        options_(context.options), resume_(resume), records_(records), report_(report) {
    for (size_t later = index + 1; later < stages.size(); ++later) later_suffixes_.push_back(stages[later].suffix);
    records_before_ = records.size();
    const auto setup_start = Clock::now();
    const Communicator world;
    // A warm start keeps the boxes of the stage it starts from: its particles
    // and the coarser ones they are interpolated from live on the same process.
    std::vector<Box<Dim>> boxes;
    if (resume) boxes = checkpoint_boxes<Dim>(*resume, world.size());
    else if (warm_from) boxes = warm_from->decomposition().boxes();
    sim_ = std::make_unique<Sim>(scene_, ExecSpace(), world, resume ? Sim::Start::Empty : Sim::Start::Lattice, boxes);
    if (stage_.keeps_level_start) sim_->keep_level_start();
    if (resume) {
      load_checkpoint<Dim>(*sim_, options_.restart_file, *resume);
      report.restarted_from_step = sim_->steps();
    } else if (warm_from) {
      warm_from->warm_start(*sim_, stage_.warm_scale, stage_.warm_extrapolation);
    }
    // After a restart, whether the stage had started warm is in the checkpoint.
    warm_started_ = resume ? resume->state.stage_warm != 0 : warm_from != nullptr;
    warm_from.reset();  // its memory, before this stage's time loop
    report.setup_seconds += std::chrono::duration<double>(Clock::now() - setup_start).count();
    // A signal during set-up is answered before the first step (time_loop),
    // with a checkpoint of the state set up and a summary, as in the loop.
    context.claim_output();
    fingerprint_ = stage_fingerprint(scene_);
    make_observers();
  }

  void make_observers() {
    Sim& sim = *sim_;
    const auto& scene = scene_;
    const RunState* restored = resume_ ? &resume_->state : nullptr;
    const bool continuing = resume_ && context_.in_place;
    const std::string& dir = options_.output_dir;
    const bool root = sim.communicator().rank() == 0;
    // What the first attempt wrote after the checkpoint goes: its later frames, its later stages.
    if (continuing && root) remove_files_after_checkpoint(dir, stage_.suffix, restored->frame_steps, later_suffixes_);
    const double dt = sim.time_step();

    // Checks every few steps: often enough to follow the shortest window or
    // spin-up time (at most L^2 / (8 nu), the Poiseuille bound of the
    // velocity scale), rarely enough to cost nothing. Clamped as a double: a
    // long time scale over a short step would overflow the conversion.
    double shortest_scale = scene.steady_window > 0 ? scene.steady_window
                                                    : sim.derived().length_scale * sim.derived().length_scale /
                                                          (8 * scene.kinematic_viscosity);
    double largest_side = 0;
    for (int d = 0; d < Dim; ++d) largest_side = std::max(largest_side, scene.cell_size[d]);
    const double acoustic_time = largest_side / sim.derived().sound_speed;  // L / c
    // A warm start is judged on means over the acoustic period L / c: 20
    // samples in it, so that the mean is a mean and the stop is not held to
    // the next of a few checks (problem III's finest level: a check every 40
    // steps, not 100).
    if (warm_started_) shortest_scale = std::min(shortest_scale, acoustic_time);
    const long long check_interval =
        static_cast<long long>(std::clamp(std::floor(shortest_scale / (20 * dt)), 1.0, 100.0));

    axis_ = force_axis(scene);
    const bool show = root && (scene.progress == ProgressMode::Always ||
                               (scene.progress == ProgressMode::Auto && options_.progress_on_terminal));
    std::string label;
    if (stage_.levels > 1) label += "[level " + std::to_string(stage_.level + 1) + "/" + std::to_string(stage_.levels) + "] ";
    if (stage_.drive_axis >= 0) label += std::string("[F along ") + "xyz"[stage_.drive_axis] + "] ";
    if (stage_.half_force) label += "[F / 2] ";
    // The march's last step; a steady solve makes no steps (Run/End Time and Max Steps are not its).
    last_step_ = scene.steady_solver ? 0 : poresph::last_step(scene.end_time, dt, scene.max_steps);
    const StageSetting<Sim> setting{sim,
                                    scene,
                                    dir,
                                    stage_.suffix,
                                    restored,
                                    continuing,
                                    stage_.finest(),
                                    warm_started_,
                                    axis_,
                                    stage_.drive_axis,
                                    check_interval,
                                    acoustic_time,
                                    context_.porosity,
                                    health_of(report_),
                                    [this](bool rates_valid) { write_checkpoint_now(rates_valid); },
                                    show,
                                    label,
                                    last_step_,
                                    [this]() { return progress_status(); }};
    for (const auto make : stage_observers<Dim, Sim>()) {
      auto observer = make(setting);
      if (!observer) continue;
      (observer->writes() ? writers_ : probes_).push_back(observer.get());
      observers_.push_back(std::move(observer));
    }
  }

  ProgressStatus progress_status() const {
    ProgressStatus status;
    for (const auto& o : observers_) o->status(status);
    return status;
  }
  // Ends the progress line before other output.
  void end_display() {
    for (const auto& o : observers_) o->end_display();
  }
  // Whether the stage measures k (has a permeability probe).
  bool measures_permeability() const { return PermeabilityProbe<Dim, Sim>::measures(scene_, axis_); }

  void write_checkpoint_now(bool rates_valid) {
    RunState state;
    state.drive_axis = stage_.drive_axis;
    state.stage = index_;
    state.stage_warm = warm_started_;
    // The stages before this one: this one's own record (made when it ends)
    // is not final while a restart may take it on further.
    for (size_t k = 0; k < records_before_; ++k) records_[k].append_to(state.completed_stages);
    state.neighbour_rebuilds = static_cast<double>(neighbour_rebuilds());
    for (auto* o : probes_) o->save(state);
    for (auto* o : writers_) o->save(state);
    write_checkpoint<Dim>(*sim_, options_.output_dir + "/checkpoint.h5", state, options_.parameters_xml, fingerprint_,
                          rates_valid);
  }

  // Stops the run for a signal: the state as it stands, and what the stage measured.
  [[noreturn]] void stop_for(int signal_number, double loop_seconds, long long first_step) {
    end_display();
    write_checkpoint_now(true);
    record("signal", loop_seconds, first_step);
    throw RunInterrupted("stopped by " + signal_name(signal_number) + " at step " + std::to_string(sim_->steps()) +
                             ", t = " + std::to_string(sim_->time()) + " s; the state is in " + options_.output_dir +
                             "/checkpoint.h5",
                         signal_number);
  }

  // Solver/Method = steady: the stage's steady state by Newton-Krylov
  // (solver/SteadySolver.hpp) in place of the time loop; the observers see
  // its end as they see the end of a time loop.
  void steady_loop() {
    Sim& sim = *sim_;
    const long long first_step = sim.steps();
    const auto loop_start = Clock::now();
    auto seconds = [&]() { return std::chrono::duration<double>(Clock::now() - loop_start).count(); };
    if (sim.communicator().any(stop_signal_pending())) stop_for(stop_signal_received(), seconds(), first_step);
    const double force = driving_force(scene_);
    // The Newton step being solved, and where its residual estimate stood a while ago.
    int step_index = -1;
    RecentAnchor anchor;
    auto show = [&](const SteadyProgress& s) {
      const double expected = s.residual * (s.linear_residual > 0 ? s.linear_residual : 1.0);
      char text[256];
      int n = std::snprintf(text, sizeof text, "Newton %d  linear %lld  residual %.2e", s.nonlinear_iterations,
                            s.linear_iterations, expected);
      // The step's end (its residual times its linear tolerance) at the rate
      // of the step's last 20 to 40 s: a step solved past the solve's
      // tolerance, or one that settles k, still shows the time it needs,
      // and one that crawls shows a time that grows.
      const double now = seconds();
      if (s.nonlinear_iterations != step_index) step_index = s.nonlinear_iterations, anchor.restart(expected, now);
      anchor.update(expected, now);
      const double step_end = s.residual * s.linear_tolerance;
      const double eta =
          s.linear_residual > 0 ? geometric_eta(anchor.value, anchor.seconds, expected, now, step_end) : std::nan("");
      if (std::isfinite(eta)) n += std::snprintf(text + n, sizeof text - n, "  step ETA %.0f s", eta);
      if (s.inner_cap > scene_.solver.max_inner_iterations)
        n += std::snprintf(text + n, sizeof text - n, "  inner cap %d", s.inner_cap);
      if (s.dg_by_blocks) n += std::snprintf(text + n, sizeof text - n, "  DG by blocks");
      if (s.restart > scene_.solver.restart) n += std::snprintf(text + n, sizeof text - n, "  restart %d", s.restart);
      if (measures_permeability() && force != 0)
        std::snprintf(text + n, sizeof text - n, "  k = %.5e m^2",
                      scene_.kinematic_viscosity * sim.superficial_velocity()[axis_] / force);
      for (const auto& o : observers_) o->show(text);
    };
    SteadySolver<Dim, ExecSpace> solver(sim, ExecSpace(), scene_.solver,
                                        [&]() { return sim.communicator().any(stop_signal_pending()); }, show);
    try {
      steady_report_ = solver.solve();
    } catch (const std::exception& error) {  // a failed allocation, MPI: summary.json says so
      end_display();
      record("error", seconds(), first_step);
      report_.failure = error.what();
      throw;
    }
    if (steady_report_->interrupted) stop_for(stop_signal_received(), seconds(), first_step);
    const double loop_seconds = seconds();
    end_display();
    for (auto* o : probes_) o->at_end(sim);
    record(steady_report_->converged ? "steady_state" : "not_converged", loop_seconds, first_step);
    if (scene_.write_final_particles)
      write_particles_csv<Dim>(sim, options_.output_dir + "/particles" + stage_.suffix + ".csv");
    for (auto* o : writers_) o->at_end(sim);
    // An unconverged solve leaves its last state for a restart, final checkpoint asked for or not.
    if (!steady_report_->converged && !scene_.final_checkpoint) write_checkpoint_now(true);
  }

  void time_loop() {
    if (scene_.steady_solver) return steady_loop();
    Sim& sim = *sim_;
    // A signal is seen by one process; all stop together at the next agreement.
    constexpr long long kSignalCheckInterval = 10;
    const long long first_step = sim.steps();
    const auto loop_start = Clock::now();
    auto seconds = [&]() { return std::chrono::duration<double>(Clock::now() - loop_start).count(); };
    const std::string checkpoint_path = options_.output_dir + "/checkpoint.h5";
    auto stop_for_signal = [&](int signal_number) { stop_for(signal_number, seconds(), first_step); };
    try {
      // One that came during the set-up (this stage's, or the run's before it).
      if (sim.communicator().any(stop_signal_pending())) stop_for_signal(stop_signal_received());
      // Continued past where this run ends (a lower Run/Max Steps or End
      // Time than the checkpoint's state): said, not a silent empty run.
      if (resume_ && first_step > last_step_) {
        std::ostringstream msg;
        msg << "--restart: the checkpoint is at step " << first_step << " (t = " << sim.time()
            << " s), past this run's last step " << last_step_ << " (Run/Max Steps " << scene_.max_steps
            << ", Run/End Time " << scene_.end_time << " s): no step is made";
        report_.warnings.push_back(msg.str());
      }
      while (sim.steps() < last_step_) {
        if (sim.steps() + 1 == options_.inject_nan_at_step) sim.poison_next_step();
        sim.step();
        bool stop = false;
        for (auto* o : probes_) {
          o->after_step(sim);
          stop = stop || o->wants_stop();
        }
        if (stop) break;  // steady: the end writes what is left
        for (auto* o : writers_) o->after_step(sim);
        // Also at the last step, so that a signal in its final few steps is not lost.
        const bool test_interrupt = index_ == options_.interrupt_stage && sim.steps() == options_.interrupt_step;
        if (test_interrupt || ((sim.steps() % kSignalCheckInterval == 0 || sim.steps() == last_step_) &&
                               sim.communicator().any(stop_signal_pending()))) {
          stop_for_signal(test_interrupt ? SIGTERM : stop_signal_received());
        }
      }
    } catch (const SimulationFailure& failure) {
      end_display();
      sim.rewind_failed_step();
      std::string saved = "; the last good state (step " + std::to_string(sim.steps()) + ") is in " + checkpoint_path;
      try {
        write_checkpoint_now(false);
      } catch (const std::exception& error) {  // the failure is still the news; the lost checkpoint is said too
        saved = "; the last good state (step " + std::to_string(sim.steps()) + ") could not be saved: " + error.what();
      }
      record("failure", seconds(), first_step);
      report_.failure = std::string(failure.what()) + saved;
      throw SimulationFailure(report_.failure, failure.step, failure.time);
    } catch (const RunInterrupted&) {
      throw;
    } catch (const std::exception& error) {  // a file that could not be written: summary.json says so
      end_display();
      record("error", seconds(), first_step);
      report_.failure = error.what();
      throw;
    }
    const double loop_seconds = seconds();
    end_display();
    for (auto* o : probes_) o->at_end(sim);
    bool steady = false;  // a probe stopped the loop (the steady-state stop)
    for (auto* o : probes_) steady = steady || o->wants_stop();
    const long long steps_to_end = steps_to_end_time(scene_.end_time, sim.time_step());
    // Recorded before the last files are written: if one of them fails, summary.json still describes the run.
    record(steady ? "steady_state" : sim.steps() >= steps_to_end ? "end_time" : "max_steps", loop_seconds, first_step);
    if (scene_.write_final_particles)
      write_particles_csv<Dim>(sim, options_.output_dir + "/particles" + stage_.suffix + ".csv");
    for (auto* o : writers_) o->at_end(sim);
  }

  // What summary.json says of this stage, however it ends: at the end, at a
  // steady k, by a signal, a failure or an error (k as of the last check).
  void record(const std::string& stopped_by, double loop_seconds, long long first_step) {
    const Sim& sim = *sim_;
    const auto& derived = sim.derived();
    RunReport& report = report_;
    report.stopped_by = stopped_by;
    report.dimension = Dim;
    report.fluid_particles = sim.fluid_particles();
    report.boundary_particles = sim.boundary_particles();
    // The steps, time and list builds of the whole run are summed from the records (app/RunSummary.cpp).
    report.timed_steps += sim.steps() - first_step;
    report.time_step = derived.time_step;
    report.particle_spacing = scene_.particle_spacing;
    report.smoothing_length = derived.smoothing_length;
    report.sound_speed = derived.sound_speed;
    report.wall_seconds += loop_seconds;  // the time loop only
    report.ranks = sim.communicator().size();
    report.threads = ExecSpace::concurrency();
    report.backend = backend_name<ExecSpace>();
    report.neighbours_per_particle = sim.neighbours_per_particle();
    const long long ghosts = sim.ghost_particles_here();
    report.ghost_particles = sim.communicator().sum(ghosts);
    report.ghost_particles_max = sim.communicator().max(ghosts);
    StageObservations observed;
    observed.health = health_of(report);
    for (const auto& o : observers_) o->report(observed);
    record_health(report, observed.health);
    if (!observed.phases.empty()) report.phases = observed.phases;
    if (observed.capillary.measured) report.capillary = observed.capillary;
    if (observed.drainage.placed) report.drainage = observed.drainage;
    if (observed.channel) {
      report.channel = true;
      report.profile_error = observed.profile_error;
      report.profile_samples = observed.profile_samples;
    }
    StageRecord r;
    r.level = stage_.level, r.axis = axis_, r.half_force = stage_.half_force, r.spacing = stage_.spacing;
    r.steps = sim.steps(), r.simulated_time = sim.time();
    r.neighbour_rebuilds = neighbour_rebuilds();
    // The time loop of this process (after a restart: since the restart).
    r.wall_seconds = loop_seconds;
    r.warm_started = warm_started_;
    if (steady_report_) {
      const auto& solve = *steady_report_;
      r.steady_solve = true;
      r.solver_converged = solve.converged;
      r.nonlinear_iterations = solve.nonlinear_iterations;
      r.linear_iterations = solve.linear_iterations;
      r.inner_iterations = solve.inner_iterations;
      r.rate_evaluations = solve.rate_evaluations;
      r.partial_rate_evaluations = solve.partial_rate_evaluations;
      r.solver_residual = solve.residual;
      r.solver_setup_seconds = solve.setup_seconds;
      r.solver_solve_seconds = solve.solve_seconds;
      r.solver_bytes_per_particle = solve.bytes_per_particle;
    }
    const double force = driving_force(scene_);
    if (steady_report_ && measures_permeability() && force != 0) {
      // The solved state's own k: no pseudo-time, so no span to judge it over.
      r.has_permeability = true;
      const auto u = sim.superficial_velocity();
      for (int i = 0; i < Dim; ++i) r.k[i] = scene_.kinematic_viscosity * u[i] / force, r.u[i] = u[i];
      r.steady = steady_report_->converged;
      // k's change over the last Newton step, as the march's over its last span.
      const double change = steady_report_->last_step_change;
      r.relative_change = std::isnan(change) ? 0.0 : change;
      r.remaining_change = 0;
    } else if (observed.has_permeability) {
      r.has_permeability = true;
      for (int i = 0; i < Dim; ++i) r.k[i] = observed.k[i], r.u[i] = observed.u[i];
      r.steady = observed.steady;
      r.relative_change = observed.relative_change;
      r.remaining_change = observed.remaining_change;
    }
    if (observed.phases.size() == 2) {
      r.has_phases = true;
      r.has_relative_permeability = observed.phases[0].has_relative_permeability;
      for (int p = 0; p < 2; ++p)
        r.saturation[p] = observed.phases[p].saturation,
        r.relative_permeability[p] = observed.phases[p].relative_permeability;
    }
    records_.push_back(r);
  }

  // The stage's list builds: after a restart, those before the checkpoint
  // and those since, less the one that rebuilt the checkpoint's list.
  long long neighbour_rebuilds() const {
    const long long since = sim_->neighbour_rebuilds();
    if (!resume_) return since;
    return static_cast<long long>(resume_->state.neighbour_rebuilds) + std::max(since - 1, 0LL);
  }

  Stage stage_;
  int index_;
  SceneConfig scene_;
  const StageContext& context_;
  const RunOptions& options_;
  const CheckpointInfo* resume_;
  std::vector<StageRecord>& records_;
  RunReport& report_;
  std::unique_ptr<Sim> sim_;
  std::string fingerprint_;
  std::vector<std::string> later_suffixes_;  // of the stages after this one
  size_t records_before_ = 0;                // records of the stages before this one
  bool warm_started_ = false;
  int axis_ = -1;
  long long last_step_ = 0;
  std::vector<std::unique_ptr<Observer<Sim>>> observers_;  // app/StageObservers.hpp, in their order
  std::optional<SteadyReport> steady_report_;  // Solver/Method = steady, once solved
  std::vector<Observer<Sim>*> probes_, writers_;  // measure, then write: the steady stop comes between
};

}  // namespace poresph
