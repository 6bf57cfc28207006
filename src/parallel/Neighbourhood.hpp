#pragma once
// Who is near whom: the ghosts of neighbouring processes and periodic images
// (parallel/Halo.hpp), the cell list over this process's box and its halo,
// and the Verlet list of pairs within the support plus a skin
// (core/NeighbourList.hpp), with what keeps them valid: the positions at the
// last build, against which a particle that has moved half the skin asks
// for a new one. It knows nothing of what the particles carry.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <array>
#include <string>
#include <utility>

#include "core/CellList.hpp"
#include "core/NeighbourList.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"
#include "parallel/Communicator.hpp"
#include "parallel/Decomposition.hpp"
#include "parallel/Halo.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
class Neighbourhood {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using ParticleSet = Particles<Dim, MemorySpace>;

  Neighbourhood() = default;
  // Pairs within cutoff + skin, on this process's box of `decomposition`
  // of a cell of sides `cell`. Fixed particles (skin 0): built once, never
  // stale, with nothing kept for later builds.
  Neighbourhood(const Communicator& comm, const Decomposition<Dim>& decomposition, const std::array<double, 3>& cell,
                double cutoff, double skin, bool fixed_particles = false)
      : comm_(comm), halo_(comm, decomposition, cutoff + skin), cutoff_(cutoff), skin_(skin), fixed_(fixed_particles) {
    const auto& box = halo_.box();
    for (int d = 0; d < Dim; ++d) {
      // The search covers the box and its halo (walls beyond the cell included).
      search_lo_[d] = std::max(box.lo[d], 0.0) - reach();
      search_hi_[d] = std::min(box.hi[d], cell[d]) + reach();
    }
  }

  double reach() const { return cutoff_ + skin_; }
  const Box<Dim>& box() const { return halo_.box(); }
  const Decomposition<Dim>& decomposition() const { return halo_.decomposition(); }

  // Whether some particle has moved more than half the skin since the last
  // build (or there was none), agreed by every process: they exchange ghosts.
  bool stale(const ExecSpace& space, const ParticleSet& P) const {
    if (!built_ || fixed_) return !built_;
    const auto x = P.x;
    const auto x0 = x_at_build_;
    const double limit_sq = 0.25 * skin_ * skin_;
    int moved = 0;
    static const std::string label = "poresph::Neighbourhood::stale";
    Kokkos::parallel_reduce(
        label, Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned),
        KOKKOS_LAMBDA(int i, int& count) {
          double d_sq = 0;
          for (int d = 0; d < Dim; ++d) d_sq += (x(i, d) - x0(i, d)) * (x(i, d) - x0(i, d));
          count += d_sq > limit_sq;
        },
        moved);
    return comm_.any(moved > 0);
  }

  // Positions stay unwrapped between builds, so that ghosts and lists stay
  // consistent; at a rebuild owned particles that left the cell are wrapped
  // back and handed to their new owners, then everything is built afresh.
  void rebuild(const ExecSpace& space, ParticleSet& P) {
    halo_.wrap(P);
    halo_.migrate(P);
    build(space, P);
  }

  // Ghosts, cells and list for the owned particles where they are.
  void build(const ExecSpace& space, ParticleSet& P) {
    halo_.build(P);
    if (fixed_) halo_.fit();  // built once
    cells_.build(space, P.x, P.total(), search_lo_, search_hi_, reach());
    cells_released_ = false;
    const bool rows = lattice_stencil_.size() > 0 &&
                      list_.build_lattice_rows(space, cells_, P.x, P.owned, P.total(), reach(), lattice_stencil_,
                                               lattice_spacing_);
    if (!rows) build_list(space, P);
    if (!fixed_) {  // fixed particles are where the list was built
      const auto owned = std::make_pair(0, P.owned);
      if (static_cast<int>(x_at_build_.extent(0)) < P.owned)
        x_at_build_ = typename ParticleSet::Vector("x_at_build", P.owned);
      Kokkos::deep_copy(space, Kokkos::subview(x_at_build_, owned, Kokkos::ALL),
                        Kokkos::subview(P.x, owned, Kokkos::ALL));
    }
    built_ = true;
    ++builds_;
  }

  // Fixed particles on a lattice of this spacing: from the next build on,
  // the list's rows are masks over this stencil where every pair is one of
  // its offsets (core/LatticeRows.hpp).
  void use_lattice_rows(const LatticeStencil<Dim, MemorySpace>& stencil, double spacing) {
    lattice_stencil_ = stencil;
    lattice_spacing_ = spacing;
  }
  // The list itself, from the cells of the last build.
  void build_list(const ExecSpace& space, const ParticleSet& P) {
    list_.build(space, cells_, P.x, P.owned, reach(), skin_ > 0);  // without skin, built once
  }

  // The ghosts' changing fields, along the routes of the last build.
  void update_ghosts(ParticleSet& P) { halo_.update(P); }
  // Values that are no particle's field (a value or a row of values per
  // slot), from the owned slots [0, owned) to the ghosts, along the same routes.
  template <class Values>
  void update_ghost_values(const Values& values, int owned) {
    halo_.update_values(values, owned);
  }
  // The next refresh wraps, migrates and builds (particles arrived from elsewhere).
  void invalidate() { built_ = false; }

  // The cell list of the last build. Fixed particles give it back once
  // their lists are made (release_cells: no step reads it); what
  // interpolates asks for it again (ensure_cells), made as the build made it.
  const CellList<Dim, ExecSpace>& cells() const { return cells_; }
  void release_cells() {
    cells_ = CellList<Dim, ExecSpace>();
    cells_released_ = true;
  }
  void ensure_cells(const ExecSpace& space, const ParticleSet& P) {
    if (!cells_released_) return;
    cells_.build(space, P.x, P.total(), search_lo_, search_hi_, reach());
    cells_released_ = false;
  }
  NeighbourList<Dim, ExecSpace>& list() { return list_; }
  const NeighbourList<Dim, ExecSpace>& list() const { return list_; }
  // Owned positions at the last build; empty for fixed particles (they are there).
  const typename ParticleSet::Vector& positions_at_build() const { return x_at_build_; }
  long long builds() const { return builds_; }
  bool built() const { return built_; }

 private:
  Communicator comm_;
  Halo<Dim, ExecSpace> halo_;
  CellList<Dim, ExecSpace> cells_;
  bool cells_released_ = false;  // release_cells() since the last build
  NeighbourList<Dim, ExecSpace> list_;
  LatticeStencil<Dim, MemorySpace> lattice_stencil_;  // empty: no rows as masks
  double lattice_spacing_ = 0;
  double cutoff_ = 0, skin_ = 0;
  bool fixed_ = false;
  Vec<Dim> search_lo_, search_hi_;  // the box extended by the reach: where ghosts and walls live
  typename ParticleSet::Vector x_at_build_;  // owned positions at the last build (moving particles)
  bool built_ = false;
  long long builds_ = 0;
};

}  // namespace poresph
