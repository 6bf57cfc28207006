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

template <int Dim, class MemorySpace>
struct Particles {
  using Vector = Kokkos::View<double* [Dim], MemorySpace>;
  using Scalar = Kokkos::View<double*, MemorySpace>;

  // State.
  Vector x, v;
  Scalar rho, p, m;
  // Derived from rho before each force evaluation, so that the pair loop
  // divides once per pair instead of three times: (p - p_ref)/rho^2 and 1/rho.
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

  int owned = 0;
  int ghosts = 0;
  bool has_surfaces = false;
  bool has_shifting = false;
  bool has_level_start = false;

  int total() const { return owned + ghosts; }

  // The fields the communication layer moves, by what it moves them for;
  // f is called with each View. It needs no idea what the fields mean,
  // except that `x` is the position (ghosts carry shifted copies of it).
  // A ghost's copy: everything a neighbour's pair loop reads.
  template <class F>
  void for_each_ghost_field(F&& f) const {
    for_each_changing_field(f);
    f(m), f(kind), f(id);
    if (has_surfaces) f(wall_vector), f(wall_scalar);
  }
  // What changes between neighbour-list rebuilds (ghost refresh).
  template <class F>
  void for_each_changing_field(F&& f) const {
    f(x), f(v), f(rho), f(p), f(pressure_term), f(inverse_density);
  }
  // Everything an owned particle is, for migration to another process.
  template <class F>
  void for_each_owned_field(F&& f) const {
    for_each_ghost_field(f);
    f(x_start), f(v_start), f(dvdt), f(rho_start), f(drhodt);
    if (has_surfaces) f(wall_drag);
    if (has_shifting) f(shift), f(shift_velocity);
    if (has_level_start) f(v_level_start), f(p_level_start);
  }
  int capacity() const { return static_cast<int>(x.extent(0)); }

  // From now on the particles carry their level start (v_level_start, p_level_start).
  void keep_level_start() {
    has_level_start = true;
    if (static_cast<int>(v_level_start.extent(0)) < capacity())
      v_level_start = Vector("v_level_start", capacity()), p_level_start = Scalar("p_level_start", capacity());
  }

  explicit Particles(bool with_surfaces = false, bool with_shifting = false)
      : has_surfaces(with_surfaces), has_shifting(with_shifting) {}

  // Grows every View to at least n slots, keeping contents; grows by 25 %
  // beyond n so that repeated ghost rebuilds do not reallocate every step.
  void reserve(int n) {
    if (n <= capacity()) return;
    const int cap = n + n / 4 + 16;
    auto grow = [cap](auto& view, const char* label) {
      if (view.extent(0) == 0) view = std::decay_t<decltype(view)>(std::string(label), cap);
      else Kokkos::resize(view, cap);
    };
    grow(x, "x"); grow(v, "v"); grow(rho, "rho"); grow(p, "p"); grow(m, "m");
    grow(pressure_term, "pressure_term"); grow(inverse_density, "inverse_density");
    grow(kind, "kind"); grow(id, "id");
    grow(x_start, "x_start"); grow(v_start, "v_start"); grow(dvdt, "dvdt");
    grow(rho_start, "rho_start"); grow(drhodt, "drhodt");
    if (has_surfaces) {
      grow(wall_vector, "wall_vector"); grow(wall_scalar, "wall_scalar"); grow(wall_drag, "wall_drag");
    }
    if (has_shifting) {
      grow(shift, "shift"); grow(shift_velocity, "shift_velocity");
    }
    if (has_level_start) {
      grow(v_level_start, "v_level_start"); grow(p_level_start, "p_level_start");
    }
  }
};

}  // namespace poresph
