#include "app/Run.hpp"

#include <Kokkos_Core.hpp>

#include <cmath>
#include <signal.h>

#include <csignal>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/RunPlan.hpp"
#include "app/RunSummary.hpp"
#include "app/Simulation.hpp"
#include "app/StageLoop.hpp"
#include "core/ExecutionSpaces.hpp"
#include "core/StopRequest.hpp"
#include "geometry/Grains.hpp"
#include "geometry/Solid.hpp"
#include "io/Checkpoint.hpp"
#include "parallel/Communicator.hpp"

namespace poresph {
namespace {

extern "C" void request_stop(int signal_number) {
  if (stop_request == 0) stop_request = signal_number;
}

// drainage.csv: the drainage curve, largest ball first (radius in m; the
// capillary pressure with Drainage/Surface Tension).
std::string drainage_csv(const DrainageMeasure& drainage) {
  std::ostringstream text;
  text << std::setprecision(10);
  text << "radius,saturation,curvature" << (drainage.has_capillary_pressure ? ",capillary_pressure" : "") << "\n";
  for (const auto& step : drainage.curve) {
    const double curvature = drainage.curvature * drainage.radius / step.radius;  // (dim - 1) cos(theta) / r
    text << step.radius << "," << step.saturation << "," << curvature;
    if (drainage.has_capillary_pressure)
      text << "," << drainage.capillary_pressure * drainage.radius / step.radius;
    text << "\n";
  }
  return text.str();
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
  report.has_solid = scene.has_solid();
  report.porosity = solid_porosity(scene);
  const std::vector<Stage> stages = plan_run(scene);
  std::vector<StageRecord> records;
  std::optional<CheckpointInfo> resume_from;
  int first_stage = 0;
  bool in_place = false;
  if (!options.restart_file.empty()) {
    resume_from = read_checkpoint_info(options.restart_file, MPI_COMM_WORLD);
    const auto& st = resume_from->state;
    first_stage = static_cast<int>(st.stage);
    if (first_stage < 0 || first_stage >= static_cast<int>(stages.size()))
      throw std::invalid_argument("--restart " + options.restart_file + ": the checkpoint is of stage " +
                                  std::to_string(first_stage + 1) + " of a run, this scene's run has " +
                                  std::to_string(stages.size()) + " (Convergence/Levels, Permeability/Tensor, "
                                  "Permeability/Linearity Check differ)");
    // What defines the physics of the stage the checkpoint is of: its spacing and force included.
    check_checkpoint_matches(*resume_from, options.restart_file,
                             stage_fingerprint(stage_scene(scene, stages[first_stage])));
    std::error_code error;
    in_place = std::filesystem::equivalent(std::filesystem::absolute(options.restart_file).parent_path(),
                                           options.output_dir, error);
    for (size_t k = 0; k + StageRecord::kSize <= st.completed_stages.size(); k += StageRecord::kSize)
      records.push_back(StageRecord::read(&st.completed_stages[k]));
    record_health(report, HealthRecord::from(st));
  }
  const StageContext context{options, claim_output, in_place, report.porosity};
  RunReport summarised;  // the report with the stages' summary: what summary.json says and run() returns
  SummaryScales scales;
  if (scene.kinematic_viscosity > 0 && report.porosity > 0) {
    scales.particle_reynolds_scale = 1.0 / (report.porosity * scene.kinematic_viscosity);
    double diameter = 0;  // the mean grain's
    for (const auto& g : scene.grains) diameter += 2 * g.radius / scene.grains.size();
    scales.reynolds_scale = diameter * scales.particle_reynolds_scale;
  }
  scales.inertia = scene.convection || scene.particle_motion != ParticleMotion::Fixed;
  scales.max_inner_iterations = scene.solver.max_inner_iterations;
  scales.raised_inner_iterations = scene.solver.raised_inner_iterations;
  scales.solver_tolerance = scene.solver.tolerance;
  scales.density_variation_limit = scene.density_variation_limit;
  auto write_summary = [&]() {
    report.particle_steps_per_second =
        report.wall_seconds > 0
            ? (report.fluid_particles + report.boundary_particles) * report.timed_steps / report.wall_seconds
            : 0.0;
    summarised = report;
    summarise_stages(records, Dim, stages.front().levels, scene.steady_tolerance > 0, summarised, scales);
    if (Communicator().rank() == 0) {
      write_summary_file(options.output_dir + "/summary.json", summarised.to_json().str() + "\n");
      if (summarised.drainage.placed)
        write_file_atomically(options.output_dir + "/drainage.csv", drainage_csv(summarised.drainage));
    }
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
    std::unique_ptr<Simulation<Dim, ExecSpace>> previous;  // the end of the stage before, for a warm start
    for (int s = first_stage; s < static_cast<int>(stages.size()); ++s) {
      // A stage that does not start warm frees the one before it first.
      if (!stages[s].warm) previous.reset();
      const CheckpointInfo* resume = s == first_stage && resume_from ? &*resume_from : nullptr;
      // What a stage observes at its end is that stage's: a later stage that
      // stops early reports none, not the stage's before it (each level's
      // phases stay in its record).
      report.phases.clear(), report.capillary = {}, report.drainage = {};
      previous = StageLoop<Dim, ExecSpace>::run(scene, stages, s, context, std::move(previous), resume, records, report);
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
  return summarised;
}

}  // namespace

void install_stop_signal_handlers() {
  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  // Interrupted reads and writes (a checkpoint's) go on where they were.
  action.sa_flags = SA_RESTART;
  for (int signal_number : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaction(signal_number, &action, nullptr);
}

std::string signal_name(int signal_number) {
  switch (signal_number) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    case SIGPIPE: return "SIGPIPE";
    default: return "signal " + std::to_string(signal_number);
  }
}

bool stop_signal_pending() { return stop_request != 0; }

int stop_signal_received() { return Communicator().max(static_cast<int>(stop_request)); }

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
      .add("particle_spacing", particle_spacing)
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
      .add("neighbours_per_particle", neighbours_per_particle)
      .add("ghost_particles", ghost_particles)
      .add("ghost_particles_max", ghost_particles_max);
  if (channel) {
    std::vector<JsonObject> samples;
    for (const auto& s : profile_samples)
      samples.push_back(JsonObject().add("sample_time", s.requested_time).add("time", s.time).add("error", s.error));
    json.add("profile_error", profile_error).add("profile_samples", samples);
  }
  if (!phases.empty()) {
    std::vector<JsonObject> entries;
    for (size_t p = 0; p < phases.size(); ++p) {
      const auto& phase = phases[p];
      JsonObject entry;
      entry.add("index", static_cast<long long>(p))
          .add("name", phase.name)
          .add("saturation", phase.saturation)
          .add("superficial_velocity", phase.superficial_velocity)
          .add("axis", std::string(1, "xyz"[phase.axis]))
          .add("driven", phase.driven);
      if (phase.has_relative_permeability) entry.add("relative_permeability", phase.relative_permeability);
      if (phase.has_extrapolation)
        entry.add("relative_permeability_extrapolated", phase.relative_permeability_extrapolated)
            .add("relative_permeability_uncertainty", phase.relative_permeability_uncertainty);
      entry.add("mass", phase.mass).add("mean_pressure", phase.mean_pressure);
      if (phase.has_phase_field) entry.add("phase_field_volume", phase.phase_field_volume);
      entries.push_back(entry);
    }
    json.add("phases", entries);
  }
  if (capillary.measured)
    json.add("capillary", JsonObject()
                              .add("inside_pressure", capillary.inside_pressure)
                              .add("outside_pressure", capillary.outside_pressure)
                              .add("pressure_jump", capillary.pressure_jump)
                              .add("laplace_pressure", capillary.laplace_pressure)
                              .add("max_speed", capillary.max_speed)
                              .add("capillary_number", capillary.capillary_number));
  if (drainage.placed) {
    JsonObject d;
    d.add("radius", drainage.radius)
        .add("saturation", drainage.saturation)
        .add("curvature", drainage.curvature)
        .add("contact_angle", drainage.contact_angle)
        .add("inlet", drainage.inlet);
    if (drainage.has_capillary_pressure) d.add("capillary_pressure", drainage.capillary_pressure);
    json.add("drainage", d);
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
  if (!levels.empty()) {
    const char* axis = "xyz";
    auto tensor = [&](const double (&k)[3][3]) {
      JsonObject t;
      for (int j = 0; j < dimension; ++j)
        if (driven[j])
          for (int i = 0; i < dimension; ++i) t.add(std::string("k") + axis[i] + axis[j], k[i][j]);
      return t;
    };
    std::vector<JsonObject> per_level;
    for (const auto& level : levels) {
      JsonObject entry;
      entry.add("spacing", level.spacing)
          .add("permeability", tensor(level.permeability))
          .add("steps", level.steps)
          .add("wall_seconds", level.wall_seconds)
          .add("warm_started", level.warm_started)
          .add("steady", level.steady);
      if (level.has_phases) {
        std::vector<JsonObject> phases_here;
        for (int p = 0; p < 2; ++p) {
          JsonObject phase;
          phase.add("saturation", level.saturation[p]);
          if (level.has_relative_permeability) phase.add("relative_permeability", level.relative_permeability[p]);
          phases_here.push_back(phase);
        }
        entry.add("phases", phases_here);
      }
      per_level.push_back(entry);
    }
    json.add("convergence", per_level)
        .add("permeability_extrapolated", tensor(permeability_extrapolated))
        .add("observed_order", observed_order)
        .add("permeability_uncertainty", tensor(permeability_uncertainty));
  }
  if (has_linearity) {
    JsonObject change;
    for (int j = 0; j < dimension; ++j)
      if (driven[j])
        for (int i = 0; i < dimension; ++i) change.add(std::string("k") + "xyz"[i] + "xyz"[j], darcy_linearity[i][j]);
    json.add("darcy_linearity", change);
  }
  {
    JsonObject solved;
    solved.add("method", solver.method);
    if (solver.method == "steady")
      solved.add("converged", solver.converged)
          .add("nonlinear_iterations", solver.nonlinear_iterations)
          .add("linear_iterations", solver.linear_iterations)
          .add("residual", solver.residual)
          .add("setup_seconds", solver.setup_seconds)
          .add("solve_seconds", solver.solve_seconds)
          .add("bytes_per_particle", solver.bytes_per_particle)
          .add("inner_iterations", solver.inner_iterations)
          .add("rate_evaluations", solver.rate_evaluations)
          .add("partial_rate_evaluations", solver.partial_rate_evaluations);
    json.add("solver", solved);
  }
  if (!failure.empty()) json.add("failure", failure);
  json.add("warnings", warnings);
  if (restarted_from_step >= 0) json.add("restarted_from_step", restarted_from_step);
  json.add("porosity", porosity);
  if (has_solid) {
    json.add("particles_inside_grains", particles_inside_grains)
        .add("max_grain_penetration", max_grain_penetration)
        .add("grain_surface_corrections", grain_surface_corrections)
        .add("max_corrected_depth", max_corrected_depth);
    if (has_permeability && reynolds_number > 0) json.add("reynolds_number", reynolds_number);
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
