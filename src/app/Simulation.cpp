#include "app/Simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/ExecutionSpaces.hpp"
#include "core/Math.hpp"
#include "core/MemoryAvailable.hpp"
#include "geometry/Grains.hpp"
#include "geometry/Lattice.hpp"
#include "parallel/RcbDecomposition.hpp"
#include "physics/ContactLaw.hpp"
#include "physics/Density.hpp"
#include "physics/LevelStart.hpp"
#include "physics/PredictorCorrector.hpp"
#include "physics/SurfaceTension.hpp"

namespace poresph {

DerivedParameters derive_parameters(const SceneConfig& scene) {
  DerivedParameters p{};
  const int dim = scene.dimension;
  p.smoothing_length = scene.smoothing_length_ratio * scene.particle_spacing;
  double force_norm = 0.0, largest_side = 0.0;
  for (int d = 0; d < dim; ++d) {
    force_norm += scene.body_force[d] * scene.body_force[d];
    largest_side = std::max(largest_side, scene.cell_size[d]);
  }
  force_norm = std::sqrt(force_norm) * scene.largest_force_factor();  // the largest of a stepped force
  if (scene.moving_grains()) {
    // A settling grain's weight is held by pressure differences in the
    // fluid, as a body force's would be: gravity counts as a body force of
    // up to the solid's density over the fluid's.
    double gravity = 0.0;
    for (int d = 0; d < dim; ++d) gravity += scene.gravity[d] * scene.gravity[d];
    double heaviest = 0.0;
    for (const Grain& g : scene.grains) heaviest = std::max(heaviest, scene.density_of(g));
    force_norm = std::max(force_norm, std::sqrt(gravity) * std::max(1.0, heaviest / scene.density));
  }
  // A component can be finite while its square overflows; either way no
  // time step follows from it, and "no flow scale" would be the wrong reason.
  if (!std::isfinite(force_norm)) {
    std::ostringstream msg;
    msg << "Fluid/Body Force = (";
    for (int d = 0; d < dim; ++d) msg << (d ? ", " : "") << scene.body_force[d];
    msg << ") has no finite magnitude";
    throw std::invalid_argument(msg.str());
  }
  // Two fluids: the least viscous sets the velocity scale, the most viscous
  // the viscous limit of the time step (one fluid: both are its nu).
  double nu = scene.kinematic_viscosity, nu_least = nu;
  for (const auto& phase : scene.phases)
    nu = std::max(nu, phase.kinematic_viscosity), nu_least = std::min(nu_least, phase.kinematic_viscosity);
  p.length_scale = scene.length_scale > 0 ? scene.length_scale : largest_side;
  // Without a given velocity scale: the larger of the moving walls' speed
  // (channel walls and the surfaces of grains set moving) and the peak of
  // plane Poiseuille flow across the length scale, F L^2 / (8 nu), an upper
  // bound for flow driven through pores narrower than L.
  p.velocity_scale = scene.velocity_scale;
  if (p.velocity_scale <= 0) {
    const double wall = std::max({std::abs(scene.lower_wall_velocity), std::abs(scene.upper_wall_velocity),
                                  scene.fastest_grain_surface()});
    const double poiseuille =
        nu_least > 0 ? force_norm * p.length_scale * p.length_scale / (8.0 * nu_least) : 0.0;
    p.velocity_scale = std::max(wall, poiseuille);
  }
  if (scene.sound_speed > 0) {
    p.sound_speed = scene.sound_speed;
  } else {
    const double c_sq = sound_speed_squared_from_scales(p.velocity_scale, p.length_scale, force_norm, nu,
                                                        scene.density_variation);
    if (!(c_sq > 0))
      throw std::invalid_argument(
          "cannot choose a speed of sound: the scene has no flow scale (no body force, no moving wall, no "
          "Fluid/Velocity Scale); set Fluid/Velocity Scale or Fluid/Sound Speed");
    p.sound_speed = std::sqrt(c_sq);
    // A grain set moving at once pushes the fluid ahead of it like a piston,
    // compressing it by V / c (a water hammer) where a steady flow at V
    // compresses it by (V / c)^2: c keeps that to half the density-variation
    // limit the run is checked against.
    const double piston = scene.fastest_grain_surface();
    if (piston > 0) p.sound_speed = std::max(p.sound_speed, 2.0 * piston / scene.density_variation_limit);
    // Surface tension holds a pressure jump of sigma kappa across the
    // interface, up to (Dim - 1) sigma / h where it bends as sharply as the
    // kernel resolves (a drop as small as it can be, a meniscus in a narrow
    // throat): the delta rule for that pressure (the phases share rho0).
    if (scene.surface_tension > 0) {
      const double laplace = (dim - 1) * scene.surface_tension / p.smoothing_length;
      p.sound_speed = std::max(p.sound_speed, std::sqrt(laplace / (scene.density * scene.density_variation)));
    }
    // Fixed particles always raise it: their steady state does not depend on
    // c (to O(Mach^2)), but the slowest way to it, pressure differences
    // diffusing through the pores, runs as c^2 (docs/method.md).
    if (scene.raise_sound_speed || scene.particle_motion == ParticleMotion::Fixed) {
      // The acoustic limit 0.25 h / c need not be smaller than the others:
      // up to there a larger c costs no steps and makes the fluid stiffer.
      const TimeStepLimits others = time_step_limits(p.smoothing_length, 0.0, nu, force_norm);
      const double other_limit = std::min(others.viscous, others.force);
      if (std::isfinite(other_limit)) p.sound_speed = std::max(p.sound_speed, 0.25 * p.smoothing_length / other_limit);
    }
  }
  if (!std::isfinite(p.sound_speed)) {
    std::ostringstream msg;
    msg << "the speed of sound chosen from the flow scales is not finite (velocity scale " << p.velocity_scale
        << " m/s, length scale " << p.length_scale << " m, |F| = " << force_norm
        << " m/s^2); set Fluid/Sound Speed or Fluid/Velocity Scale";
    throw std::invalid_argument(msg.str());
  }
  p.limits = time_step_limits(p.smoothing_length, p.sound_speed, nu, force_norm);
  // Free grains touch: the time step resolves the shortest collision, that of
  // the two lightest grains at the velocity scale, or the contact is made as
  // soft as the fluid's time step resolves.
  const bool contacts = scene.grain_motion == GrainMotion::Free && !scene.grains.empty();
  const double young = scene.grain_contact.young_modulus;
  if (contacts && young > 0) {
    const double duration = dim == 2 ? shortest_collision<2>(scene, young, p.velocity_scale)
                                     : shortest_collision<3>(scene, young, p.velocity_scale);
    p.limits.contact = duration / kStepsPerCollision;
  }
  if (scene.moving_interface)
    p.limits.capillary = capillary_time_step(p.smoothing_length, scene.density, scene.surface_tension);
  p.time_step = scene.time_step > 0 ? scene.time_step : p.limits.smallest();
  if (!(p.time_step > 0) || !std::isfinite(p.time_step)) {
    std::ostringstream msg;
    msg << "the time step comes out as " << p.time_step << " s (acoustic limit " << p.limits.acoustic
        << ", viscous " << p.limits.viscous << ", body force " << p.limits.force
        << "): no run can step with it; check Fluid/Sound Speed, Fluid/Kinematic Viscosity and Fluid/Body Force";
    throw std::invalid_argument(msg.str());
  }
  if (p.time_step > p.limits.smallest() * (1 + 1e-12)) {
    std::ostringstream msg;
    msg << "Discretization/Time Step = " << scene.time_step << " exceeds the stability limit "
        << p.limits.smallest() << " (acoustic " << p.limits.acoustic << ", viscous " << p.limits.viscous
        << ", body force " << p.limits.force << ", contact " << p.limits.contact << ", capillary "
        << p.limits.capillary << ")";
    throw std::invalid_argument(msg.str());
  }
  p.contact_modulus = !contacts  ? 0.0
                      : young > 0 ? young
                      : dim == 2  ? soft_contact_modulus<2>(scene, p.velocity_scale, p.time_step)
                                  : soft_contact_modulus<3>(scene, p.velocity_scale, p.time_step);
  return p;
}

bool lagrangian_shifting(const SceneConfig& scene) {
  return scene.particle_motion == ParticleMotion::Lagrangian && scene.shifting_coefficient > 0;
}

namespace {
template <int Dim>
bool same_boxes(const Decomposition<Dim>& a, const Decomposition<Dim>& b) {
  if (a.ranks() != b.ranks()) return false;
  for (int r = 0; r < a.ranks(); ++r)
    if (a.box(r).lo != b.box(r).lo || a.box(r).hi != b.box(r).hi) return false;
  return true;
}

}  // namespace

template <int Dim>
Decomposition<Dim> decompose(const SceneConfig& scene, int ranks) {
  std::array<double, Dim> cell{};
  std::array<bool, Dim> periodic{};
  std::array<std::vector<double>, Dim> cuts;
  for (int d = 0; d < Dim; ++d) cell[d] = scene.cell_size[d], periodic[d] = scene.periodic[d], cuts[d] = scene.cuts[d];
  return grid_decomposition<Dim>(cell, periodic, ranks, scene.process_grid, cuts);
}

template <int Dim, class ExecSpace>
Simulation<Dim, ExecSpace>::Simulation(const SceneConfig& scene, const ExecSpace& space, const Communicator& comm,
                                       Start start, const std::vector<Box<Dim>>& boxes)
    : scene_(scene),
      space_(space),
      comm_(comm),
      derived_(derive_parameters(scene)),
      particles_(scene.walls != WallType::None || scene.has_solid(), lagrangian_shifting(scene)),
      kernel_(derived_.smoothing_length) {
  if (scene.dimension != Dim) throw std::invalid_argument("Simulation: scene dimension does not match");
  fixed_ = scene.particle_motion == ParticleMotion::Fixed;
  if (fixed_) particles_.fix_positions();  // no x_start, no room to grow
  convection_ = fixed_ && scene.convection;
  volume_density_ = fixed_ ? scene.density : 0.0;
  // Particles that never move need no skin: their list is exact forever.
  const double skin = fixed_ ? 0.0 : scene.neighbour_skin * derived_.smoothing_length;
  Decomposition<Dim> decomposition;
  if (!boxes.empty()) {
    std::array<double, Dim> cell{};
    std::array<bool, Dim> periodic{};
    for (int d = 0; d < Dim; ++d) cell[d] = scene.cell_size[d], periodic[d] = scene.periodic[d];
    decomposition = Decomposition<Dim>(boxes, cell, periodic);
    decomposition.check(comm_.size());
    // An image is held in the pieces of the process grid's boxes: boxes of
    // another decomposition (a checkpoint of RCB's) would put particles
    // beyond their process's piece.
    if (scene.image.voxels && !same_boxes(decomposition, decompose<Dim>(scene, comm_.size())))
      throw std::invalid_argument(
          "the sub-domains given (a checkpoint's) are not the process grid an image scene is divided by: continue "
          "the run on another number of processes, which divides the cell anew");
  } else {
    // An image is held in the pieces of the process grid's boxes (scene/ImageScene.hpp).
    decomposition = scene.grid_decomposition || scene.image.voxels ? decompose<Dim>(scene, comm_.size())
                                                                   : rcb_decomposition<Dim>(scene, comm_);
  }
  neighbourhood_ = Neighbourhood<Dim, ExecSpace>(comm_, decomposition, scene.cell_size, kernel_.cutoff, skin, fixed_);
  const auto& box = neighbourhood_.box();
  double box_lo[Dim], box_hi[Dim];
  for (int d = 0; d < Dim; ++d) {
    box_lo[d] = box.lo[d], box_hi[d] = box.hi[d];
    body_force_[d] = scene.force_factor(0.0) * scene.body_force[d];
  }
  // The bound sqrt(3)/4 dx on d_a (Morris et al. 1997) keeps a moving
  // particle that nears a wall from a huge, noisy pull. Fixed particles have
  // no noise, and their drag is integrated exactly (PredictorCorrector.hpp),
  // so the bound only guards the division: as a lattice point next to the
  // surface should, it keeps almost no velocity (docs/method.md: with the
  // bound, the square array c = 0.2 at dx = 0.01 L came out 0.45 % high;
  // without it, 0.14 % low).
  const bool exact_wall_drag = scene.particle_motion == ParticleMotion::Fixed;
  fluid_ = FluidProperties{scene.kinematic_viscosity,
                           (exact_wall_drag ? 1e-6 : std::sqrt(3.0) / 4.0) * scene.particle_spacing, exact_wall_drag};
  reference_pressure_ =
      (1.0 - scene.background_pressure) * derived_.sound_speed * derived_.sound_speed * scene.density;

  pair_options_.shifting = ShiftingParameters{lagrangian_shifting(scene) ? scene.shifting_coefficient : 0.0,
                                              derived_.smoothing_length * derived_.time_step,
                                              0.05 * scene.particle_spacing};
  pair_options_.convection = convection_;
  extrapolate_walls_ = particles_.has_surfaces && scene.wall_pressure == WallPressure::Extrapolated;
  pair_options_.wall_continuity = !extrapolate_walls_;
  // Fixed particles' loop adds straight into their rates (the sums' first
  // copy, core/PairSums.hpp): its sums are d rho/dt, dv/dt and with
  // surfaces the wall drag, which its finish overwrites. Where the
  // surfaces' forces are measured (compute_surface_forces), boundary
  // particles' rates must be zero, as the finish leaves them without wall
  // continuity and without reactions in the time loop (grains held still).
  const int sum_components = pair_sum_components<Dim, ExecSpace>(particles_, pair_options_);
  const bool sums_in_rates = fixed_ && !scene.moving_grains() &&
                             !(particles_.has_surfaces && pair_options_.wall_continuity) &&
                             sum_components == 1 + Dim + (particles_.has_surfaces ? 1 : 0);
  pair_sums_ = PairSums<Dim, ExecSpace>(sum_components, sums_in_rates);
  check_grains(scene.grains, scene);
  solid_map_ = make_solid_map<Dim, MemorySpace>(scene, kernel_.cutoff);

  const double h = derived_.smoothing_length, dt = derived_.time_step;
  health_limits_ = HealthLimits{scene.density, scene.density_variation_limit, 0.25 * h / dt, h / (16 * dt * dt)};
  if (fixed_) make_stencils();
  make_step_stages();
  // Set before a checkpoint's particles load: they carry their grain, their phase.
  if (scene.moving_grains()) particles_.keep_grain_index();
  if (scene.has_phases()) {
    particles_.keep_phase();
    for (size_t p = 0; p < scene.phases.size(); ++p)
      fluid_.phase_kinematic_viscosity[p] = scene.phases[p].kinematic_viscosity;
    if (scene.surface_tension > 0 || scene.driven_phase >= 0) particles_.keep_phase_acceleration();
    if (scene.moving_interface) particles_.keep_colour();
  }
  if (start == Start::Empty) return;

  {  // the seeds (about 100 bytes a particle in 3D) are gone before the lists are made
    const auto seeds = fill_lattice<Dim>(scene, box_lo, box_hi);
    load_seeds<Dim, ExecSpace>(seeds, scene.density, scene.particle_spacing, particles_);
    long long fluid = 0;
    for (const auto& s : seeds) fluid += s.kind == kFluid;
    fluid_count_ = comm_.sum(fluid);
    total_count_ = comm_.sum(static_cast<long long>(seeds.size()));
  }
  // Nothing would flow: every measure of the run would be a plausible zero.
  if (fluid_count_ == 0) {
    std::ostringstream msg;
    msg << "the scene has no fluid particle: at Discretization/Particle Spacing = " << scene.particle_spacing
        << " every lattice point lies in a grain or a wall (" << total_count_
        << " boundary particles); refine the spacing or leave the grains room";
    throw std::invalid_argument(msg.str());
  }
  if (scene.has_phases()) place_phases();
  if (scene.moving_interface) {
    start_interface();  // the surface tension and the driven phase's force too
  } else {
    if (scene.surface_tension > 0) place_surface_tension();
    if (scene.driven_phase >= 0) place_phase_body_force(body_force_);
  }
  if (scene.moving_grains()) start_moving_grains();
  compute_rates();
  if (rigid_grains_.moving()) rigid_grains_.take_loads(particles_, comm_);
}

// Each particle's phase from its lattice point (scene/SceneConfig.hpp,
// phase_at), once: fixed particles never leave it. A phase that holds no
// fluid particle would report a saturation of zero as if measured.
template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::place_phases() {
  const int owned = particles_.owned;
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.kind);
  auto phase = Kokkos::create_mirror_view(particles_.phase);
  std::vector<long long> counts(scene_.phases.size(), 0);
  const bool drained = scene_.phases[1].drained(), labelled = scene_.phases[1].from_image();
  if (drained) drain_phase_one();
  for (int i = 0; i < owned; ++i) {
    double at[Dim];
    for (int d = 0; d < Dim; ++d) at[d] = x(i, d);
    if (kind(i) != kFluid)
      phase(i) = 0;
    else if (labelled)
      phase(i) = image_phase_one(at) ? 1 : 0;
    else
      phase(i) = drained ? drainage_.drained[lattice_point_index(at)] : phase_at(scene_, at);
    if (kind(i) == kFluid) ++counts[phase(i)];
  }
  drainage_.drained = std::vector<char>();
  Kokkos::deep_copy(particles_.phase, phase);
  for (size_t p = 1; p < counts.size(); ++p)
    if (comm_.sum(counts[p]) == 0) {
      std::ostringstream msg;
      if (labelled) {
        msg << "Phases/Phase " << p << "/Image Values: no fluid particle lies in a voxel of these values";
      } else if (drained) {
        double entering = 0;  // the largest step of the curve at which balls enter
        for (const auto& step : drainage_.curve)
          if (step.saturation > 0) entering = std::max(entering, step.radius);
        const auto& rule = scene_.phases[p].drainage;
        if (rule.capillary_pressure > 0)
          msg << "Phases/Phase " << p << "/Drainage/Capillary Pressure = " << rule.capillary_pressure
              << " Pa (balls of radius " << drainage_.radius << ")";
        else
          msg << "Phases/Phase " << p << "/Drainage/Radius = " << drainage_.radius;
        msg << ": no ball of that radius reaches from the inlet into the pore space, so the phase holds no fluid "
               "particle (balls of radius "
            << entering << " enter); make it "
            << (rule.capillary_pressure > 0 ? "larger (the radius smaller)" : "smaller");
      } else {
        msg << "Phases/Phase " << p
            << (scene_.phases[p].round() ? "/Region Centre and Region Radius: the disc (sphere)"
                                         : "/Region Low and Region High: the box")
            << " holds no fluid particle at Discretization/Particle Spacing = " << scene_.particle_spacing
            << " (it lies between lattice points, or in a grain or a wall); enlarge it";
      }
      throw std::invalid_argument(msg.str());
    }
}

// Whether the fluid particle at x is of phase 1 by the image's labels
// (PhaseConfig::image_values): the voxel holding x (on a face, the one
// above); in a solid voxel (the walls lie between voxels, smoothed), most
// of the pore voxels of the 3^Dim block about it. Read from this
// process's piece of the image, which holds its particles' voxels and a
// halo about them.
template <int Dim, class ExecSpace>
bool Simulation<Dim, ExecSpace>::image_phase_one(const double* x) const {
  const auto& values = scene_.phases[1].image_values;
  const auto& solid = scene_.image.solid_values;
  // -1 solid, 0 phase 0, 1 phase 1, of a voxel's value.
  auto label = [&](int value) {
    if (std::find(solid.begin(), solid.end(), value) != solid.end()) return -1;
    return std::find(values.begin(), values.end(), value) != values.end() ? 1 : 0;
  };
  const int own = label(image_value(x, {0, 0, 0}));
  if (own >= 0) return own == 1;
  int votes[2] = {0, 0};
  for (int value : image_block_values(x)) {
    const int l = label(value);
    if (l >= 0) ++votes[l];
  }
  return votes[1] > votes[0];
}

// The value of the image's voxel `offset` voxels from the one holding x,
// from this process's piece (which holds its particles' voxels and a halo).
template <int Dim, class ExecSpace>
int Simulation<Dim, ExecSpace>::image_value(const double* x, const long long (&offset)[3]) const {
  const ImageConfig& image = scene_.image;
  const VoxelImage& voxels = *image.voxels;
  const auto wraps = image_field_periodic(image, scene_.periodic);
  long long at[3] = {0, 0, 0};
  for (int d = 0; d < Dim; ++d) {
    // A lattice point on a face between voxels (a spacing of two voxels) is
    // x / voxel_size = a whole number to round-off: nudged to the voxel above.
    long long i = static_cast<long long>(std::floor(x[d] / image.voxel_size + 1e-9)) + offset[d] - image.piece_first[d];
    if (wraps[d])
      i = ((i % voxels.shape[d]) + voxels.shape[d]) % voxels.shape[d];
    else
      i = std::clamp(i, 0LL, voxels.shape[d] - 1);
    at[d] = i;
  }
  return voxels.at(at[0], at[1], at[2]);
}

// The values of the 3^Dim voxels about the one holding x, itself among them.
template <int Dim, class ExecSpace>
std::vector<int> Simulation<Dim, ExecSpace>::image_block_values(const double* x) const {
  std::vector<int> values;
  const int reach[3] = {1, Dim > 1 ? 1 : 0, Dim > 2 ? 1 : 0};
  for (long long k = -reach[2]; k <= reach[2]; ++k)
    for (long long j = -reach[1]; j <= reach[1]; ++j)
      for (long long i = -reach[0]; i <= reach[0]; ++i) values.push_back(image_value(x, {i, j, k}));
  return values;
}

// A fluid particle's lattice point as an index of the whole lattice
// (x fastest), from its position (i + 1/2) dx.
template <int Dim, class ExecSpace>
long long Simulation<Dim, ExecSpace>::lattice_point_index(const double* x) const {
  long long n = 0;
  for (int d = Dim - 1; d >= 0; --d) {
    const long long cells = std::llround(scene_.cell_size[d] / scene_.particle_spacing);
    n = n * cells + std::llround(x[d] / scene_.particle_spacing - 0.5);
  }
  return n;
}

// Phase 1 by drainage (scene/Drainage.hpp): every process marks its fluid
// particles' points on the whole lattice, the marks are joined, and each
// process places the phase on the same lattice (so the same points on any
// number of processes). It holds up to about kDrainageBytesPerPoint a
// lattice point while it does (flags, distances, transforms, the search's
// queue): refused up front, on every process alike, where the processes of
// a machine would not have that.
template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::drain_phase_one() {
  constexpr double kDrainageBytesPerPoint = 64;
  DrainageLattice lattice;
  lattice.dimension = Dim;
  for (int d = 0; d < Dim; ++d) {
    lattice.shape[d] = std::llround(scene_.cell_size[d] / scene_.particle_spacing);
    lattice.periodic[d] = scene_.periodic[d];
  }
  const MemoryBudget budget = machine_memory_budget(scene_.memory_limit_bytes, comm_.on_this_machine());
  const double need = kDrainageBytesPerPoint * static_cast<double>(lattice.size()) * budget.processes_on_machine;
  std::string problem;
  if (need > budget.available_bytes) {
    std::ostringstream msg;
    msg << std::setprecision(3) << "Phases/Phase 1/Drainage runs on the whole lattice on every process, up to "
        << kDrainageBytesPerPoint << " bytes a point: " << lattice.size() << " points on "
        << budget.processes_on_machine << " process(es) of this machine need " << need / 1e9 << " GB, and "
        << budget.available_bytes / 1e9 << " GB are available (" << budget.source
        << "); use fewer processes per machine or a coarser Discretization/Particle Spacing";
    problem = msg.str();
  }
  problem = comm_.first_problem(problem);
  if (!problem.empty()) throw std::invalid_argument(problem);
  lattice.fluid.assign(static_cast<size_t>(lattice.size()), 0);
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.kind);
  for (int i = 0; i < particles_.owned; ++i) {
    if (kind(i) != kFluid) continue;
    double at[Dim];
    for (int d = 0; d < Dim; ++d) at[d] = x(i, d);
    lattice.fluid[static_cast<size_t>(lattice_point_index(at))] = 1;
  }
  comm_.any(lattice.fluid);
  drainage_ = place_by_drainage(scene_.phases[1].drainage, lattice, scene_.particle_spacing);
}

// The surface tension's acceleration of each owned fluid particle, once
// (physics/SurfaceTension.hpp): the colour of every lattice point is the
// scene's (phase_at, phase_one_fraction), so that no ghost is needed.
// Surface tension is only taken in a periodic cell without boundary
// particles (scene/SceneBuilder.cpp), where every lattice point is fluid.
template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::place_surface_tension() {
  const double dx = scene_.particle_spacing;
  std::array<long long, Dim> cells{};
  for (int d = 0; d < Dim; ++d) cells[d] = std::llround(scene_.cell_size[d] / dx);
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x);
  std::vector<std::array<long long, Dim>> points(particles_.owned);
  for (int i = 0; i < particles_.owned; ++i)
    for (int d = 0; d < Dim; ++d)
      points[i][d] = ((static_cast<long long>(std::floor(x(i, d) / dx)) % cells[d]) + cells[d]) % cells[d];
  // Sub-cells per axis for a disc's (sphere's) share of a lattice cell: its
  // sampling error in the colour stays below 1/samples^Dim of a cell.
  const int samples = Dim == 2 ? 16 : 8;
  const bool fraction = scene_.colour == ColourFunction::VolumeFraction;
  const auto colour = [&](const std::array<long long, Dim>& i) {
    double at[Dim];
    for (int d = 0; d < Dim; ++d) at[d] = (static_cast<double>(i[d]) + 0.5) * dx;
    return fraction ? phase_one_fraction(scene_, at, dx, samples) : (phase_at(scene_, at) == 1 ? 1.0 : 0.0);
  };
  const auto geometry = interface_geometry<Dim>(points, cells, dx, derived_.smoothing_length, colour);
  auto acceleration = Kokkos::create_mirror_view(particles_.phase_acceleration);
  for (int i = 0; i < particles_.owned; ++i) {
    const Vec<Dim> a = surface_tension_acceleration<Dim>(scene_.surface_tension, geometry[i].smoothed_curvature,
                                                         geometry[i].normal, scene_.density);
    for (int d = 0; d < Dim; ++d) acceleration(i, d) = a[d];
  }
  Kokkos::deep_copy(particles_.phase_acceleration, acceleration);
}

// A moving interface's start: phi of each fluid particle from the phases'
// placement (the share of its lattice cell in phase 1's box or disc, else
// its phase), then the field on the lattice and the forces from it.
template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::start_interface() {
  const double dx = scene_.particle_spacing;
  const int samples = Dim == 2 ? 16 : 8;
  const PhaseConfig& second = scene_.phases[1];
  const bool placed_by_region = !second.drained() && !second.from_image();
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x);
  const auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.kind);
  const auto phase = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.phase);
  auto colour = Kokkos::create_mirror_view(particles_.colour);
  for (int i = 0; i < particles_.owned; ++i) {
    double at[Dim];
    for (int d = 0; d < Dim; ++d) at[d] = x(i, d);
    colour(i) = kind(i) != kFluid    ? 0.0
                : placed_by_region ? phase_one_fraction(scene_, at, dx, samples)
                                   : static_cast<double>(phase(i));
  }
  Kokkos::deep_copy(particles_.colour, colour);
  make_phase_field();
  place_interface_forces(fluid_lattice_points());
}

// The lattice of the whole cell with the owned fluid particles' phi on
// their points; every other point is solid (a grain, an image's solid, or
// beyond a wall). The mobility's rule: the capillary speed sigma / mu of
// the more viscous phase (the speed at which surface tension moves an
// interface against viscosity; without surface tension the flow's velocity
// scale), capped where the explicit update would take more than one
// sub-step per time step.
template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::make_phase_field() {
  const double dx = scene_.particle_spacing;
  std::array<long long, Dim> cells{};
  std::array<bool, Dim> periodic{};
  for (int d = 0; d < Dim; ++d)
    cells[d] = std::llround(scene_.cell_size[d] / dx), periodic[d] = scene_.periodic[d];
  PhaseFieldSettings settings;
  settings.width = scene_.interface_width * dx;
  settings.smoothing_length = scene_.smoothing_length_ratio * dx;
  settings.cos_contact_angle = std::cos(scene_.contact_angle * 3.14159265358979323846 / 180);
  double mobility = scene_.interface_mobility;
  if (!(mobility > 0)) {
    double mu = 0;
    for (const auto& p : scene_.phases) mu = std::max(mu, p.density * p.kinematic_viscosity);
    mobility = scene_.surface_tension > 0 && mu > 0 ? scene_.surface_tension / mu : derived_.velocity_scale;
    const double one_substep =
        0.5 * std::min(dx * dx / (2 * Dim * settings.width), dx) / derived_.time_step;  // gamma of stable_step = dt
    mobility = std::min(mobility, one_substep);
  }
  settings.mobility = mobility;
  std::size_t points = 1;
  for (int d = 0; d < Dim; ++d) points *= static_cast<std::size_t>(cells[d]);
  const auto colour = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.colour);
  std::vector<double> owned_phi(static_cast<std::size_t>(particles_.owned));
  for (int i = 0; i < particles_.owned; ++i) owned_phi[i] = colour(i);
  const LatticeValues all = gather_on_lattice(fluid_lattice_points(), owned_phi, 1);
  std::vector<char> fluid(points, 0);
  std::vector<double> phi(points, 0.0);
  for (std::size_t j = 0; j < all.points.size(); ++j) {
    const auto k = static_cast<std::size_t>(all.points[j]);
    fluid[k] = 1, phi[k] = all.values[j];
  }
  phase_field_ = std::make_unique<LatticePhaseField<Dim>>(cells, periodic, dx, settings, std::move(fluid),
                                                          solid_wetting(points, settings.cos_contact_angle));
  phase_field_->values() = std::move(phi);
}

// With Phases/Contact Angles, cos(theta) at each solid lattice point: a
// grain's boundary particle takes its grain's angle, an image's the angle
// of its voxel's solid value (of the solid values about it, the most
// common, where the smoothed surface leaves it in a pore voxel). Gathered
// from every process, as the field is whole on each; a solid point without
// a particle (deep in a solid, which no fluid point faces) keeps the scene's
// angle. Empty without per-solid angles.
template <int Dim, class ExecSpace>
std::vector<double> Simulation<Dim, ExecSpace>::solid_wetting(std::size_t points, double cos_everywhere) const {
  const auto& angles = scene_.solid_contact_angles;
  if (angles.empty()) return {};
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x);
  const auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.kind);
  const auto grain = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), grain_ids());
  const auto& solid = scene_.image.solid_values;
  const auto solid_index = [&](int value) {
    return static_cast<int>(std::find(solid.begin(), solid.end(), value) - solid.begin());
  };
  const int solids = static_cast<int>(solid.size());
  std::vector<long long> at(static_cast<std::size_t>(particles_.owned), -1);
  std::vector<double> cosine(static_cast<std::size_t>(particles_.owned), cos_everywhere);
  for (int i = 0; i < particles_.owned; ++i) {
    double p[Dim];
    bool inside = true;
    for (int d = 0; d < Dim; ++d) p[d] = x(i, d), inside = inside && p[d] >= 0 && p[d] < scene_.cell_size[d];
    if (kind(i) == kFluid || kind(i) == kWallBoundary || !inside) continue;  // plane walls: the scene's angle
    int which = -1;
    if (kind(i) == kGrainBoundary) {
      which = grain(i);
    } else {
      which = solid_index(image_value(p, {0, 0, 0}));
      if (which == solids) {
        std::vector<int> votes(static_cast<std::size_t>(solids), 0);
        for (int value : image_block_values(p)) {
          const int s = solid_index(value);
          if (s < solids) ++votes[static_cast<std::size_t>(s)];
        }
        const auto most = std::max_element(votes.begin(), votes.end());
        which = *most > 0 ? static_cast<int>(most - votes.begin()) : -1;
      }
    }
    if (which < 0) continue;
    at[static_cast<std::size_t>(i)] = lattice_point_index(p);
    const double degrees = angles[static_cast<std::size_t>(which)];
    cosine[static_cast<std::size_t>(i)] = std::cos(degrees * 3.14159265358979323846 / 180);
  }
  const LatticeValues all = gather_on_lattice(at, cosine, 1);
  std::vector<double> solid_cos(points, cos_everywhere);
  for (std::size_t j = 0; j < all.points.size(); ++j)
    solid_cos[static_cast<std::size_t>(all.points[j])] = all.values[j];
  return solid_cos;
}

// After the step: phi carried by the fluid's velocity over it, and the
// phases and forces of the next step from the new phi.
template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::interface_stage() {
  const auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.v);
  // Fixed particles keep their points until the neighbourhood is built anew (built_neighbourhood).
  if (interface_points_.empty()) interface_points_ = fluid_lattice_points();
  const std::vector<long long>& at = interface_points_;
  std::vector<Vec<Dim>>& velocity = lattice_velocity_;  // kept: made anew each step it costs its pages
  velocity.assign(phase_field_->size(), Vec<Dim>::zero());
  if (comm_.size() == 1) {
    for (int i = 0; i < particles_.owned; ++i)
      if (at[static_cast<std::size_t>(i)] >= 0)
        for (int d = 0; d < Dim; ++d) velocity[static_cast<std::size_t>(at[static_cast<std::size_t>(i)])][d] = v(i, d);
  } else {
    // Every process's fluid points, gathered once with its counts (they stay
    // until the neighbourhood is built anew); then the velocities alone.
    if (gathered_points_.empty()) {
      std::vector<long long> mine;
      for (long long k : at)
        if (k >= 0) mine.push_back(k);
      gathered_counts_ = comm_.all_gather_counts(static_cast<int>(mine.size()));
      long long total = 0;
      for (int count : gathered_counts_) total += count;
      gathered_points_.resize(static_cast<std::size_t>(total));
      comm_.all_gather(mine.data(), gathered_counts_, gathered_points_.data());
      for (int& count : gathered_counts_) count *= Dim;  // the velocities' values
    }
    std::vector<double> owned_velocity;
    owned_velocity.reserve(static_cast<std::size_t>(particles_.owned) * Dim);
    for (int i = 0; i < particles_.owned; ++i)
      if (at[static_cast<std::size_t>(i)] >= 0)
        for (int d = 0; d < Dim; ++d) owned_velocity.push_back(v(i, d));
    std::vector<double> all(gathered_points_.size() * Dim);
    comm_.all_gather(owned_velocity.data(), gathered_counts_, all.data());
    for (std::size_t j = 0; j < gathered_points_.size(); ++j)
      for (int d = 0; d < Dim; ++d) velocity[static_cast<std::size_t>(gathered_points_[j])][d] = all[j * Dim + d];
  }
  phase_field_->advance(derived_.time_step, velocity);
  place_interface_forces(at);
}

// Each owned particle's lattice point (lattice_point_index) if it is a
// fluid particle, -1 if it is a boundary particle.
template <int Dim, class ExecSpace>
std::vector<long long> Simulation<Dim, ExecSpace>::fluid_lattice_points() const {
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x);
  const auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.kind);
  std::vector<long long> points(static_cast<std::size_t>(particles_.owned), -1);
  for (int i = 0; i < particles_.owned; ++i) {
    if (kind(i) != kFluid) continue;
    double at[Dim];
    for (int d = 0; d < Dim; ++d) at[d] = x(i, d);
    points[i] = lattice_point_index(at);
  }
  return points;
}

// The phase field is whole on every process, and each advances it alike
// from the same values: every process's fluid particles, gathered
// (MPI_Allgatherv; on one process, its own). Its cost does not fall with
// the processes: it is for scenes whose lattice one process can hold.
template <int Dim, class ExecSpace>
typename Simulation<Dim, ExecSpace>::LatticeValues Simulation<Dim, ExecSpace>::gather_on_lattice(
    const std::vector<long long>& at, const std::vector<double>& values, int components) const {
  LatticeValues mine;
  for (std::size_t i = 0; i < at.size(); ++i) {
    if (at[i] < 0) continue;
    mine.points.push_back(at[i]);
    mine.values.insert(mine.values.end(), values.begin() + static_cast<std::ptrdiff_t>(i * components),
                       values.begin() + static_cast<std::ptrdiff_t>((i + 1) * components));
  }
  if (comm_.size() == 1) return mine;
  const std::vector<int> counts = comm_.all_gather_counts(static_cast<int>(mine.points.size()));
  std::vector<int> value_counts(counts);
  long long total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) total += counts[r], value_counts[r] *= components;
  LatticeValues all;
  all.points.resize(static_cast<std::size_t>(total));
  all.values.resize(static_cast<std::size_t>(total) * static_cast<std::size_t>(components));
  comm_.all_gather(mine.points.data(), counts, all.points.data());
  comm_.all_gather(mine.values.data(), value_counts, all.values.data());
  return all;
}

// Each fluid particle's phi from the field, its phase (1 where phi >= 1/2)
// and its phase acceleration: the surface force sigma kappa grad(phi) / rho0
// and, with one phase driven, the body force on its phase.
template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::place_interface_forces(const std::vector<long long>& at) {
  const auto& phi = phase_field_->values();
  const bool forces = particles_.has_phase_acceleration;
  const std::vector<Vec<Dim>>* surface =
      forces && scene_.surface_tension > 0 ? &phase_field_->surface_force(scene_.surface_tension) : nullptr;
  auto colour = Kokkos::create_mirror_view(particles_.colour);
  auto phase = Kokkos::create_mirror_view(particles_.phase);
  auto acceleration = Kokkos::create_mirror_view(particles_.phase_acceleration);
  Kokkos::deep_copy(phase, particles_.phase);
  for (int i = 0; i < particles_.owned; ++i) {
    if (at[i] < 0) {
      colour(i) = 0;
      continue;
    }
    const auto k = static_cast<std::size_t>(at[i]);
    colour(i) = phi[k];
    phase(i) = phi[k] >= 0.5 ? 1 : 0;
    if (!forces) continue;
    // The finish adds the body force itself unless one phase alone is driven.
    Vec<Dim> a = scene_.driven_phase >= 0 ? scene_.phase_force_share(phase(i)) * body_force_ : Vec<Dim>::zero();
    if (surface) a += (1.0 / scene_.density) * (*surface)[k];
    for (int d = 0; d < Dim; ++d) acceleration(i, d) = a[d];
  }
  Kokkos::deep_copy(particles_.colour, colour);
  Kokkos::deep_copy(particles_.phase, phase);
  if (forces) Kokkos::deep_copy(particles_.phase_acceleration, acceleration);
}

// With one phase driven (Phases/Driven Phase), the body force enters each
// fluid particle of that phase through its phase acceleration (on top of
// any surface tension's), and the finish adds no force of its own
// (finish_body_force).
template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::place_phase_body_force(const Vec<Dim>& body_force) {
  const auto acceleration = particles_.phase_acceleration;
  const auto kind = particles_.kind, phase = particles_.phase;
  const PhaseBodyForce<Dim, MemorySpace> force = phase_body_force(body_force);
  static const std::string label = "poresph::place_phase_body_force";
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(space_, 0, particles_.owned), KOKKOS_LAMBDA(int a) {
        if (kind(a) != kFluid) return;
        for (int d = 0; d < Dim; ++d) acceleration(a, d) += force.of(a)[d];
      });
  space_.fence();
}

// Phases/Force Steps: the body force of the span the step starts in. With
// one phase driven, its particles carry the force in their phase
// acceleration (which the interface stage of the step before set): they
// take the change there too.
template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::force_step_stage() {
  const double factor = scene_.force_factor(time_);
  Vec<Dim> change = Vec<Dim>::zero();
  bool changed = false;
  for (int d = 0; d < Dim; ++d) {
    change[d] = factor * scene_.body_force[d] - body_force_[d];
    changed = changed || change[d] != 0;
  }
  if (!changed) return;
  for (int d = 0; d < Dim; ++d) body_force_[d] = factor * scene_.body_force[d];
  if (scene_.driven_phase >= 0) place_phase_body_force(change);
}

template <int Dim, class ExecSpace>
PhaseBodyForce<Dim, typename ExecSpace::memory_space> Simulation<Dim, ExecSpace>::phase_body_force(
    const Vec<Dim>& body_force) const {
  PhaseBodyForce<Dim, MemorySpace> force;
  if (scene_.driven_phase < 0) return force;
  force.phase = particles_.phase;
  for (int p = 0; p < 2; ++p) force.force[p] = scene_.phase_force_share(p) * body_force;
  return force;
}

template <int Dim, class ExecSpace>
Vec<Dim> Simulation<Dim, ExecSpace>::finish_body_force() const {
  return scene_.driven_phase < 0 ? body_force_ : Vec<Dim>::zero();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::add_phase_acceleration() {
  const auto dvdt = particles_.dvdt, acceleration = particles_.phase_acceleration;
  static const std::string label = "poresph::add_phase_acceleration";
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(space_, 0, particles_.owned), KOKKOS_LAMBDA(int a) {
        for (int d = 0; d < Dim; ++d) dvdt(a, d) += acceleration(a, d);
      });
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::start_moving_grains() {
  const int owned = particles_.owned;
  Kokkos::deep_copy(space_, Kokkos::subview(particles_.grain, Kokkos::make_pair(0, owned)), grain_ids());
  rigid_grains_ = RigidGrains<Dim, ExecSpace>(scene_, comm_.sum(local_fluid_mass()), derived_.contact_modulus);
  rigid_grains_.set_particle_velocities(space_, particles_);
  couple_grains();
}

// What the fluid's steps take of the moving grains: their share of the body
// force, the loads on them, and their spins in the no-slip.
template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::couple_grains() {
  for (int d = 0; d < Dim; ++d) body_force_[d] = rigid_grains_.fluid_body_force()[d];
  pair_options_.surface_reactions = true;
  no_slip_factors_.set_grain_spin(rigid_grains_.spin_view());
}

template <int Dim, class ExecSpace>
double Simulation<Dim, ExecSpace>::local_fluid_mass(int phase) const {
  const auto kind = particles_.kind;
  const auto m = particles_.m;
  const auto which = particles_.phase;
  double mass = 0;
  static const std::string label = "poresph::fluid_mass";
  Kokkos::parallel_reduce(
      label, Kokkos::RangePolicy<ExecSpace>(space_, 0, particles_.owned),
      KOKKOS_LAMBDA(int i, double& sum) { sum += kind(i) == kFluid && (phase < 0 || which(i) == phase) ? m(i) : 0.0; },
      mass);
  return mass;
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::restore_grains(double fluid_mass, const std::vector<double>& state) {
  rigid_grains_ = RigidGrains<Dim, ExecSpace>(scene_, fluid_mass, derived_.contact_modulus);
  rigid_grains_.restore(state);
  couple_grains();
  follow_grains();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::place_grains() {
  rigid_grains_.place(space_, particles_);
  space_.fence();
  follow_grains();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::follow_grains() {
  const auto& bodies = rigid_grains_.bodies();
  for (size_t g = 0; g < bodies.size(); ++g)
    for (int d = 0; d < Dim; ++d) {
      double c = bodies[g].centre[d];
      if (scene_.periodic[d]) c -= scene_.cell_size[d] * std::floor(c / scene_.cell_size[d]);
      scene_.grains[g].centre[d] = c;
    }
  solid_map_ = make_solid_map<Dim, MemorySpace>(scene_, kernel_.cutoff);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::grains_predict_stage() {
  rigid_grains_.predict(derived_.time_step);
  place_grains();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::grain_loads_stage() {
  rigid_grains_.take_loads(particles_, comm_);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::grains_correct_stage() {
  rigid_grains_.correct(derived_.time_step);
  place_grains();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::update_pressure_and_ghosts() {
  update_pressure(space_, particles_, derived_.sound_speed * derived_.sound_speed, reference_pressure_,
                  volume_density_);
  space_.fence();
  neighbourhood_.update_ghosts(particles_);
  update_wall_pressure();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::update_wall_pressure() {
  if (!extrapolate_walls_) return;
  extrapolate_wall_pressure(space_, particles_, wall_neighbours_, kernel_, body_force_,
                            derived_.sound_speed * derived_.sound_speed, scene_.density, reference_pressure_,
                            volume_density_, rigid_grains_.wall_acceleration(), phase_body_force(body_force_));
  space_.fence();
  neighbourhood_.update_ghosts(particles_);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::refresh_neighbourhood() {
  refresh_neighbourhood_only();
  update_wall_pressure();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::refresh_neighbourhood_only() {
  const bool moving_owners = next_decomposition_.has_value();
  const auto start = moving_owners ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point();
  if (moving_owners) {  // a rebalance: the particles go to their new owners now
    const double skin = scene_.neighbour_skin * derived_.smoothing_length;
    neighbourhood_ =
        Neighbourhood<Dim, ExecSpace>(comm_, *next_decomposition_, scene_.cell_size, kernel_.cutoff, skin, fixed_);
    next_decomposition_.reset();
  }
  // Fixed particles keep their first list; moving ones until some has gone half the skin.
  const bool rebuild = !neighbourhood_.built() || (!fixed_ && neighbourhood_.stale(space_, particles_));
  update_pressure(space_, particles_, derived_.sound_speed * derived_.sound_speed, reference_pressure_,
                  volume_density_);
  space_.fence();
  if (!rebuild) {
    neighbourhood_.update_ghosts(particles_);
  } else {
    neighbourhood_.rebuild(space_, particles_);
    built_neighbourhood();
  }
  if (moving_owners) {
    space_.fence();
    dividing_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::built_neighbourhood() {
  // The particles may have moved to other owners or places in their arrays.
  interface_points_.clear(), gathered_points_.clear();
  if (extrapolate_walls_) wall_neighbours_.build(space_, neighbourhood_.cells(), particles_, neighbourhood_.reach());
  if (fixed_) find_pair_geometry();
  // Fixed particles' lists are made for good: the cells (8 bytes a slot
  // and a quarter more) come back only for what interpolates
  // (Neighbourhood::ensure_cells), and are gone before the no-slip factors
  // are made, so that the two are never held at once.
  if (fixed_) neighbourhood_.release_cells();
  if (fixed_ && particles_.has_surfaces)
    no_slip_factors_.build(space_, particles_, neighbourhood_.list(), fluid_.min_surface_distance);
  else
    no_slip_factors_.clear();
  // Fixed particles' volumes use rho0: 1/rho is a constant of the pair loop
  // (they hold no inverse_density), and so is m where they have one mass.
  pair_options_.uniform_mass = fixed_ ? common_mass(space_, particles_, particles_.total()) : 0.0;
  pair_options_.uniform_inverse_density = fixed_ ? 1.0 / volume_density_ : 0.0;
  pair_sums_.reserve(particles_.owned, !fixed_);
}

// Fixed particles, at set-up: the stencils of the lattice's offsets, from
// the scene's spacing and kernel, and the pair stencil for the rows the
// neighbourhood's builds make (core/LatticeRows.hpp).
template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::make_stencils() {
  std::array<double, Dim> spacing{};
  spacing.fill(scene_.particle_spacing);  // the lattice is square (cubic): geometry/Lattice.hpp
  const auto kernel = kernel_;
  pair_stencil_ = LatticeStencil<Dim, MemorySpace>(spacing, neighbourhood_.reach(),
                                                   [&](double r) { return kernel.derivative_over_r(r); });
  if (extrapolate_walls_)
    wall_stencil_ = LatticeStencil<Dim, MemorySpace>(spacing, neighbourhood_.reach(),
                                                     [&](double r) { return kernel.value(r); });
  neighbourhood_.use_lattice_rows(pair_stencil_, scene_.particle_spacing);
}

// The stencil where every entry of both lists, on every process, is a
// lattice offset (the pair list's rows then masks over it where they could
// be made so, core/LatticeRows.hpp): then the run reads the same table
// everywhere, whatever the process count. Else every process caches each
// entry's geometry.
template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::find_pair_geometry() {
  auto& list = neighbourhood_.list();
  const auto& x = particles_.x;
  const int owned = particles_.owned;
  bool lattice = list.on_lattice_rows() || list.find_stencil_ids(space_, x, owned, pair_stencil_);
  if (extrapolate_walls_) lattice = wall_neighbours_.find_stencil_ids(space_, x, owned, wall_stencil_) && lattice;
  if (!comm_.any(!lattice)) {
    if (!list.on_lattice_rows()) list.use_stencil(space_, pair_stencil_);
    if (extrapolate_walls_) wall_neighbours_.use_stencil(wall_stencil_);
  } else {
    if (list.on_lattice_rows()) neighbourhood_.build_list(space_, particles_);
    list.cache_geometry(space_, x, owned, kernel_);
    if (extrapolate_walls_) wall_neighbours_.cache_geometry(space_, x, owned, kernel_);
  }
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::compute_rates() {
  neighbourhood_stage();
  wall_pressure_stage();
  pair_rates_stage();
  finish_stage();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::compute_rates(RateTerms terms) {
  if (terms == RateTerms::All) return compute_rates();
  neighbourhood_stage();
  const auto& list = neighbourhood_.list();
  if (terms == RateTerms::Pressure) {
    wall_pressure_stage();
    compute_pair_rates_of(space_, particles_, list, pair_sums_, kernel_, fluid_, body_force_, pair_options_,
                          no_slip_factors_, PairTermList<PressureTerm<Dim, ExecSpace>>{});
  } else if (terms == RateTerms::Velocity || terms == RateTerms::Viscous) {
    PairLoopOptions options = pair_options_;
    options.convection = options.convection && terms == RateTerms::Velocity;
    compute_velocity_rates(space_, particles_, list, pair_sums_, kernel_, fluid_, body_force_, options,
                           no_slip_factors_);
  } else {
    compute_pair_rates_of(space_, particles_, list, pair_sums_, kernel_, fluid_, body_force_, pair_options_,
                          no_slip_factors_, PairTermList<ContinuityTerm<Dim, ExecSpace>>{});
  }
  space_.fence();
}

template <int Dim, class ExecSpace>
bool Simulation<Dim, ExecSpace>::take_linear_state() {
  const auto& list = neighbourhood_.list();
  if (!fixed_ || comm_.any(!list.on_lattice_rows())) return false;
  const int slots = particles_.total();
  if (!lattice_products_.built()) {
    lattice_products_ = LatticeProducts<Dim, ExecSpace>(space_, list.lattice_rows(), particles_);
    if (comm_.any(!lattice_products_.built())) {
      lattice_products_ = {};
      return false;
    }
    pressure_slope_ = Scalars("poresph::Simulation::pressure_slope", slots);
    slot_scalars_ = Scalars("poresph::Simulation::slot_scalars", slots);
    slot_rows_ = Rows("poresph::Simulation::slot_rows", slots, Dim);
    if (extrapolate_walls_) {
      const double c2 = derived_.sound_speed * derived_.sound_speed;
      wall_pressure_weights_ = WallPressureWeights<Dim, ExecSpace>(space_, particles_, wall_neighbours_, kernel_,
                                                                   body_force_, c2, phase_body_force(body_force_));
    }
  }
  // Each slot's d(p/rho^2)/dp at the state: fluid and boundary particles
  // alike (an extrapolated wall has rho = p / c^2 too).
  const auto P = particles_;
  const auto slope = pressure_slope_;
  const double c2 = derived_.sound_speed * derived_.sound_speed, reference = reference_pressure_;
  static const std::string label = "poresph::Simulation::take_linear_state";
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(space_, 0, slots), KOKKOS_LAMBDA(int j) {
        slope(j) = pressure_term_slope(P.p(j) - reference, P.rho(j), c2);
      });
  space_.fence();
  if (linear_velocity_products(RateTerms::Viscous) && !lattice_products_.has_fluid_masses()) {  // fixed masses: once
    fluid_mass_ = Scalars("poresph::Simulation::fluid_mass", slots);
    const auto mass = fluid_mass_;
    static const std::string label_mass = "poresph::Simulation::take_linear_state_fluid_mass";
    Kokkos::parallel_for(
        label_mass, Kokkos::RangePolicy<ExecSpace>(space_, 0, slots),
        KOKKOS_LAMBDA(int j) { mass(j) = P.kind(j) == kFluid ? P.m(j) : 0.0; });
    space_.fence();
    lattice_products_.take_fluid_masses(fluid_mass_);
  }
  return true;
}

// The viscous terms are Morris's between fluid particles, with 1/rho0 for
// every 1/rho, and the walls' drag: linear in the velocities and the same
// at every state, a stencil sum unless a second fluid's viscosities enter;
// the whole velocity block is that where there is no convection.
template <int Dim, class ExecSpace>
bool Simulation<Dim, ExecSpace>::linear_velocity_products(RateTerms terms) const {
  const bool viscous_only = terms == RateTerms::Viscous || (terms == RateTerms::Velocity && !pair_options_.convection);
  return viscous_only && lattice_products_.built() && !particles_.has_phase &&
         pair_options_.uniform_inverse_density > 0 && (fluid_.separate_wall_drag || !particles_.has_surfaces);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::pressure_product(const Scalars& dp, const Rows& dvdt) {
  const auto P = particles_;
  const auto values = slot_scalars_, slope = pressure_slope_;
  const int owned = particles_.owned, slots = particles_.total();
  static const std::string label_take = "poresph::Simulation::pressure_product_take";
  Kokkos::parallel_for(
      label_take, Kokkos::RangePolicy<ExecSpace>(space_, 0, owned),
      KOKKOS_LAMBDA(int i) { values(i) = P.kind(i) == kFluid ? dp(i) : 0.0; });
  space_.fence();
  neighbourhood_.update_ghost_values(values, owned);
  // The walls' pressures follow the fluid's (or keep their own: continuity).
  if (extrapolate_walls_) {
    extrapolate_wall_pressure_change(space_, particles_, wall_neighbours_, wall_pressure_weights_, values);
    space_.fence();
  }
  static const std::string label_terms = "poresph::Simulation::pressure_product_terms";
  Kokkos::parallel_for(
      label_terms, Kokkos::RangePolicy<ExecSpace>(space_, 0, slots), KOKKOS_LAMBDA(int j) { values(j) *= slope(j); });
  space_.fence();
  if (extrapolate_walls_) neighbourhood_.update_ghost_values(values, owned);
  lattice_products_.gradient(values, particles_.m, dvdt);
}

// The owned fluid particles' rows of dv in the slots (zero on other
// particles), the ghosts' from their owners: what the products of a
// velocity change gather from.
template <int Dim, class ExecSpace>
typename Simulation<Dim, ExecSpace>::Rows Simulation<Dim, ExecSpace>::fluid_rows_in_slots(const Rows& dv) {
  const auto P = particles_;
  const auto values = slot_rows_;
  const int owned = particles_.owned;
  static const std::string label_take = "poresph::Simulation::fluid_rows_in_slots";
  Kokkos::parallel_for(
      label_take, Kokkos::RangePolicy<ExecSpace>(space_, 0, owned), KOKKOS_LAMBDA(int i) {
        for (int d = 0; d < Dim; ++d) values(i, d) = P.kind(i) == kFluid ? dv(i, d) : 0.0;
      });
  space_.fence();
  neighbourhood_.update_ghost_values(values, owned);
  return values;
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::continuity_product(const Rows& dv, const Scalars& drhodt) {
  const Rows values = fluid_rows_in_slots(dv);
  lattice_products_.divergence(values, particles_.m, drhodt);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::velocity_product(const Rows& dv, const Rows& dvdt) {
  const Rows values = fluid_rows_in_slots(dv);
  const double coefficient = 2.0 * fluid_.kinematic_viscosity * pair_options_.uniform_inverse_density;
  lattice_products_.viscous(values, fluid_mass_, coefficient, dvdt);
}

template <int Dim, class ExecSpace>
double Simulation<Dim, ExecSpace>::linear_product_values() const {
  if (!lattice_products_.built()) return 0;
  return lattice_products_.values_held() + static_cast<double>(pressure_slope_.extent(0)) * (2 + Dim) +
         static_cast<double>(wall_pressure_weights_.entries()) +
         static_cast<double>(fluid_mass_.extent(0));
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::make_step_stages() {
  using S = Simulation;
  const bool grains_move = scene_.moving_grains();
  step_stages_ = {};
  if (!scene_.force_steps.empty()) step_stages_.push_back({"poresph::step::force_step", &S::force_step_stage});
  step_stages_.push_back({"poresph::step::predict", &S::predict_stage});
  if (grains_move) step_stages_.push_back({"poresph::step::grains_predict", &S::grains_predict_stage});
  step_stages_.push_back({"poresph::step::neighbourhood", &S::neighbourhood_stage});
  if (extrapolate_walls_) step_stages_.push_back({"poresph::step::wall_pressure", &S::wall_pressure_stage});
  step_stages_.push_back({"poresph::step::pair_rates", &S::pair_rates_stage});
  step_stages_.push_back({"poresph::step::finish", &S::finish_stage});
  if (grains_move) step_stages_.push_back({"poresph::step::grain_loads", &S::grain_loads_stage});
  step_stages_.push_back({"poresph::step::correct", &S::correct_stage});
  if (scene_.moving_interface) step_stages_.push_back({"poresph::step::interface", &S::interface_stage});
  if (grains_move) step_stages_.push_back({"poresph::step::grains_correct", &S::grains_correct_stage});
  if (particles_.has_shifting || (!fixed_ && !solid_map_.empty()))
    step_stages_.push_back({"poresph::step::constraints", &S::constraints_stage});
  step_stages_.push_back({"poresph::step::check", &S::check_stage});
  if (!fixed_ && scene_.resummation_interval > 0)
    step_stages_.push_back({"poresph::step::density_resummation", &S::resummation_stage});
  measure_balance_ = !fixed_ && comm_.size() > 1;
  if (measure_balance_) {
    step_stages_.push_back({"poresph::step::balance", &S::balance_stage});
    balance_start_ = std::chrono::steady_clock::now();
  }
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::step() {
  // The work this process did in the step: its wall time less the time in
  // collective operations, where it waits for the others.
  const auto start = measure_balance_ ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point();
  const double waited = communication_seconds();
  for (const StepStage& stage : step_stages_) {
    Kokkos::Profiling::pushRegion(stage.name);
    (this->*stage.run)();
    Kokkos::Profiling::popRegion();
  }
  space_.fence();
  if (measure_balance_)
    compute_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() -
                        (communication_seconds() - waited);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::balance_stage() {
  if (++balance_steps_ < scene_.rebalance_interval) return;
  const auto now = std::chrono::steady_clock::now();
  const double steps = balance_steps_;
  BalanceRecord& b = balance_;
  b.step = steps_;
  b.seconds_per_step = comm_.max(std::chrono::duration<double>(now - balance_start_).count()) / steps;
  b.compute_max = comm_.max(compute_seconds_) / steps;
  b.compute_mean = comm_.sum(compute_seconds_) / comm_.size() / steps;
  b.imbalance = b.compute_mean > 0 ? b.compute_max / b.compute_mean : 1.0;
  b.particles_min = -comm_.max(-particles_.owned);
  b.particles_max = comm_.max(particles_.owned);
  // A division made at the last measurement moved its particles in this
  // interval: its cost is the slowest process's time in both.
  const double divided = comm_.max(dividing_seconds_);
  if (divided > 0) b.division_seconds = divided;
  dividing_seconds_ = 0;
  const bool past = scene_.rebalance_threshold > 0 && b.imbalance > scene_.rebalance_threshold;
  // What balance would have saved: the slowest process's excess working
  // time, counted where the imbalance is past the threshold (below it, the
  // user's threshold says, it is noise a division cannot take away).
  if (past) lost_since_division_ += (b.compute_max - b.compute_mean) * steps;
  b.lost_seconds = lost_since_division_;
  // Divide once the time lost pays for a division (the first, of unknown
  // cost, at once): a division that costs more than it saves, such as one
  // chasing an imbalance that flickers about the threshold, waits.
  b.rebalanced = past && b.lost_seconds >= b.division_seconds;
  // By measured time, not counts: a process on a shared core, or with more
  // work a particle, weighs its particles more and is given fewer.
  if (b.rebalanced) {
    const auto divide_start = std::chrono::steady_clock::now();
    rebalance(compute_seconds_ / std::max(1, particles_.owned));
    dividing_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - divide_start).count();
    lost_since_division_ = 0;
  }
  compute_seconds_ = 0;
  balance_steps_ = 0;
  balance_start_ = std::chrono::steady_clock::now();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::rebalance(double weight) {
  const int n = particles_.owned;
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x);
  const auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.id);
  std::vector<double> coordinates(static_cast<size_t>(n) * Dim), weights(n, weight);
  std::vector<long long> ids(n);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < Dim; ++d) coordinates[static_cast<size_t>(i) * Dim + d] = x(i, d);
    ids[i] = id(i);
  }
  next_decomposition_ = rcb_decomposition_of_particles<Dim>(scene_, coordinates, ids, weights, comm_);
  ++balance_.rebalances;
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::predict_stage() {
  predict_to_midpoint(space_, particles_, derived_.time_step, !fixed_, fluid_.separate_wall_drag);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::neighbourhood_stage() {
  refresh_neighbourhood_only();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::wall_pressure_stage() {
  update_wall_pressure();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::pair_rates_stage() {
  sum_pair_rates(space_, particles_, neighbourhood_.list(), pair_sums_, kernel_, fluid_, pair_options_,
                 no_slip_factors_);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::finish_stage() {
  finish_pair_rates(space_, particles_, neighbourhood_.list(), pair_sums_, fluid_, finish_body_force(),
                    pair_options_, no_slip_factors_);
  if (particles_.has_phase_acceleration) add_phase_acceleration();
  space_.fence();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::correct_stage() {
  // The corrector checks the particles it writes, unless something moves
  // them after it (shifting, the push out of grains) or a test poisons them.
  corrector_checks_ = !particles_.has_shifting && (fixed_ || solid_map_.empty()) && !poison_next_step_;
  corrector_unhealthy_ = correct_full_step(space_, particles_, derived_.time_step, !fixed_,
                                           fluid_.separate_wall_drag, corrector_checks_ ? &health_limits_ : nullptr);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::constraints_stage() {
  if (particles_.has_shifting) apply_shifting(space_, particles_);
  if (!fixed_ && !solid_map_.empty()) {
    const auto pushed = fluid_in_grains(space_, particles_, solid_map_, true, 1e-6 * scene_.particle_spacing);
    surface_corrections_ += pushed.particles;
    deepest_correction_ = std::max(deepest_correction_, pushed.max_depth);
  }
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::check_stage() {
  if (poison_next_step_ && particles_.owned > 0) {
    Kokkos::deep_copy(Kokkos::subview(particles_.v, 0, 0), std::numeric_limits<double>::quiet_NaN());
    poison_next_step_ = false;
  }
  ++steps_;
  time_ = steps_ * derived_.time_step;  // not a running sum: no drift of the clock over 10^5 steps
  check_step(corrector_checks_ && corrector_unhealthy_ == 0);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::resummation_stage() {
  if (steps_ % scene_.resummation_interval != 0) return;
  refresh_neighbourhood();
  resum_fluid_density(space_, particles_, neighbourhood_.list(), pair_sums_, kernel_);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::check_step(bool known_healthy) {
  // Particles only change hands at rebuilds, but a lost one must stop the run
  // the step it happens; so must a broken state. One reduction over the
  // particles (none if the corrector found every one healthy) and one small
  // MPI reduction a step cover both.
  const HealthCounts local = known_healthy ? HealthCounts() : count_health_problems(space_, particles_, health_limits_);
  long long totals[1 + kHealthCauses];
  totals[0] = particles_.owned;
  for (int c = 0; c < kHealthCauses; ++c) totals[1 + c] = local.count[c];
  comm_.sum(totals, 1 + kHealthCauses);
  if (totals[0] != total_count_)
    throw SimulationFailure("particle count changed from " + std::to_string(total_count_) + " to " +
                                std::to_string(totals[0]) + " at step " + std::to_string(steps_),
                            steps_, time_);
  HealthCounts global;
  for (int c = 0; c < kHealthCauses; ++c) global.count[c] = totals[1 + c];
  if (global.total() > 0) report_failure(global);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::report_failure(const HealthCounts& counts) {
  int cause = 0;
  while (counts.count[cause] == 0) ++cause;
  // The particle with the smallest id among those with the first cause, wherever it lives.
  const int index = first_particle_with(space_, particles_, health_limits_, cause);
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.id);
  const long long mine = index >= 0 ? id(index) : std::numeric_limits<long long>::max();
  const long long chosen = comm_.min(mine);
  std::vector<double> where(3 * Dim + 2, 0.0);  // x, v, dvdt, rho, on its owner only (summed)
  if (index >= 0 && mine == chosen) {
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x);
    auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.v);
    auto a = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.dvdt);
    auto rho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.rho);
    for (int d = 0; d < Dim; ++d) where[d] = x(index, d), where[Dim + d] = v(index, d), where[2 * Dim + d] = a(index, d);
    where[3 * Dim] = rho(index);
    where[3 * Dim + 1] = 1;
  }
  comm_.sum(where.data(), static_cast<int>(where.size()));
  std::ostringstream msg;
  msg.precision(6);
  msg << "step " << steps_ << ", t = " << time_ << " s: " << kHealthCauseNames[cause] << " (" << counts.count[cause]
      << " particle" << (counts.count[cause] == 1 ? "" : "s") << "); particle " << chosen << " at (";
  for (int d = 0; d < Dim; ++d) msg << (d ? ", " : "") << where[d];
  msg << ") with velocity (";
  for (int d = 0; d < Dim; ++d) msg << (d ? ", " : "") << where[Dim + d];
  msg << ") m/s, acceleration (";
  for (int d = 0; d < Dim; ++d) msg << (d ? ", " : "") << where[2 * Dim + d];
  msg << ") m/s^2, density " << where[3 * Dim] << " kg/m^3";
  if (cause == kDensityVariation) msg << " (limit " << health_limits_.density_variation << " of rho0)";
  if (cause == kSpeedLimit) msg << " (limit h/(4 dt) = " << health_limits_.speed << " m/s)";
  if (cause == kAccelerationLimit) msg << " (limit h/(16 dt^2) = " << health_limits_.acceleration << " m/s^2)";
  throw SimulationFailure(msg.str(), steps_, time_);
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::rewind_failed_step() {
  const auto owned = std::make_pair(0, particles_.owned);
  if (!fixed_)  // fixed particles never left their x (the predictor keeps no x_start for them)
    Kokkos::deep_copy(space_, Kokkos::subview(particles_.x, owned, Kokkos::ALL),
                      Kokkos::subview(particles_.x_start, owned, Kokkos::ALL));
  Kokkos::deep_copy(space_, Kokkos::subview(particles_.v, owned, Kokkos::ALL),
                    Kokkos::subview(particles_.v_start, owned, Kokkos::ALL));
  Kokkos::deep_copy(space_, Kokkos::subview(particles_.rho, owned), Kokkos::subview(particles_.rho_start, owned));
  space_.fence();
  --steps_;
  time_ = steps_ * derived_.time_step;
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::resume(long long steps, const typename ParticleSet::Vector& x_at_build,
                                        bool rates_valid) {
  steps_ = steps;
  time_ = steps_ * derived_.time_step;
  const auto owned = std::make_pair(0, particles_.owned);
  if (x_at_build.extent(0) > 0) {
    // Rebuild the halo and lists from the positions they were built from,
    // then put the current positions back: the same lists, in the same order.
    auto current = typename ParticleSet::Vector("resume_positions", particles_.owned);
    Kokkos::deep_copy(space_, current, Kokkos::subview(particles_.x, owned, Kokkos::ALL));
    Kokkos::deep_copy(space_, Kokkos::subview(particles_.x, owned, Kokkos::ALL),
                      Kokkos::subview(x_at_build, owned, Kokkos::ALL));
    space_.fence();
    neighbourhood_.build(space_, particles_);
    built_neighbourhood();
    Kokkos::deep_copy(space_, Kokkos::subview(particles_.x, owned, Kokkos::ALL), current);
    space_.fence();
  } else {
    neighbourhood_.invalidate();  // the next refresh wraps, migrates and builds
  }
  long long fluid = 0;
  const auto kind = particles_.kind;
  static const std::string label_count_fluid = "poresph::count_fluid";
  Kokkos::parallel_reduce(
      label_count_fluid, Kokkos::RangePolicy<ExecSpace>(space_, 0, particles_.owned),
      KOKKOS_LAMBDA(int i, long long& n) { n += kind(i) == kFluid; }, fluid);
  fluid_count_ = comm_.sum(fluid);
  total_count_ = comm_.sum(static_cast<long long>(particles_.owned));
  // The particles brought their phi: the field is made again from it.
  if (scene_.moving_interface) make_phase_field();
  // The particles brought their phases; the drainage's step and curve,
  // which summary.json reports, are made again from the same lattice.
  if (scene_.has_phases() && scene_.phases[1].drained()) {
    drain_phase_one();
    drainage_.drained = std::vector<char>();
  }
  // With the saved rates the next step needs nothing else: its mid-point
  // refresh updates the ghosts (or, after a redistribution, builds them).
  if (!rates_valid) {
    compute_rates();
    if (rigid_grains_.moving()) rigid_grains_.take_loads(particles_, comm_);
  }
  space_.fence();
}

template <int Dim, class ExecSpace>
GridBlock<Dim> Simulation<Dim, ExecSpace>::interpolate_to_grid(const std::vector<int>& points,
                                                              std::vector<double>& values) {
  // Ghosts to the current state without a rebuild, so that writing output
  // never changes when the lists are rebuilt (and so the run's bits).
  update_pressure_and_ghosts();
  GridBlock<Dim> block;
  const auto& box = neighbourhood_.box();
  for (int d = 0; d < Dim; ++d) {
    block.spacing[d] = scene_.cell_size[d] / points[d];
    // Nodes (i + 1/2) spacing inside [lo, hi) of this box (clipped to the cell).
    const double lo = std::max(box.lo[d], 0.0), hi = std::min(box.hi[d], scene_.cell_size[d]);
    const long long first = static_cast<long long>(std::ceil(lo / block.spacing[d] - 0.5));
    const long long end = static_cast<long long>(std::ceil(hi / block.spacing[d] - 0.5));
    block.first[d] = std::max(0LL, first);
    block.count[d] = std::max(0LL, std::min<long long>(end, points[d]) - block.first[d]);
  }
  Kokkos::View<double**, MemorySpace> grid("grid_values", block.nodes(), Dim + 2);
  neighbourhood_.ensure_cells(space_, particles_);
  if (block.nodes() > 0)
    poresph::interpolate_to_grid(space_, particles_, neighbourhood_.cells(), kernel_, solid_map_, block, grid);
  space_.fence();
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), grid);
  values.assign(host.data(), host.data() + host.size());
  return block;
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::keep_level_start() {
  if (!fixed_) throw std::logic_error("keep_level_start: moving particles leave the points their start was given at");
  particles_.keep_level_start();
}

template <int Dim, class ExecSpace>
void Simulation<Dim, ExecSpace>::warm_start(Simulation& finer, double scale, double extrapolation) {
  update_pressure_and_ghosts();  // the ghosts as they are now: they serve the box's edge
  auto& F = finer.particles_;
  const int n = F.owned;
  const double rest_pressure = derived_.sound_speed * derived_.sound_speed * scene_.density;
  Kokkos::View<double**, MemorySpace> values("warm_start_values", n, Dim + 1);
  neighbourhood_.ensure_cells(space_, particles_);
  interpolate_fluid_at(space_, particles_, neighbourhood_.cells(), kernel_, F.x, n, rest_pressure, values);
  // This level's own start, interpolated the same way (its ghosts first):
  // what this level changed of it is what the refinement before changed.
  const bool extrapolate = extrapolation != 0 && particles_.has_level_start;
  Kokkos::View<double**, MemorySpace> start_values("warm_start_level_start", extrapolate ? n : 0, Dim + 1);
  if (extrapolate) {
    ParticleSet start = particles_;
    start.v = particles_.v_level_start, start.p = particles_.p_level_start;
    neighbourhood_.update_ghosts(start);
    interpolate_fluid_at(space_, start, neighbourhood_.cells(), kernel_, F.x, n, rest_pressure, start_values);
  }
  space_.fence();
  const double fine_c_sq = finer.derived_.sound_speed * finer.derived_.sound_speed;
  take_level_start(finer.space_, F, values, start_values,
                   LevelStartRule{scale, extrapolate ? extrapolation : 0.0, fine_c_sq, finer.scene_.density});
  finer.space_.fence();
  finer.compute_rates();
}

template <int Dim, class ExecSpace>
Kokkos::View<int*, typename ExecSpace::memory_space> Simulation<Dim, ExecSpace>::grain_ids() const {
  Kokkos::View<int*, MemorySpace> ids("grain_ids", particles_.owned);
  Kokkos::deep_copy(space_, ids, -1);
  if (!solid_map_.has_grains) return ids;
  const auto Q = particles_;
  const auto map = solid_map_.grains;
  const double tolerance = 1e-6 * scene_.particle_spacing;
  static const std::string label_grain_ids = "poresph::grain_ids";
  Kokkos::parallel_for(
      label_grain_ids, Kokkos::RangePolicy<ExecSpace>(space_, 0, particles_.owned), KOKKOS_LAMBDA(int i) {
        if (Q.kind(i) != kGrainBoundary) return;
        double x[Dim], offset[Dim];
        for (int d = 0; d < Dim; ++d) x[d] = Q.x(i, d), offset[d] = Q.wall_vector(i, d);
        ids(i) = map.grain_with_offset(x, offset, tolerance);
      });
  space_.fence();
  return ids;
}

template <int Dim, class ExecSpace>
SurfaceLoads<Dim> Simulation<Dim, ExecSpace>::surface_loads() {
  neighbourhood_stage();
  wall_pressure_stage();
  // One list, summed over the processes at once: per grain its force and
  // torque, then the walls' force, the image's, the fluid's mass, and the
  // count of grain boundary particles that no grain has (0 in a correct run).
  constexpr int kSpin = spin_components<Dim>();
  const int grains = static_cast<int>(scene_.grains.size());
  const int walls = grains * (Dim + kSpin), image = walls + Dim, fluid_mass = image + Dim, lost = fluid_mass + 1;
  Kokkos::View<double*, MemorySpace> totals("surface_loads", lost + 1);
  const auto Q = particles_;
  const auto map = solid_map_.grains;
  const double tolerance = 1e-6 * scene_.particle_spacing;
  compute_surface_forces(
      space_, particles_, neighbourhood_.list(), pair_sums_, kernel_, fluid_, pair_options_, no_slip_factors_,
      KOKKOS_LAMBDA(int a, const Vec<Dim>& F) {
        const int kind = Q.kind(a);
        int first = kind == kSampledBoundary ? image : walls;
        double x[Dim], offset[Dim];
        if (kind == kGrainBoundary) {  // its grain, from its offset to the centre (Simulation::grain_ids)
          for (int d = 0; d < Dim; ++d) x[d] = Q.x(a, d), offset[d] = Q.wall_vector(a, d);
          const int g = map.grain_with_offset(x, offset, tolerance);
          if (g < 0) {
            Kokkos::atomic_add(&totals(lost), 1.0);
            return;
          }
          double torque[kSpin];
          grain_moment<Dim>(offset, Q.wall_scalar(a), F.c, torque);
          first = g * (Dim + kSpin);
          for (int k = 0; k < kSpin; ++k) Kokkos::atomic_add(&totals(first + Dim + k), torque[k]);
        }
        for (int d = 0; d < Dim; ++d) Kokkos::atomic_add(&totals(first + d), F[d]);
      });
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), totals);
  std::vector<double> sums(host.data(), host.data() + lost + 1);
  sums[fluid_mass] = local_fluid_mass(scene_.driven_phase);  // the fluid the body force acts on
  comm_.sum(sums.data(), static_cast<int>(sums.size()));
  if (sums[lost] > 0)
    throw std::logic_error("surface_loads: " + std::to_string(static_cast<long long>(sums[lost])) +
                           " boundary particles of grains that no grain has");
  SurfaceLoads<Dim> loads;
  loads.grain_force.resize(grains);
  loads.grain_torque.resize(grains);
  for (int g = 0; g < grains; ++g) {
    const double* s = sums.data() + g * (Dim + kSpin);
    for (int d = 0; d < Dim; ++d) loads.grain_force[g][d] = s[d];
    for (int k = 0; k < kSpin; ++k) loads.grain_torque[g][k] = s[Dim + k];
    if (rigid_grains_.moving()) {
      const auto beyond_pairs = rigid_grains_.torque_beyond_pairs(g);
      for (int k = 0; k < kSpin; ++k) loads.grain_torque[g][k] += beyond_pairs[k];
    }
  }
  for (int d = 0; d < Dim; ++d) {
    loads.walls[d] = sums[walls + d], loads.image[d] = sums[image + d];
    loads.body_force_on_fluid[d] = sums[fluid_mass] * scene_.body_force[d];
  }
  return loads;
}

template <int Dim, class ExecSpace>
typename Simulation<Dim, ExecSpace>::DensityStatistics Simulation<Dim, ExecSpace>::density_statistics() const {
  const auto rho = particles_.rho;
  const auto kind = particles_.kind;
  const double rho0 = scene_.density;
  double sum = 0.0, variation = 0.0;
  static const std::string label_density_statistics = "poresph::density_statistics";
  Kokkos::parallel_reduce(
      label_density_statistics, Kokkos::RangePolicy<ExecSpace>(space_, 0, particles_.owned),
      KOKKOS_LAMBDA(int i, double& total, double& worst) {
        if (kind(i) != kFluid) return;
        total += rho(i);
        const double dev = math::fabs(rho(i) / rho0 - 1.0);
        if (dev > worst) worst = dev;
      },
      sum, Kokkos::Max<double>(variation));
  return {comm_.max(variation), comm_.sum(sum) / (fluid_count_ * rho0) - 1.0};
}

template <int Dim, class ExecSpace>
Vec<Dim> Simulation<Dim, ExecSpace>::superficial_velocity() const {
  const auto v = particles_.v;
  const auto m = particles_.m, rho = particles_.rho;
  const auto kind = particles_.kind;
  const double volume_density = volume_density_;  // fixed particles: volume m / rho0 = dx^N
  double volume = 1.0;
  for (int d = 0; d < Dim; ++d) volume *= scene_.cell_size[d];
  Vec<Dim> result;
  for (int d = 0; d < Dim; ++d) {
    double flux = 0.0;
    static const std::string label_superficial_velocity = "poresph::superficial_velocity";
    Kokkos::parallel_reduce(
        label_superficial_velocity, Kokkos::RangePolicy<ExecSpace>(space_, 0, particles_.owned),
        KOKKOS_LAMBDA(int i, double& sum) {
          if (kind(i) == kFluid) sum += m(i) / (volume_density > 0 ? volume_density : rho(i)) * v(i, d);
        },
        flux);
    result[d] = comm_.sum(flux) / volume;
  }
  return result;
}

template <int Dim, class ExecSpace>
GrainPenetration Simulation<Dim, ExecSpace>::fluid_inside_grains() const {
  auto result = fluid_in_grains(space_, particles_, solid_map_, false, 0.0);
  result.particles = comm_.sum(result.particles);
  result.max_depth = comm_.max(result.max_depth);
  return result;
}

template <int Dim, class ExecSpace>
GrainPenetration Simulation<Dim, ExecSpace>::grain_surface_corrections() const {
  GrainPenetration result;
  result.particles = comm_.sum(surface_corrections_);
  result.max_depth = comm_.max(deepest_correction_);
  return result;
}

template Decomposition<2> decompose<2>(const SceneConfig&, int);
template Decomposition<3> decompose<3>(const SceneConfig&, int);

#define PORESPH_INSTANTIATE(SPACE)       \
  template class Simulation<2, SPACE>; \
  template class Simulation<3, SPACE>;
PORESPH_FOR_EACH_EXECUTION_SPACE(PORESPH_INSTANTIATE)

}  // namespace poresph
