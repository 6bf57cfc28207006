#pragma once
// A scene as the solver sees it: plain values, already validated. Only the
// io layer knows about Teuchos and files; it fills this struct, which the
// geometry, physics and app layers read (hence its own folder, below them
// all but core).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "geometry/VoxelImage.hpp"
#include "solver/SteadyOptions.hpp"

namespace poresph {

enum class WallType { None, Channel };

// A soil grain: circle (2D) or sphere (3D); centre uses the first `dimension` values.
struct Grain {
  std::array<double, 3> centre{};
  double radius = 0;
  std::string origin;  // where it was defined, for messages: "grains.txt:12", "Grains/Inline #3"
  double density = 0;  // kg/m^3, the grain file's density column (moving grains); 0: Grains/Density
};
// A segmented image as the solid (the Image sublist), instead of grains.
struct ImageConfig {
  std::string file;  // as read (a relative name resolved); empty: no image
  std::vector<int> solid_values;
  double voxel_size = 0.0;
  int mirror_axis = -1;  // Image/Mirror: the axis the image was mirrored along (the driven one); -1: none
  // The voxels as read (and mirrored), shared: the scene is copied for
  // every level of the resolution ladder, the volume need not be.
  std::shared_ptr<const VoxelImage> voxels;
  VoxelCounts counts;
  // The signed distance to the solid's surface at the voxel centres (m),
  // made once from the voxels (surface_distance, geometry/DistanceTransform.hpp).
  std::shared_ptr<const std::vector<float>> distance;
  // Where a process holds only its piece of the image (scene/ImagePieces.hpp):
  // the cell's voxel of the piece's voxel 0 (below 0 in a halo across a
  // periodic face), and per axis whether the piece is the whole periodic
  // axis and wraps as the cell does. The whole image: 0, and the cell's own.
  std::array<long long, 3> piece_first{};
  std::array<bool, 3> piece_wraps{{true, true, true}};
  // The voxels this process's box owns (each voxel is one box's); empty:
  // all of them (the whole image).
  VoxelBox owned;
  // The whole image's shape (after Image/Mirror) and the checksum of its
  // solid voxels (io/Checksum.hpp's row checksum, a voxel a row), summed
  // over the pieces: what a checkpoint's fingerprint names the image by.
  std::array<long long, 3> cell_voxels{{0, 0, 1}};
  std::uint64_t solid_checksum = 0;
  // Per axis the image is driven along: the width (m) its widest pore path
  // that way narrows to, from the distance field (0: not driven that way).
  std::array<double, 3> bottleneck{};
};

// A fluid phase besides the Fluid sublist's (the Phases sublist). Phase 0
// is that fluid and fills whatever no other phase's region claims; phase p
// >= 1 fills its region, set once on the fixed lattice (particles never
// change phase: they never move): the box [region_low, region_high), or
// with region_radius > 0 the disc (sphere) of that radius about
// region_centre, its distance taken across periodic faces (the nearest image).
struct PhaseConfig {
  std::string name;
  double density = 0;              // kg/m^3
  double kinematic_viscosity = 0;  // m^2/s
  std::array<double, 3> region_low{}, region_high{};  // phase 0: unused
  std::array<double, 3> region_centre{};
  double region_radius = 0;  // > 0: a disc (sphere), not a box
  bool round() const { return region_radius > 0; }
  // Instead of a region: placed by the morphological drainage rule
  // (scene/Drainage.hpp), at a ball radius or at the first radius that
  // reaches a saturation.
  struct Drainage {
    double saturation = 0;  // > 0: the target saturation of this phase
    double radius = 0;      // > 0: the ball radius (m), given or from the capillary pressure
    double capillary_pressure = 0;  // > 0: Drainage/Capillary Pressure (Pa), which set the radius
    int inlet_axis = 0;
    bool inlet_anywhere = false;
    bool trapping = false;       // wetting phase cut off from the outlet stays
    double contact_angle = 0;    // degrees, through phase 0
    double surface_tension = 0;  // N/m, for the capillary pressure reported; 0: not reported
  } drainage;
  bool drained() const { return drainage.saturation > 0 || drainage.radius > 0; }
  // Instead of a region: the image's pore voxels of these values (a
  // segmented image of the solid and two fluids).
  std::vector<int> image_values;
  bool from_image() const { return !image_values.empty(); }
};

// How the surface tension's colour function is made (Phases/Colour, physics/SurfaceTension.hpp).
enum class ColourFunction { VolumeFraction, Phase };

enum class ProgressMode { Auto, Always, Never };
// How particles move. Fixed: they stay on their lattice and only velocity
// and density evolve (an Eulerian SPH), so their arrangement cannot lose its
// order and neighbour lists never change. Lagrangian: they move with the
// flow, as in the paper.
enum class ParticleMotion { Fixed, Lagrangian };
// The pressure of boundary particles: extrapolated from the fluid next to
// them (Adami et al. 2012), or from their own density by the continuity
// equation (the paper).
enum class WallPressure { Extrapolated, Continuity };
enum class Backend { Default, Serial, OpenMP };
// Whether grains move: Fixed, Free (rigid bodies that translate and turn
// under the fluid's force and torque and gravity), Rotating (centres held,
// turning freely). physics/RigidGrains.hpp.
enum class GrainMotion { Fixed, Free, Rotating };
// What Grains/Contact sets (physics/ContactLaw.hpp): the solid's
// elasticity, the restitution and friction of a contact, and the gap at
// which it begins.
struct ContactMaterial {
  double young_modulus = 0;  // Pa; 0: soft, from the time step (soft_contact_modulus)
  double poisson_ratio = 0.3;
  double restitution = 0.9;
  double friction = 0.3;
  double cutoff_spacings = 1.0;  // the gap, in particle spacings
};

struct SceneConfig {
  std::string name = "scene";
  int dimension = 2;
  std::array<double, 3> cell_size{};  // periodic cell [0, L_d)
  std::array<bool, 3> periodic{{true, true, true}};

  double density = 1000.0;
  double kinematic_viscosity = 1e-6;
  std::array<double, 3> body_force{};
  double sound_speed = 0.0;  // 0: from the scales below
  double density_variation = 0.01;
  bool raise_sound_speed = false;  // c up to what the other time-step limits allow
  double velocity_scale = 0.0;  // 0: estimated (see Parameters.cpp)
  double length_scale = 0.0;    // 0: largest cell side
  double background_pressure = 0.0;  // fraction of c^2 rho0 the momentum equation keeps (1: p = c^2 rho)

  ParticleMotion particle_motion = ParticleMotion::Fixed;
  // Fixed particles: the convective term -(v.grad)v of the Navier-Stokes
  // momentum equation (a moving particle carries it in its own motion).
  bool convection = true;
  WallPressure wall_pressure = WallPressure::Extrapolated;

  double particle_spacing = 0.0;
  double smoothing_length_ratio = 1.0;  // h / dx
  int resummation_interval = 0;         // steps; 0 = never
  double time_step = 0.0;               // 0: from the stability limits
  double shifting_coefficient = 0.0;    // particle shifting A; 0 = off
  double neighbour_skin = 0.2;          // Verlet skin in units of h

  // Empty: no grains, and none of their machinery runs.
  std::vector<Grain> grains;
  bool allow_overlapping_grains = false;
  GrainMotion grain_motion = GrainMotion::Fixed;
  double grain_density = 0.0;          // kg/m^3, for moving grains' mass and inertia
  std::array<double, 3> gravity{};     // on moving grains and the fluid (Grains/Gravity)
  std::vector<double> grain_velocity;  // Grains/Initial Velocity: Dim values, or Dim a grain; empty: at rest
  std::vector<double> grain_spin;      // Grains/Initial Spin: 1 value (3 in 3D), or as many a grain; empty: none
  std::vector<int> held_grains;        // Grains/Held: indices of grains that hold still while the others move
  std::vector<int> prescribed_grains;  // Grains/Prescribed: grains that keep their initial velocity and spin
  ContactMaterial grain_contact;       // Grains/Contact
  bool moving_grains() const { return grain_motion != GrainMotion::Fixed && !grains.empty(); }
  // A grain's solid density: its own from the grain file, or Grains/Density.
  double density_of(const Grain& g) const { return g.density > 0 ? g.density : grain_density; }
  bool held(std::size_t g) const {
    return std::find(held_grains.begin(), held_grains.end(), static_cast<int>(g)) != held_grains.end();
  }
  // Where grain g's start values begin in Grains/Initial Velocity or Initial
  // Spin (`per_grain` values a grain): one set for every grain, or one a grain.
  static std::size_t first_start_value(const std::vector<double>& values, std::size_t g, std::size_t per_grain) {
    return values.size() == per_grain ? 0 : g * per_grain;
  }
  // The fastest point of a moving grain's surface at the start, |U| + |omega| r
  // from Grains/Initial Velocity and Initial Spin (held grains stay at rest):
  // a moving wall, for the sound-speed rule. 0 while the grains hold still.
  double fastest_grain_surface() const {
    if (!moving_grains()) return 0.0;
    const std::size_t dim = static_cast<std::size_t>(dimension), spins = dimension == 2 ? 1 : 3;
    auto length_of = [](const std::vector<double>& values, std::size_t g, std::size_t per_grain) {
      const std::size_t first = first_start_value(values, g, per_grain);
      double sum = 0;
      for (std::size_t k = first; k < first + per_grain && k < values.size(); ++k) sum += values[k] * values[k];
      return std::sqrt(sum);
    };
    double fastest = 0;
    for (std::size_t g = 0; g < grains.size(); ++g) {
      if (held(g)) continue;
      const double speed = length_of(grain_velocity, g, dim) + length_of(grain_spin, g, spins) * grains[g].radius;
      fastest = std::max(fastest, speed);
    }
    return fastest;
  }
  bool grain_densities_given() const {
    return !grains.empty() && std::all_of(grains.begin(), grains.end(), [](const Grain& g) { return g.density > 0; });
  }
  // How the grains were made when PoreSPH made them (Grains/Random Pack):
  // the header of grains_used.txt. Empty for grains given in the scene.
  std::string grains_note;
  // Image/File was given: the solid is these voxels (no grains).
  ImageConfig image;
  // A solid in the cell, whichever describes it (geometry/Solid.hpp).
  bool has_solid() const { return !grains.empty() || image.voxels != nullptr; }
  // What the checks of the input found worth saying but not refusing (narrow throats).
  std::vector<std::string> warnings;

  // Two fluids: phases[0] is the Fluid sublist's, phases[1] fills its
  // region. Empty: one fluid, and none of the phases' machinery runs.
  std::vector<PhaseConfig> phases;
  double single_phase_permeability = 0;  // Phases/Single Phase Permeability (m^2); 0: not given, no k_r
  // Phases/Surface Tension sigma between the two phases (N/m); 0: none, and
  // none of its machinery runs (physics/SurfaceTension.hpp).
  double surface_tension = 0;
  ColourFunction colour = ColourFunction::VolumeFraction;
  // Phases/Driven Phase: the phase the body force acts on (0 or 1); -1:
  // both. The other phase is moved only by its neighbours (viscous coupling).
  int driven_phase = -1;
  // Phases/Interface = moving: the phases are a phase field carried by the
  // flow (physics/PhaseField.hpp); fixed (false): each particle keeps its phase.
  bool moving_interface = false;
  double interface_width = 0.75;    // Phases/Interface Width, in particle spacings
  double interface_mobility = 0.0;  // Phases/Interface Mobility (m/s); 0: the rule of Simulation
  double contact_angle = 90.0;      // Phases/Contact Angle (degrees, through phase 0) on every solid
  // Phases/Contact Angles: per Image/Solid Values entry (an image) or per
  // grain (grains), in degrees through phase 0; empty: contact_angle on all.
  std::vector<double> solid_contact_angles;
  // Phases/Force Steps: the body force is force_steps[i] times body_force
  // during the i-th of force_steps.size() equal spans of end_time; empty: it holds.
  std::vector<double> force_steps;
  // The factor of body_force at time t (1 without force steps).
  double force_factor(double t) const {
    if (force_steps.empty()) return 1.0;
    const double span = end_time / static_cast<double>(force_steps.size());
    const auto i = static_cast<std::size_t>(std::max(0.0, std::floor(t / span * (1 + 1e-12))));
    return force_steps[std::min(i, force_steps.size() - 1)];
  }
  double largest_force_factor() const {
    return force_steps.empty() ? 1.0 : *std::max_element(force_steps.begin(), force_steps.end());
  }
  bool has_phases() const { return !phases.empty(); }
  // The body force's share on a phase: 1 where it acts, 0 where it does not.
  double phase_force_share(int phase) const { return driven_phase < 0 || driven_phase == phase ? 1.0 : 0.0; }

  WallType walls = WallType::None;
  double lower_wall_velocity = 0.0;  // along x
  double upper_wall_velocity = 0.0;
  // A channel with nothing in it, driven along x or by its walls: the flow
  // whose start-up the series solution gives (diagnostics/ChannelFlow.hpp).
  bool empty_channel() const {
    return walls == WallType::Channel && grains.empty() && !image.voxels && body_force[1] == 0 && body_force[2] == 0;
  }

  double end_time = 0.0;
  long long max_steps = 0;  // 0: no limit
  std::vector<double> profile_sample_times;

  ProgressMode progress = ProgressMode::Auto;
  Backend backend = Backend::Default;  // Kokkos execution space of the kernels
  int threads = 0;                     // threads per process; 0 = Kokkos's default
  double memory_limit_bytes = 0;       // for the run's processes on one machine; 0: what it has available

  // Sub-domains across MPI ranks: a process grid (empty: chosen from the
  // cell's shape), with optional cuts per direction (the paper's adjusted
  // sub-cell boundaries; empty: equal parts).
  bool grid_decomposition = false;  // the paper's process grid instead of Zoltan2's RCB
  double rebalance_threshold = 0;   // slowest over mean compute time that divides the cell anew; 0: never
  int rebalance_interval = 100;     // steps between measurements of the balance
  std::vector<int> process_grid;
  std::array<std::vector<double>, 3> cuts;
  bool write_final_particles = false;  // particles.csv of the final state
  // Field output (HDF5 + XDMF): every field_interval seconds of simulated
  // time (0: none), the named particle fields, and the SPH-interpolated
  // velocity and pressure on a grid of grid_points per direction (empty: none).
  double field_interval = 0.0;
  std::vector<std::string> fields;  // of: velocity density pressure kind grain id
  std::vector<int> grid_points;
  long long checkpoint_interval = 0;  // steps; 0: only the final checkpoint
  bool final_checkpoint = true;
  // The run stops, naming the particle, when |rho/rho0 - 1| of a fluid particle exceeds this.
  double density_variation_limit = 0.1;

  // The resolution ladder (app/RunPlan.hpp): this many levels, each
  // refinement_ratio times finer than the one before, the finest at
  // particle_spacing, each starting from the one before.
  int convergence_levels = 1;
  double refinement_ratio = 2.0;
  // Permeability: drive every direction in turn (full tensor) or only along the body force.
  bool permeability_tensor = false;
  // Repeat the finest level at half the body force: how linear (Darcy) the flow is.
  bool linearity_check = false;
  double steady_tolerance = 0.0;  // on k's change over a span and its predicted change to come; 0 = run to the end
  double steady_window = 0.0;     // shortest span (s); the spin-up time k / (nu porosity) when longer
  // Solver/: march in time, or solve for the steady state (fixed particles;
  // solver/SteadySolver.hpp), and what that solve is asked for.
  bool steady_solver = false;
  SteadyOptions solver;
};

// The distance from x to a round region's centre, across periodic faces
// to the nearest image of the centre.
inline double distance_to_centre(const SceneConfig& scene, const PhaseConfig& phase, const double* x) {
  double sum = 0;
  for (int d = 0; d < scene.dimension; ++d) {
    double s = x[d] - phase.region_centre[d];
    const double L = scene.cell_size[d];
    if (scene.periodic[d] && L > 0) s -= L * std::round(s / L);
    sum += s * s;
  }
  return std::sqrt(sum);
}

// Whether x lies in phase p's region (p >= 1).
inline bool in_phase_region(const SceneConfig& scene, int p, const double* x) {
  const PhaseConfig& phase = scene.phases[p];
  if (phase.round()) return distance_to_centre(scene, phase, x) < phase.region_radius;
  bool inside = true;
  for (int d = 0; d < scene.dimension; ++d)
    inside = inside && x[d] >= phase.region_low[d] && x[d] < phase.region_high[d];
  return inside;
}

// The phase of a particle at x (in the cell): the last phase whose region
// holds x, phase 0 where none does.
inline int phase_at(const SceneConfig& scene, const double* x) {
  int phase = 0;
  for (int p = 1; p < static_cast<int>(scene.phases.size()); ++p)
    if (in_phase_region(scene, p, x)) phase = p;
  return phase;
}

// The share of the lattice cell of side dx about x that phase 1's region
// covers: exact for a box, sampled at samples^Dim points for a disc
// (sphere) where the cell meets its surface (scene with two phases).
inline double phase_one_fraction(const SceneConfig& scene, const double* x, double dx, int samples) {
  const PhaseConfig& phase = scene.phases[1];
  const int dim = scene.dimension;
  if (!phase.round()) {
    double fraction = 1;
    for (int d = 0; d < dim; ++d) {
      // x is a lattice point of the cell: its lattice cell lies in [0, L), as the box does.
      const double overlap =
          std::min(x[d] + 0.5 * dx, phase.region_high[d]) - std::max(x[d] - 0.5 * dx, phase.region_low[d]);
      fraction *= std::max(0.0, overlap) / dx;
    }
    return fraction;
  }
  const double r = distance_to_centre(scene, phase, x), half_diagonal = 0.5 * dx * std::sqrt(double(dim));
  if (r + half_diagonal < phase.region_radius) return 1.0;
  if (r - half_diagonal >= phase.region_radius) return 0.0;
  long long inside = 0, total = 1;
  for (int d = 0; d < dim; ++d) total *= samples;
  for (long long k = 0; k < total; ++k) {
    double at[3];
    long long rest = k;
    for (int d = 0; d < dim; ++d, rest /= samples)
      at[d] = x[d] + ((rest % samples) + 0.5) / samples * dx - 0.5 * dx;
    inside += distance_to_centre(scene, phase, at) < phase.region_radius;
  }
  return static_cast<double>(inside) / static_cast<double>(total);
}

// |F|, the body force's magnitude.
inline double body_force_magnitude(const SceneConfig& scene) {
  double sum = 0;
  for (int d = 0; d < scene.dimension; ++d) sum += scene.body_force[d] * scene.body_force[d];
  return std::sqrt(sum);
}

// The one axis the body force points along, or -1 (no force, or several components).
inline int force_axis(const SceneConfig& scene) {
  int axis = -1;
  for (int d = 0; d < scene.dimension; ++d) {
    if (scene.body_force[d] == 0) continue;
    if (axis >= 0) return -1;
    axis = d;
  }
  return axis;
}

// The force k is measured against, k_i = nu <u_i> / F: with a force along
// one axis, its signed component there, so that a force along -x gives the
// same positive k as one along +x; with a force along several axes, |F|,
// and k is then the tensor times F's direction.
inline double driving_force(const SceneConfig& scene) {
  const int axis = force_axis(scene);
  return axis >= 0 ? scene.body_force[axis] : body_force_magnitude(scene);
}

}  // namespace poresph
