#pragma once
// One SPH run on one process: owns the particles and advances them. The
// dimension and the execution space are template parameters; Simulation.cpp
// instantiates the combinations the Kokkos build has.
#include <Kokkos_Core.hpp>

#include <array>

#include "core/CellList.hpp"
#include "core/NeighbourList.hpp"
#include "core/Kernel.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"
#include "geometry/GrainMap.hpp"
#include "io/SceneConfig.hpp"
#include "parallel/Communicator.hpp"
#include "parallel/Decomposition.hpp"
#include "parallel/Halo.hpp"
#include "physics/GrainContact.hpp"
#include "physics/PairRates.hpp"
#include "physics/TimeStep.hpp"

namespace poresph {

// Numbers derived from a scene: the smoothing length, sound speed and step.
struct DerivedParameters {
  double smoothing_length;
  double sound_speed;
  double velocity_scale;
  double length_scale;
  TimeStepLimits limits;
  double time_step;
};

DerivedParameters derive_parameters(const SceneConfig& scene);

// The scene's sub-domains for `ranks` processes.
template <int Dim>
Decomposition<Dim> decompose(const SceneConfig& scene, int ranks);

template <int Dim, class ExecSpace>
class Simulation {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using ParticleSet = Particles<Dim, MemorySpace>;

  explicit Simulation(const SceneConfig& scene, const ExecSpace& space = ExecSpace(),
                      const Communicator& comm = Communicator());

  // One predictor-corrector step of size time_step().
  void step();
  // Re-evaluates the rates at the current state (after the state was edited).
  void compute_rates();

  double time() const { return time_; }
  long long steps() const { return steps_; }
  double time_step() const { return derived_.time_step; }
  const DerivedParameters& derived() const { return derived_; }
  const SceneConfig& scene() const { return scene_; }
  ParticleSet& particles() { return particles_; }
  const ParticleSet& particles() const { return particles_; }

  // Neighbour-list rebuilds so far (the list is kept while particles move less than half the skin).
  long long neighbour_rebuilds() const { return rebuilds_; }
  long long neighbour_pairs() const { return neighbours_.pairs(); }

  // Over all processes.
  long long fluid_particles() const { return fluid_count_; }
  long long boundary_particles() const { return total_count_ - fluid_count_; }
  const Communicator& communicator() const { return comm_; }
  // max |rho/rho0 - 1| over fluid particles.
  double max_density_variation() const;
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
  // half the skin since the last build, otherwise the ghosts updated in place.
  void refresh_neighbourhood();
  bool moved_beyond_skin() const;

  SceneConfig scene_;
  ExecSpace space_;
  Communicator comm_;
  DerivedParameters derived_;
  ParticleSet particles_;
  QuinticKernel<Dim> kernel_;
  Halo<Dim, ExecSpace> halo_;
  CellList<Dim, ExecSpace> cells_;
  NeighbourList<Dim, ExecSpace> neighbours_;
  double skin_ = 0.0;
  typename ParticleSet::Vector x_at_build_;  // owned positions when the list was built
  bool built_ = false;
  long long rebuilds_ = 0;
  Vec<Dim> search_lo_, search_hi_;  // cell extended by the support: where ghosts and walls live
  Vec<Dim> body_force_;
  GrainMap<Dim, MemorySpace> grain_map_;
  long long surface_corrections_ = 0;  // on this process
  double deepest_correction_ = 0.0;
  FluidProperties fluid_;
  ShiftingParameters shifting_;
  // Subtracted from p = c^2 rho in the momentum equation. A uniform pressure
  // has no gradient, but through the SPH gradient of a sheared or disordered
  // particle arrangement it exerts spurious forces proportional to itself
  // (docs/validation.md): (1 - background) c^2 rho0.
  double reference_pressure_ = 0.0;
  long long fluid_count_ = 0, total_count_ = 0;
  double time_ = 0.0;
  long long steps_ = 0;
};

}  // namespace poresph
