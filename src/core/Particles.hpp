#pragma once
// Particle storage: one Kokkos View per field (structure of arrays).
// Slots [0, owned) are this process's particles, [owned, owned + ghosts) are
// copies of neighbours' particles and periodic images made by the halo layer.
#include <Kokkos_Core.hpp>

#include <string>

namespace poresph {

// What a particle is. Boundary particles carry the shape of the surface they
// belong to, because the no-slip velocity is measured from that surface.
enum ParticleKind : int {
  kFluid = 0,
  kWallBoundary = 1,   // plane wall: wall_vector = unit normal into the fluid, wall_scalar = depth below the wall
  kGrainBoundary = 2,  // grain: wall_vector = position minus grain centre, wall_scalar = grain radius
  // A surface known only by its distance field (an image): wall_vector =
  // unit normal into the fluid, wall_scalar = depth, as for a plane wall;
  // fixed fluid particles near it carry their own normal and distance to it
  // in their wall_vector and wall_scalar (physics/NoSlip.hpp).
  kSampledBoundary = 3,
};

// The most fluid phases a scene may have (Particles::phase).
constexpr int kMaxPhases = 2;

template <int Dim, class MemorySpace>
struct Particles {
  using Vector = Kokkos::View<double* [Dim], MemorySpace>;
  using Scalar = Kokkos::View<double*, MemorySpace>;

  // State.
  Vector x, v;
  Scalar rho, p, m;
  // Derived from rho before each force evaluation, so that the pair loop
  // divides once per pair instead of three times: (p - p_ref)/rho^2 and 1/rho.
  // Fixed particles hold no inverse_density: their volumes use rho0, and the
  // pair loop takes 1/rho0 as a constant (PairLoopOptions::uniform_inverse_density).
  Scalar pressure_term, inverse_density;
  Kokkos::View<int*, MemorySpace> kind;
  Kokkos::View<long long*, MemorySpace> id;
  // Start-of-step state and rates for the predictor-corrector (owned slots).
  Vector x_start, v_start, dvdt;
  Scalar rho_start, drhodt;
  // Surface of each boundary particle; empty in a scene without walls or grains.
  Vector wall_vector;
  Scalar wall_scalar;
  // Fixed particles next to a surface (owned slots): the no-slip drag
  // coefficient kappa of dv/dt = a - kappa v, kept apart from the rates so
  // that the step integrates it exactly (physics/PredictorCorrector.hpp);
  // empty in a scene without walls or grains.
  Scalar wall_drag;
  // Particle shifting (owned slots): displacement towards uniform spacing and
  // the velocity change that carries the field along; empty when not enabled.
  Vector shift, shift_velocity;
  // A ladder level's start (fixed particles): the velocity and pressure it
  // took from the level before, so that the next level can be started from
  // what this one then changed (app/Simulation.hpp, warm_start); empty
  // unless keep_level_start(). Owned slots; the ghost slots are scratch.
  Vector v_level_start;
  Scalar p_level_start;
  // Moving grains (physics/RigidGrains.hpp): the grain a boundary particle
  // belongs to, -1 for the others; empty when the grains hold still.
  Kokkos::View<int*, MemorySpace> grain;
  // Two fluids (scene/SceneConfig.hpp, phases): each particle's phase, set
  // once on the fixed lattice; empty in a scene of one fluid.
  Kokkos::View<int*, MemorySpace> phase;
  // Two fluids: each owned fluid particle's acceleration that the phases'
  // placement fixes, set once (the phases never move) and added like a body
  // force: the surface tension sigma kappa n / rho0 between the phases
  // (physics/SurfaceTension.hpp) and, with one phase driven (Phases/Driven
  // Phase), the body force on that phase's particles. Empty without either.
  Vector phase_acceleration;
  // A moving interface (Phases/Interface = moving): each owned particle's
  // phase field phi (physics/PhaseField.hpp), 0 at a boundary particle.
  Scalar colour;

  int owned = 0;
  int ghosts = 0;
  bool has_surfaces = false;
  bool has_shifting = false;
  bool has_level_start = false;
  bool fixed_positions = false;  // fix_positions()
  bool has_grain_index = false;  // keep_grain_index()
  bool has_phase = false;        // keep_phase()
  bool has_phase_acceleration = false;  // keep_phase_acceleration()
  bool has_colour = false;              // keep_colour()

  int total() const { return owned + ghosts; }

  // The fields the communication layer moves, by what it moves them for;
  // f is called with each View. It needs no idea what the fields mean,
  // except that `x` is the position (ghosts carry shifted copies of it),
  // first in each group that has it.
  // A ghost's copy: everything a neighbour's pair loop reads.
  template <class F>
  void for_each_ghost_field(F&& f) const {
    f(x);
    for_each_changing_value(f);
    f(m), f(kind), f(id);
    if (has_surfaces && !has_grain_index) f(wall_vector);  // else a changing field
    if (has_surfaces) f(wall_scalar);
    if (has_grain_index) f(grain);
    if (has_phase && !has_colour) f(phase);  // else a changing field
  }
  // What changes between neighbour-list rebuilds (ghost refresh): with
  // moving grains, a boundary particle's offset from its turning grain's
  // centre too. Fixed particles' positions never change, so their ghosts
  // keep the x of the build (a third of what a refresh would send).
  template <class F>
  void for_each_changing_field(F&& f) const {
    if (!fixed_positions) f(x);
    for_each_changing_value(f);
  }
  template <class F>
  void for_each_changing_value(F&& f) const {
    f(v), f(rho), f(p), f(pressure_term);
    if (!fixed_positions) f(inverse_density);
    if (has_grain_index) f(wall_vector);
    if (has_colour) f(phase);  // a moving interface changes the particles' phases
  }
  // Everything an owned particle is, for migration to another process.
  template <class F>
  void for_each_owned_field(F&& f) const {
    for_each_ghost_field(f);
    if (!fixed_positions) f(x_start);
    f(v_start), f(dvdt), f(rho_start), f(drhodt);
    if (has_surfaces) f(wall_drag);
    if (has_shifting) f(shift), f(shift_velocity);
    if (has_level_start) f(v_level_start), f(p_level_start);
    if (has_phase_acceleration) f(phase_acceleration);
    if (has_colour) f(colour);
  }
  int capacity() const { return static_cast<int>(x.extent(0)); }              // slots a ghost may take
  int owned_capacity() const { return static_cast<int>(v_start.extent(0)); }  // slots an owned particle may take

  // From now on each particle carries the grain it belongs to (`grain`, -1 for none).
  void keep_grain_index() {
    has_grain_index = true;
    if (static_cast<int>(grain.extent(0)) < capacity()) grain = Kokkos::View<int*, MemorySpace>("grain", capacity());
  }

  // From now on each particle carries its phase (`phase`, 0 until set).
  void keep_phase() {
    has_phase = true;
    if (static_cast<int>(phase.extent(0)) < capacity()) phase = Kokkos::View<int*, MemorySpace>("phase", capacity());
  }

  // From now on each owned particle carries its phase acceleration (0 until set).
  void keep_phase_acceleration() {
    has_phase_acceleration = true;
    if (static_cast<int>(phase_acceleration.extent(0)) < owned_capacity())
      phase_acceleration = Vector("phase_acceleration", owned_capacity());
  }

  // From now on each owned particle carries its phase field (0 until set).
  void keep_colour() {
    has_colour = true;
    if (static_cast<int>(colour.extent(0)) < owned_capacity()) colour = Scalar("colour", owned_capacity());
  }

  // From now on the particles carry their level start (v_level_start, p_level_start).
  void keep_level_start() {
    has_level_start = true;
    if (static_cast<int>(v_level_start.extent(0)) < capacity())
      v_level_start = Vector("v_level_start", capacity()), p_level_start = Scalar("p_level_start", capacity());
  }

  explicit Particles(bool with_surfaces = false, bool with_shifting = false)
      : has_surfaces(with_surfaces), has_shifting(with_shifting) {}

  // Fixed particles: x never changes (no x_start), their 1/rho is 1/rho0
  // (no inverse_density), and the slots are known once the ghosts are in
  // (no room to grow): the views are cut to the owned particles now and
  // grow by what each build asks, no more.
  void fix_positions() {
    fixed_positions = true;
    x_start = Vector();
    inverse_density = Scalar();
    for_each_view(true, [this](auto& view, const char*) {
      if (static_cast<int>(view.extent(0)) > owned) Kokkos::resize(view, owned);
    });
  }

  // Grows every View to at least n slots, keeping contents; grows by 25 %
  // beyond n so that repeated ghost rebuilds do not reallocate every step
  // (fixed particles: exactly n).
  void reserve(int n) { grow(n, true); }
  // The same for the fields a ghost carries only (for_each_ghost_field):
  // the owned particles' own fields (start of step, rates) keep their size.
  void reserve_ghosts(int n) { grow(n, false); }

 private:
  void grow(int n, bool owned_fields) {
    if (n <= capacity() && (!owned_fields || n <= owned_capacity())) return;
    const int cap = fixed_positions ? n : n + n / 4 + 16;
    for_each_view(owned_fields, [cap](auto& view, const char* label) {
      if (view.extent(0) == 0) view = std::decay_t<decltype(view)>(std::string(label), cap);
      else if (static_cast<int>(view.extent(0)) < cap) Kokkos::resize(view, cap);
    });
  }
  // f(view, label) for each View the particles hold: what a ghost carries,
  // and with owned_fields what only owned particles have.
  template <class F>
  void for_each_view(bool owned_fields, F&& f) {
    f(x, "x"), f(v, "v"), f(rho, "rho"), f(p, "p"), f(m, "m");
    f(pressure_term, "pressure_term");
    if (!fixed_positions) f(inverse_density, "inverse_density");
    f(kind, "kind"), f(id, "id");
    if (has_surfaces) f(wall_vector, "wall_vector"), f(wall_scalar, "wall_scalar");
    if (has_grain_index) f(grain, "grain");
    if (has_phase) f(phase, "phase");
    // Owned, but the ghost slots are scratch for the level's start's own ghosts (Simulation::warm_start).
    if (has_level_start) f(v_level_start, "v_level_start"), f(p_level_start, "p_level_start");
    if (!owned_fields) return;
    if (!fixed_positions) f(x_start, "x_start");
    f(v_start, "v_start"), f(dvdt, "dvdt"), f(rho_start, "rho_start"), f(drhodt, "drhodt");
    if (has_surfaces) f(wall_drag, "wall_drag");
    if (has_shifting) f(shift, "shift"), f(shift_velocity, "shift_velocity");
    if (has_phase_acceleration) f(phase_acceleration, "phase_acceleration");
    if (has_colour) f(colour, "colour");
  }
};

}  // namespace poresph
