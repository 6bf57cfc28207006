#pragma once
// What watches a stage's time loop (app/StageLoop.hpp): after every step
// each observer does its part (a probe samples, a writer writes, a
// checkpoint is taken), one may ask the loop to stop (the steady-state
// stop), each says what it has done at the end, saves where it stands into
// a checkpoint so that a restart goes on from there, and reports what it
// measured into the stage's observations, which summary.json is made of.
// Sim is the simulation type (app/Simulation.hpp), a parameter so that the
// observers depend on what they use of it, not on the app layer.
//
// Observers are made by a factory (diagnostics/StageSetting.hpp): each
// observer has a static make(setting), which returns none when the stage
// does not need it, and one line in app/StageObservers.hpp lists it.
#include <cmath>
#include <string>
#include <vector>

#include "diagnostics/ChannelFlow.hpp"
#include "io/RunState.hpp"
#include "scene/Drainage.hpp"

namespace poresph {

// The state of the fluid over a run, as the health watch has seen it
// (diagnostics/HealthWatch.hpp).
struct HealthRecord {
  double max_density_variation = 0, max_density_drift = 0;
  long long particles_inside_grains = 0;
  double max_grain_penetration = 0;  // in particle spacings
  long long grain_surface_corrections = 0;
  double max_corrected_depth = 0;    // in particle spacings

  static HealthRecord from(const RunState& s) {
    return {s.max_density_variation, s.max_density_drift, static_cast<long long>(s.particles_inside_grains),
            s.max_grain_penetration, static_cast<long long>(s.grain_surface_corrections), s.max_corrected_depth};
  }
};

// One fluid phase's volume and its volume flux along an axis (m^Dim, m^(Dim+1)/s).
struct PhaseSums {
  double volume = 0, flux = 0, mass = 0, pressure = 0;  // pressure: sum of V p
};
// What a run measured of one fluid phase (diagnostics/PhaseProbe.hpp).
struct PhaseMeasure {
  std::string name;
  int axis = 0;                      // of the superficial velocity
  double saturation = 0;             // its share of the fluid volume
  double superficial_velocity = 0;   // its volume flux over the cell's volume (m/s)
  bool driven = true;                // the body force acts on it (Phases/Driven Phase)
  bool has_relative_permeability = false;
  double relative_permeability = 0;  // with Phases/Single Phase Permeability; one phase driven: the coupling to it
  // With Convergence/Levels > 1: k_r extrapolated from the levels, and its
  // relative uncertainty (the grid convergence index, as for k).
  bool has_extrapolation = false;
  double relative_permeability_extrapolated = 0, relative_permeability_uncertainty = 0;
  double mass = 0;                   // of its particles (kg per m^(3-Dim)); fixed particles keep it exactly
  double mean_pressure = 0;          // its volume-weighted mean p (Pa): phase 1's less phase 0's is the capillary pressure
  // A moving interface (Phases/Interface = moving): its volume by the phase
  // field, sum of phi dV (phase 1) or (1 - phi) dV (phase 0) over the fluid,
  // which the field's update conserves to round-off.
  bool has_phase_field = false;
  double phase_field_volume = 0;
};
// A round phase-1 region (a drop) against Laplace's law (diagnostics/PhaseProbe.hpp).
struct CapillaryMeasure {
  bool measured = false;
  double inside_pressure = 0;   // mean p of phase 1 at r < R - 3h (Pa)
  double outside_pressure = 0;  // mean p of phase 0 at r > R + 3h (Pa)
  double pressure_jump = 0;     // inside less outside
  double laplace_pressure = 0;  // sigma / R (2D), 2 sigma / R (3D)
  double max_speed = 0;         // largest |v| of a fluid particle (m/s)
  double capillary_number = 0;  // max_speed mu / sigma, mu the larger dynamic viscosity
};

// Phase 1 placed by drainage (scene/Drainage.hpp): the step of the rule
// it sits at, and the drainage curve of the lattice.
struct DrainageMeasure {
  bool placed = false;
  double radius = 0;      // m
  double saturation = 0;  // of phase 1, of the fluid particles
  double curvature = 0;   // (dim - 1) cos(theta) / r (1/m)
  bool has_capillary_pressure = false;
  double capillary_pressure = 0;  // sigma x curvature (Pa), with Drainage/Surface Tension
  double contact_angle = 0;       // degrees
  std::string inlet;              // x, y, z or anywhere
  std::vector<DrainageStep> curve;  // radius (m), saturation
};

// What a stage's observers measured, however the stage ended: what each
// reports of itself (Observer::report), for the stage's record and summary.json.
struct StageObservations {
  HealthRecord health;
  // The channel's start-up profiles against the series solution.
  bool channel = false;
  double profile_error = 0;
  std::vector<ProfileSample> profile_samples;
  // The permeability along the driven axis, as of the last check.
  bool has_permeability = false;
  double k[3] = {0, 0, 0}, u[3] = {0, 0, 0};  // k_i = nu <u_i> / F (driving_force), and the superficial velocity
  bool steady = false;
  double relative_change = 0, remaining_change = 0;
  // Two fluids: each phase at the end of the stage (empty: one fluid, or not measured).
  std::vector<PhaseMeasure> phases;
  CapillaryMeasure capillary;
  DrainageMeasure drainage;
};

// Where a run stands, for the progress line (io/ProgressLine.hpp).
struct ProgressStatus {
  long long step = 0;
  double time = 0;               // simulated (s)
  double fraction_of_end = 0;    // of the steps to End Time (or Max Steps)
  bool has_permeability = false;
  double permeability = 0;       // m^2, along the drive
  double remaining_change = INFINITY;  // predicted relative change still to come
  double steady_time = NAN;      // simulated time of the predicted steady stop; NaN if unknown
};

template <class Sim>
class Observer {
 public:
  virtual ~Observer() = default;
  // A writer writes after every probe has measured (the steady stop comes between).
  virtual bool writes() const { return false; }
  // After every step of the loop.
  virtual void after_step(Sim& sim) { (void)sim; }
  // Whether the loop may stop after this step.
  virtual bool wants_stop() const { return false; }
  // After the loop, when it ended by itself (End Time, Max Steps, steady).
  virtual void at_end(Sim& sim) { (void)sim; }
  // The loop is ending (by itself, a failure, a signal, an error): what it
  // shows on a terminal ends before other output.
  virtual void end_display() {}
  // Where it stands, for a checkpoint.
  virtual void save(RunState& state) const { (void)state; }
  // What it measured, into the stage's observations.
  virtual void report(StageObservations& observations) const { (void)observations; }
  // Where the run stands as it sees it, for the progress line.
  virtual void status(ProgressStatus& status) const { (void)status; }
  // A line of progress from a loop without steps (a steady solve).
  virtual void show(const std::string& text) { (void)text; }
};

}  // namespace poresph
