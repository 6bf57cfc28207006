#pragma once
// Runs a scene from start to end and reports it: the time loop, the
// diagnostics sampled along the way, the progress line and summary.json.
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "diagnostics/ChannelFlow.hpp"
#include "diagnostics/Observer.hpp"
#include "scene/SceneConfig.hpp"
#include "io/Summary.hpp"

namespace poresph {

struct RunOptions {
  std::string output_dir;
  bool progress_on_terminal = true;  // stdout is a terminal
  std::string restart_file;          // a checkpoint to continue from (empty: start afresh)
  std::string parameters_xml;        // the parameter list in use, stored in checkpoints
  long long inject_nan_at_step = -1;  // testing the failure path: this step ends with a NaN velocity
  // Testing restarts: the run stops as if by SIGTERM after this step of this stage.
  int interrupt_stage = -1;
  long long interrupt_step = -1;
  // Called by every process once the first set-up has succeeded, before
  // anything is written: the command line claims the output directory there
  // (io/OutputDirectory.hpp), so that a run refused during set-up writes nothing.
  std::function<void()> prepare_output;
  double setup_seconds_before = 0;  // spent reading and checking the scene before run_scene
};

// A run stopped by a signal (stop_signal_pending) after writing its checkpoint.
struct RunInterrupted : std::runtime_error {
  RunInterrupted(const std::string& message, int signal_number_)
      : std::runtime_error(message), signal_number(signal_number_) {}
  int signal_number;
};

// Installs the handlers of the signals that stop a run with a checkpoint
// and a summary: SIGINT (Ctrl-C), SIGTERM (kill, a batch system's end),
// SIGHUP (the terminal or ssh connection closed) and SIGPIPE (the reader of
// the output went away: `poresph ... | head -1`). The handlers only note
// the signal; the run stops where it can save its state. A write to a pipe
// with no reader then fails with EPIPE instead of ending the process.
void install_stop_signal_handlers();
// Whether this process has received one of them (no communication).
bool stop_signal_pending();
// The first of them received, or 0, agreed by all processes.
int stop_signal_received();
// "SIGTERM", ...
std::string signal_name(int signal_number);

// What a run measured; summary.json is this, serialised.
struct RunReport {
  std::string scene;
  int dimension = 0;
  long long fluid_particles = 0, boundary_particles = 0;
  long long steps = 0;
  long long timed_steps = 0;  // steps run by this process (after a restart: since it)
  double simulated_time = 0, time_step = 0, smoothing_length = 0, sound_speed = 0;
  double particle_spacing = 0;  // of the finest level
  std::string stopped_by;  // end_time, max_steps, steady_state, not_converged, failure, signal, error (of the last stage)
  std::string failure;     // what stopped a failed run
  std::vector<std::string> warnings;  // from the input checks (narrow throats)
  long long restarted_from_step = -1;
  double wall_seconds = 0, setup_seconds = 0, particle_steps_per_second = 0;
  int ranks = 1, threads = 1;
  std::string backend;
  double max_density_variation = 0;  // max |rho/rho0 - 1| of fluid, over the checks of the run and its end
  double max_density_drift = 0;      // max |<rho>/rho0 - 1| of fluid, likewise
  long long neighbour_rebuilds = 0;
  double neighbours_per_particle = 0;  // listed pairs (support + skin) per owned particle
  long long ghost_particles = 0, ghost_particles_max = 0;  // over all processes, and the most one holds
  bool channel = false;
  double profile_error = 0;
  std::vector<ProfileSample> profile_samples;
  // Two fluids: each phase's saturation, superficial velocity and k_r (diagnostics/PhaseProbe.hpp).
  std::vector<PhaseMeasure> phases;
  // A drop (Phases/Phase 1 round, Phases/Surface Tension > 0): its pressure jump against Laplace's law.
  CapillaryMeasure capillary;
  // Phase 1 placed by drainage: its step of the rule and the drainage curve (also drainage.csv).
  DrainageMeasure drainage;

  // Porous-media measures (present when the scene is driven by a body force).
  bool has_permeability = false;
  double permeability[3][3] = {};      // k[i][j] = nu <u_i> / F_j
  bool driven[3] = {false, false, false};  // which columns j were driven
  double superficial_velocity[3] = {};  // of the first driven run
  bool steady = false;                  // every driven run reached the steady-state tolerance
  double steady_relative_change = 0;    // of k over the last span compared (worst over runs)
  double steady_remaining_change = 0;   // predicted change of k still to come (worst over runs)
  bool has_solid = false;               // grains or an image
  double porosity = 1.0;
  double reynolds_number = 0;           // mean pore velocity x mean grain diameter / nu; 0: no grains
  long long particles_inside_grains = 0;     // most fluid particles found inside grains at any check
  double max_grain_penetration = 0;     // deepest of them at any check, in particle spacings
  // Fluid particles put back on a grain surface after a step (GrainContact.hpp),
  // summed over steps, and the deepest they had gone, in particle spacings.
  long long grain_surface_corrections = 0;
  double max_corrected_depth = 0;

  // The resolution ladder (Convergence/Levels > 1): what each level measured,
  // coarse to fine, and the grid convergence index from them.
  struct Level {
    double spacing = 0;
    double permeability[3][3] = {};
    long long steps = 0;
    double wall_seconds = 0;
    bool warm_started = true, steady = true;
    // Two fluids: each phase's saturation and k_r at this level.
    bool has_phases = false, has_relative_permeability = false;
    double saturation[2] = {0, 0}, relative_permeability[2] = {0, 0};
  };
  std::vector<Level> levels;
  double permeability_extrapolated[3][3] = {};
  double permeability_uncertainty[3][3] = {};  // relative; NaN where a component is about zero
  double observed_order = 0;                   // of the largest component (NaN with two levels)
  // Solver/: how the stages were solved. A steady solve's figures are summed
  // over its stages (the residual and memory: the largest).
  struct Solver {
    std::string method = "explicit";
    bool converged = true;
    long long nonlinear_iterations = 0, linear_iterations = 0, inner_iterations = 0, rate_evaluations = 0,
              partial_rate_evaluations = 0;
    double residual = 0, setup_seconds = 0, solve_seconds = 0, bytes_per_particle = 0;
  } solver;
  // Permeability/Linearity Check: (k at F/2 - k at F) / k at F, per component.
  bool has_linearity = false;
  double darcy_linearity[3][3] = {};

  JsonObject to_json() const;
};

// The execution space a scene runs on, and its threads per process (after Kokkos::initialize).
std::string backend_for(const SceneConfig& scene);
int threads_for(const SceneConfig& scene);

// Runs the scene on the default host execution space; writes
// output_dir/summary.json (and profiles.csv for channel scenes).
RunReport run_scene(const SceneConfig& scene, const RunOptions& options);

}  // namespace poresph
