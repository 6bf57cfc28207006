#pragma once
// One SPH run on one process: owns the particles and advances them. The
// dimension and the execution space are template parameters; Simulation.cpp
// instantiates the combinations the Kokkos build has.
#include <Kokkos_Core.hpp>

#include <array>
#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/CellList.hpp"
#include "core/NeighbourList.hpp"
#include "core/Kernel.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"
#include "geometry/Solid.hpp"
#include "diagnostics/Health.hpp"
#include "diagnostics/SurfaceLoads.hpp"
#include "scene/Drainage.hpp"
#include "scene/SceneConfig.hpp"
#include "parallel/Communicator.hpp"
#include "parallel/Decomposition.hpp"
#include "parallel/Neighbourhood.hpp"
#include "physics/GrainContact.hpp"
#include "physics/GridInterpolation.hpp"
#include "physics/LatticeProducts.hpp"
#include "physics/PairRates.hpp"
#include "physics/PhaseField.hpp"
#include "physics/RigidGrains.hpp"
#include "physics/TimeStep.hpp"
#include "physics/WallPressure.hpp"

namespace poresph {

// Numbers derived from a scene: the smoothing length, sound speed and step.
struct DerivedParameters {
  double smoothing_length;
  double sound_speed;
  double velocity_scale;
  double length_scale;
  TimeStepLimits limits;
  double time_step;
  double contact_modulus;  // Young's modulus of moving grains' contacts (Grains/Contact); 0: none
};

DerivedParameters derive_parameters(const SceneConfig& scene);

// Whether the scene's particles move and are shifted (Lind et al. 2012).
bool lagrangian_shifting(const SceneConfig& scene);

// The scene's sub-domains for `ranks` processes.
template <int Dim>
Decomposition<Dim> decompose(const SceneConfig& scene, int ranks);

// A step whose result is not a solution (diagnostics/Health.hpp): what, where, when.
struct SimulationFailure : std::runtime_error {
  SimulationFailure(const std::string& message, long long step_, double time_)
      : std::runtime_error(message), step(step_), time(time_) {}
  long long step;
  double time;
};

template <int Dim, class ExecSpace>
class Simulation {
 public:
  using ExecutionSpace = ExecSpace;
  using MemorySpace = typename ExecSpace::memory_space;
  using ParticleSet = Particles<Dim, MemorySpace>;
  static constexpr int dimension = Dim;

  // A fresh run starts from the lattice, on boxes from the scene's
  // decomposition. A restart passes the saved boxes (empty: decompose for
  // this number of processes) and Start::Empty, loads the saved particles
  // into particles() and calls resume().
  enum class Start { Lattice, Empty };
  explicit Simulation(const SceneConfig& scene, const ExecSpace& space = ExecSpace(),
                      const Communicator& comm = Communicator(), Start start = Start::Lattice,
                      const std::vector<Box<Dim>>& boxes = {});

  // Continues from loaded particles at `steps`. With x_at_build (the saved
  // positions at the last neighbour-list build, same processes and order)
  // the halo and lists are rebuilt exactly as they were, so the run goes on
  // bit for bit; without (extent 0), particles go to their owners and the
  // lists are built afresh. rates_valid: dvdt and drhodt are the rates the
  // next predictor uses; otherwise they are evaluated at the loaded state.
  void resume(long long steps, const typename ParticleSet::Vector& x_at_build, bool rates_valid);
  // Testing the failure path: the next step ends with a NaN velocity.
  void poison_next_step() { poison_next_step_ = true; }
  // After a SimulationFailure: back to the state at the start of the failed
  // step (positions, velocities, densities; the rates are not kept).
  void rewind_failed_step();

  // One predictor-corrector step of size time_step(): the scene's stages
  // (step_stages()) in order.
  void step();
  // The rates dv/dt and d rho/dt (and the wall drag, the shifting) of the
  // current state, without advancing time: pressures, ghosts and lists
  // brought to the state, the wall pressure, the pair loop and its finish.
  // The entry point for anything that needs the rates of a state it made
  // (after editing velocities or densities; a steady solver). With a wall
  // drag kept apart (fixed particles next to surfaces), a fluid particle's
  // dv/dt is dvdt - wall_drag v.
  void compute_rates();
  // The same with a part of the pair terms (the steady solver's
  // preconditioner): Pressure, the pressure gradient alone (dv/dt of fluid
  // particles; with the wall pressure), Continuity alone (d rho/dt of fluid
  // particles), or Velocity, the terms whose accelerations depend on the
  // velocities (dv/dt of fluid particles from those terms and the body
  // force, and their wall drag: VelocityCorePairTerms). The other rates, and
  // those of boundary particles, are not the state's until the next
  // compute_rates().
  // Viscous: the velocity block's terms without convection (the viscous and
  // no-slip terms, the Stokes part), which the steady solver's
  // preconditioner takes for the velocity block.
  enum class RateTerms { All, Pressure, Continuity, Velocity, Viscous };
  void compute_rates(RateTerms terms);

  // The same two parts as exact linear products, for fixed particles whose
  // pair list is said by lattice rows on every process (the steady solver's
  // preconditioner; physics/LatticeProducts.hpp): about the state at the
  // last take_linear_state(), which must follow a compute_rates() of that
  // state (its pressures and ghosts current). pressure_product: the change
  // of the owned fluid particles' dv/dt from the pressure term for changes
  // dp of the fluid's pressures (p = c^2 rho; owned slots), the wall
  // pressure following them; continuity_product: the change of their
  // d rho/dt for changes dv of the fluid's velocities. Other particles'
  // rows are not written (the steady system's own pass over the rows sets
  // them). Both leave the particles as they are. velocity_product:
  // the change of their dv/dt from the velocity block's terms
  // (RateTerms::Velocity) for changes dv of the fluid's velocities, the
  // wall drag's share -kappa dv left out (the wall_drag at the state; the
  // steady solver's rows keep it apart); only where
  // linear_velocity_products(terms): the viscous terms (RateTerms::Viscous,
  // or RateTerms::Velocity without convection) of one fluid.
  using Scalars = Kokkos::View<double*, MemorySpace>;
  using Rows = Kokkos::View<double**, Kokkos::LayoutRight, MemorySpace>;
  bool take_linear_state();  // false: no lattice rows somewhere, no products
  void pressure_product(const Scalars& dp, const Rows& dvdt);
  void continuity_product(const Rows& dv, const Scalars& drhodt);
  bool linear_velocity_products(RateTerms terms) const;
  void velocity_product(const Rows& dv, const Rows& dvdt);
  // What the products hold, in doubles (0 until the first take_linear_state()).
  double linear_product_values() const;

  // A step is a named sequence of stages, each a member function; which a
  // scene has is decided once, at construction (make_step_stages): a new
  // stage (rigid-body motion, say) is one member function and one line there.
  struct StepStage {
    std::string name;  // also the Kokkos profiling region around it
    void (Simulation::*run)();
  };
  const std::vector<StepStage>& step_stages() const { return step_stages_; }

  double time() const { return time_; }
  const Vec<Dim>& body_force() const { return body_force_; }  // on the fluid now (Phases/Force Steps)
  long long steps() const { return steps_; }
  double time_step() const { return derived_.time_step; }
  const DerivedParameters& derived() const { return derived_; }
  const SceneConfig& scene() const { return scene_; }
  // Phase 1 placed by drainage (scene/Drainage.hpp): its radius,
  // saturation and capillary pressure, and the drainage curve.
  const DrainagePlacement& drainage() const { return drainage_; }
  // The phase field of a moving interface (Phases/Interface = moving); null otherwise.
  const LatticePhaseField<Dim>* phase_field() const { return phase_field_.get(); }
  ParticleSet& particles() { return particles_; }
  const ParticleSet& particles() const { return particles_; }

  const Decomposition<Dim>& decomposition() const { return neighbourhood_.decomposition(); }

  // The load balance of moving particles on 2 or more processes
  // (Parallel/Rebalance Threshold): every Rebalance Interval steps each
  // process's working time (its steps' wall time less its time in
  // collective operations) is compared, and past the threshold the cell is
  // divided anew once the time lost to the imbalance since the last
  // division pays for a division (the slowest process's excess over the
  // mean, summed over the intervals past the threshold, against the last
  // division's measured wall time: for a steadily growing imbalance, the
  // least mean cost a step, as in Nicol & Saltz's stop-at-rise rule). What
  // the last measurement found:
  struct BalanceRecord {
    long long step = -1;                      // of the last measurement (-1: none yet)
    double seconds_per_step = 0;              // wall time a step over the interval
    double compute_max = 0, compute_mean = 0;  // working seconds a step, slowest and mean process
    double imbalance = 1;                     // compute_max / compute_mean
    bool rebalanced = false;                  // the cell was divided anew after it
    double lost_seconds = 0;                  // the slowest's excess past the threshold since the last division
    double division_seconds = 0;              // wall time of the last division (0: none measured yet)
    long long particles_min = 0, particles_max = 0;  // owned particles per process at the measurement
    long long rebalances = 0;                 // in the run so far
  };
  bool measures_balance() const { return measure_balance_; }
  const BalanceRecord& balance() const { return balance_; }
  // Divides the cell anew by RCB with each owned particle weighing
  // `weight` (this process's measured time per particle); the particles
  // move to their new owners at the next step's neighbourhood refresh
  // (until then the lists, ghosts and checkpoint boxes are the old ones).
  void rebalance(double weight);
  const typename ParticleSet::Vector& positions_at_build() const {
    return fixed_ ? particles_.x : neighbourhood_.positions_at_build();  // fixed particles stay where it was built
  }

  // Velocity, pressure and solid flag on this process's block of a grid of
  // `points` nodes per direction over the cell (physics/GridInterpolation.hpp),
  // node-major, x fastest; the block is returned too.
  GridBlock<Dim> interpolate_to_grid(const std::vector<int>& points, std::vector<double>& values);

  // The fluid's velocity and pressure above the rest pressure c^2 rho0 at the
  // owned fluid particles of `finer` (a simulation of the same scene at
  // another spacing, decomposed into the same boxes), interpolated from this
  // one's fluid, ghosts included; then `finer` starts from them: its
  // velocity, and its density from the pressure under its own sound speed.
  // Boundary particles keep theirs (their pressure follows the fluid's).
  // scale multiplies what is taken (0.5 for the same flow at half the force).
  // With extrapolation e > 0 and a level start kept here (keep_level_start),
  // `finer` starts instead from what is taken plus e times the change this
  // level made of its own start, both interpolated: the next refinement
  // continues the last one (Richardson: e = 1 / (r^p - 1)). If `finer` keeps
  // a level start, it keeps the plain interpolation.
  void warm_start(Simulation& finer, double scale = 1.0, double extrapolation = 0.0);
  // Makes the particles keep the velocity and pressure warm_start gives them
  // (fixed particles only: moving ones leave the points they were given).
  void keep_level_start();
  bool keeps_level_start() const { return particles_.has_level_start; }

  // Per owned particle, the grain a grain-boundary particle belongs to; -1 for the others.
  Kokkos::View<int*, MemorySpace> grain_ids() const;
  // Moving grains: their state (centres, velocities, spins, loads); empty when they hold still.
  const RigidGrains<Dim, ExecSpace>& rigid_grains() const { return rigid_grains_; }
  // A restart of moving grains, before resume(): the fluid's mass at the
  // start and the grains' state as a checkpoint saved them (RigidGrains::state).
  void restore_grains(double fluid_mass, const std::vector<double>& state);

  // The fluid's force on the solid at the current state, summed over all
  // processes: each grain's force and torque about its centre, the plane
  // walls' and an image's force, and the fluid's mass times the body force.
  // From the pair terms of the rates, so that the loads and the fluid's
  // momentum change from the surfaces add to zero to round-off
  // (physics/PairRates.hpp, compute_surface_forces); summed per grain in
  // that pass, with no array a particle. Brings pressures, ghosts and the
  // wall pressure to the state first; the rates are left as they were.
  SurfaceLoads<Dim> surface_loads();

  // Neighbour-list rebuilds so far (the list is kept while particles move less than half the skin).
  long long neighbour_rebuilds() const { return neighbourhood_.builds(); }
  long long neighbour_pairs() const { return neighbourhood_.list().pairs(); }
  // Fixed particles, once the list is built: whether the pairs' geometry is
  // read from the lattice stencil (else from the per-entry cache).
  bool pairs_on_stencil() const { return neighbourhood_.list().on_stencil(); }
  bool pairs_on_lattice_rows() const { return neighbourhood_.list().on_lattice_rows(); }
  // The pair list of the last build (fixed particles: for_each_entry gives each row's pairs).
  const NeighbourList<Dim, ExecSpace>& neighbour_list() const { return neighbourhood_.list(); }
  // Ghost slots take their owners' values (a value per slot, owned slots
  // sent): what a set-up pass over pairs needs beyond this process's box.
  void update_ghost_values(const Scalars& values) { neighbourhood_.update_ghost_values(values, particles_.owned); }
  // Listed neighbours (support and skin) per owned particle, counting both ends of a half list's pairs.
  double neighbours_per_particle() const { return neighbourhood_.list().neighbours_per_particle(); }

  // Over all processes.
  long long fluid_particles() const { return fluid_count_; }
  long long boundary_particles() const { return total_count_ - fluid_count_; }
  // On this process: the ghosts it holds now (other processes' particles and
  // periodic images within the kernel's reach of its own).
  long long ghost_particles_here() const { return particles_.ghosts; }
  const Communicator& communicator() const { return comm_; }
  // Of the fluid particles, in one pass: max |rho/rho0 - 1|, and
  // <rho>/rho0 - 1, the drift of the mean density.
  struct DensityStatistics {
    double max_variation;
    double mean_drift;
  };
  DensityStatistics density_statistics() const;
  // Darcy's superficial velocity <u> = (1/V_cell) sum over fluid of (m/rho) v.
  Vec<Dim> superficial_velocity() const;
  // Fluid particles whose position lies inside a grain now (0 in a correct
  // run), and how deep the deepest one is.
  GrainPenetration fluid_inside_grains() const;
  // Particles put back on a grain surface after a step (summed over steps),
  // and the deepest they had gone.
  GrainPenetration grain_surface_corrections() const;

 private:
  // Pressure of owned particles, then ghosts at the current positions: a
  // fresh halo, cell list and neighbour list if some particle moved more than
  // half the skin since the last build, otherwise the ghosts updated in place;
  // then the wall pressure (update_wall_pressure).
  void refresh_neighbourhood();
  // The same without the wall pressure.
  void refresh_neighbourhood_only();
  // Pressure of owned particles, then the ghosts' changing fields along the recorded routes.
  void update_pressure_and_ghosts();
  // With an extrapolated wall pressure: the owned boundary particles' from
  // the fluid (ghosts current), then the ghosts again, so that they carry it.
  void update_wall_pressure();
  // What rests on a fresh neighbourhood: the cached pair geometry of fixed
  // particles, the boundary particles' fluid neighbours, room for the sums.
  void built_neighbourhood();
  void make_stencils();       // fixed particles, at set-up: the lattice stencils the lists and rows read
  void find_pair_geometry();  // fixed particles: the lists' geometry, from the stencil or per entry
  // The stages of a step, in order (step_stages()).
  void make_step_stages();
  void predict_stage();          // "predict": to the mid-point with the old rates
  void neighbourhood_stage();    // "neighbourhood": pressures, ghosts, lists at the mid-point
  void wall_pressure_stage();    // "wall pressure": boundary pressures from the fluid
  void pair_rates_stage();       // "pair rates": the pair loop
  void finish_stage();           // "finish": the sums into rates, the body force
  void correct_stage();          // "correct": the full step with the mid-point rates
  void constraints_stage();      // "constraints": shifting, particles put back out of grains
  void check_stage();            // "check": the clock, and the step's health
  void resummation_stage();      // "density resummation": every Density Resummation Interval steps
  // Moving grains (physics/RigidGrains.hpp):
  void grains_predict_stage();   // "grains predict": grains to the mid-point, their particles placed
  void grain_loads_stage();      // "grain loads": the fluid's force and torque on them, their accelerations
  void grains_correct_stage();   // "grains correct": the whole step, their particles placed
  void place_phases();           // at set-up: each particle's phase from its lattice point
  void drain_phase_one();        // at set-up: phase 1's points by drainage, on the whole lattice
  long long lattice_point_index(const double* x) const;
  bool image_phase_one(const double* x) const;  // phase 1 by the image's labels
  int image_value(const double* x, const long long (&offset)[3]) const;  // of the voxel offset from x's
  std::vector<int> image_block_values(const double* x) const;            // of the 3^Dim voxels about x's
  void place_surface_tension();  // at set-up: each fluid particle's surface-tension acceleration
  // The body force on one phase (of body_force's size) into its particles' acceleration.
  void place_phase_body_force(const Vec<Dim>& body_force);
  void force_step_stage();  // "force_step": the body force of the span of Phases/Force Steps the step starts in
  void add_phase_acceleration();  // in the finish: the phase acceleration into dv/dt
  // A moving interface (Phases/Interface = moving, physics/PhaseField.hpp):
  void start_interface();        // at set-up: phi from the phases' placement, the field, the forces
  void make_phase_field();       // the lattice's field from the particles' phi (set-up, restart)
  // cos(theta) per lattice point of the solids' own angles (Phases/Contact Angles), or empty.
  std::vector<double> solid_wetting(std::size_t points, double cos_everywhere) const;
  void interface_stage();        // "interface": phi carried over the step, the phases and forces from it
  // Each fluid particle's phi, phase and phase acceleration from the field; at: fluid_lattice_points().
  void place_interface_forces(const std::vector<long long>& at);
  std::vector<long long> fluid_lattice_points() const;
  // The owned particles' values (`components` each, particle-major) at their
  // lattice points (at[i] < 0: none), gathered from every process: the field is whole on each.
  struct LatticeValues {
    std::vector<long long> points;
    std::vector<double> values;
  };
  LatticeValues gather_on_lattice(const std::vector<long long>& at, const std::vector<double>& values,
                                  int components) const;
  // The force per phase a wall's pressure takes from the fluid beside it
  // (Phases/Driven Phase), of body_force; empty with one force for all the fluid.
  PhaseBodyForce<Dim, MemorySpace> phase_body_force(const Vec<Dim>& body_force) const;
  Vec<Dim> finish_body_force() const;  // the force the finish adds to every fluid particle
  void start_moving_grains();    // at set-up: the grain of each particle, the fluid's share of gravity
  void couple_grains();          // the fluid's share of the body force, the loads, the spins in the no-slip
  void place_grains();           // the grains' particles where the grains are, and the solid map with them
  void follow_grains();          // the scene's grain centres and the solid map where the grains are
  void balance_stage();          // measures the balance; divides the cell anew past the threshold
  double local_fluid_mass(int phase = -1) const;  // of this process's fluid particles (of one phase)
  // Stops the run if the step left a particle count change or an unhealthy
  // particle; known_healthy: the corrector found none here (only the count
  // is left to check).
  void check_step(bool known_healthy = false);
  [[noreturn]] void report_failure(const HealthCounts& counts);

  SceneConfig scene_;
  ExecSpace space_;
  Communicator comm_;
  DerivedParameters derived_;
  ParticleSet particles_;
  QuinticKernel<Dim> kernel_;
  Neighbourhood<Dim, ExecSpace> neighbourhood_;  // ghosts, cells, the pair list
  WallNeighbours<Dim, ExecSpace> wall_neighbours_;  // with an extrapolated wall pressure
  NoSlipFactors<Dim, ExecSpace> no_slip_factors_;   // fixed particles with surfaces, per list entry
  // Fixed particles: the lattice offsets within the lists' reach with F =
  // (1/r) dW/dr (pair list) and W (wall list), built with the first list.
  LatticeStencil<Dim, MemorySpace> pair_stencil_, wall_stencil_;
  PairSums<Dim, ExecSpace> pair_sums_;  // what both ends of a listed pair add to, per thread
  // The steady solver's linear products (take_linear_state()): the
  // stencil sums, each slot's pressure-term slope at the state, the walls'
  // pressure weights, and values per slot that the halo carries to the ghosts.
  LatticeProducts<Dim, ExecSpace> lattice_products_;
  Scalars pressure_slope_, slot_scalars_;
  Rows slot_rows_;
  Scalars fluid_mass_;  // the viscous term's masses: m on fluid slots, zero on the others
  Rows fluid_rows_in_slots(const Rows& dv);  // into slot_rows_, ghosts current
  WallPressureWeights<Dim, ExecSpace> wall_pressure_weights_;  // the walls' pressures' change from the fluid's
  Vec<Dim> body_force_;
  SolidMap<Dim, MemorySpace> solid_map_;
  RigidGrains<Dim, ExecSpace> rigid_grains_;  // Grains/Motion = free or rotating
  std::unique_ptr<LatticePhaseField<Dim>> phase_field_;  // Phases/Interface = moving
  std::vector<long long> interface_points_;  // fluid_lattice_points() since the neighbourhood was built; empty: none
  std::vector<Vec<Dim>> lattice_velocity_;   // the interface stage's work array, on the whole lattice
  // Every process's interface_points_ (fluid ones), in rank order, and the
  // velocity values each sends (Dim a point); empty: to gather.
  std::vector<long long> gathered_points_;
  std::vector<int> gathered_counts_;
  DrainagePlacement drainage_;  // phase 1 placed by drainage: where, and the curve (not the points: freed)
  bool measure_balance_ = false;  // moving particles on 2 or more processes
  BalanceRecord balance_;
  std::optional<Decomposition<Dim>> next_decomposition_;  // from rebalance(), taken at the next refresh
  double compute_seconds_ = 0;    // working (not waiting) since the last measurement
  double dividing_seconds_ = 0;   // in the division since the last measurement: RCB and the particles' move
  double lost_since_division_ = 0;  // BalanceRecord::lost_seconds, summed until a division
  int balance_steps_ = 0;         // steps since the last measurement
  std::chrono::steady_clock::time_point balance_start_;
  long long surface_corrections_ = 0;  // on this process
  double deepest_correction_ = 0.0;
  FluidProperties fluid_;
  // Fixed particles (Eulerian SPH): positions never change, the lists are
  // built once, and the pair loop adds the convective term if asked.
  bool fixed_ = false;
  bool convection_ = false;
  double volume_density_ = 0.0;  // rho0 for fixed particles (volumes dx^N), 0: m / rho
  bool extrapolate_walls_ = false;  // boundary pressures from the fluid (physics/WallPressure.hpp)
  PairLoopOptions pair_options_;
  // Subtracted from p = c^2 rho in the momentum equation. A uniform pressure
  // has no gradient, but through the SPH gradient of a sheared or disordered
  // particle arrangement it exerts spurious forces proportional to itself
  // (docs/validation.md): (1 - background) c^2 rho0.
  double reference_pressure_ = 0.0;
  HealthLimits health_limits_{};
  bool poison_next_step_ = false;
  std::vector<StepStage> step_stages_;
  // Within a step: whether the corrector checked the particles it wrote,
  // and how many it found unhealthy.
  bool corrector_checks_ = false;
  long long corrector_unhealthy_ = 0;
  long long fluid_count_ = 0, total_count_ = 0;
  double time_ = 0.0;
  long long steps_ = 0;
};

}  // namespace poresph
