#pragma once
// The fluid's regions, for the steady solver's borders: the sets of fixed
// fluid particles joined by chains of lattice neighbours (points one step
// apart along each axis: faces, edges and corners), over all processes.
//
// Why: the march keeps each region's mass. A pocket of pore space sealed by
// solid exchanges none with the rest, and one sealed by a wall thinner than
// the kernel's reach exchanges mass only through the pairs across it, at
// the rate of a mode of the continuity-gradient operator so weak that the
// march's k settles long before it does (docs/steady_solver.md, "One
// border per region of the fluid"). Each region therefore keeps its own
// mean density and its own uniform density drift in the steady solve, one
// border each.
//
// How: a union-find over this process's pairs (set-up only, on the host:
// the backends are Serial and OpenMP), then rounds in which every local
// piece takes the smallest label among its slots and the ghosts take their
// owners' labels, until no label changes anywhere: about as many rounds as
// processes a region crosses, however winding it is.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "app/Simulation.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"

namespace poresph {

template <class MemorySpace>
struct FluidRegions {
  Kokkos::View<int*, MemorySpace> of;  // per owned particle: its region, -1 for a boundary particle
  std::vector<double> sizes;           // fluid particles per region, over all processes
  int count() const { return static_cast<int>(sizes.size()); }
};

// Whether two fixed particles at r are lattice neighbours (spacing dx):
// |r|^2 below (Dim + 1/2) dx^2 holds the corner at sqrt(Dim) dx and not the
// point two steps away along an axis.
template <int Dim>
KOKKOS_INLINE_FUNCTION bool lattice_neighbours(const Vec<Dim>& r, double dx) {
  return dot(r, r) < (Dim + 0.5) * dx * dx;
}

namespace detail {

// The slots' local pieces: a root slot per slot (union-find with path halving).
class LocalPieces {
 public:
  explicit LocalPieces(int slots) : parent_(slots) { std::iota(parent_.begin(), parent_.end(), 0); }
  int root(int a) {
    while (parent_[a] != a) a = parent_[a] = parent_[parent_[a]];
    return a;
  }
  void join(int a, int b) {
    a = root(a), b = root(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

// Every fluid slot's value becomes the smallest among the slots of its
// region, over all processes; the others' are left as they are. values:
// host-accessible, a value per slot, the owned ones set.
template <int Dim, class ExecSpace, class Kinds>
void spread_minimum(Simulation<Dim, ExecSpace>& sim, LocalPieces& pieces, const Kinds& kind,
                    const typename Simulation<Dim, ExecSpace>::Scalars& values) {
  const int owned = sim.particles().owned, slots = sim.particles().total();
  std::vector<double> least(slots);
  for (bool changed = true; changed;) {
    sim.update_ghost_values(values);
    std::fill(least.begin(), least.end(), std::numeric_limits<double>::infinity());
    for (int a = 0; a < slots; ++a)
      if (kind(a) == kFluid) least[pieces.root(a)] = std::min(least[pieces.root(a)], values(a));
    bool lowered = false;
    for (int a = 0; a < owned; ++a) {
      if (kind(a) != kFluid || !(least[pieces.root(a)] < values(a))) continue;
      values(a) = least[pieces.root(a)];
      lowered = true;
    }
    changed = sim.communicator().any(lowered);
  }
}

}  // namespace detail

// The regions of a fixed-particle simulation whose pair list is built.
// Numbered by their smallest particle id, so the same on any number of processes.
template <int Dim, class ExecSpace>
FluidRegions<typename ExecSpace::memory_space> find_fluid_regions(Simulation<Dim, ExecSpace>& sim) {
  using Scalars = typename Simulation<Dim, ExecSpace>::Scalars;
  static_assert(Kokkos::SpaceAccessibility<Kokkos::HostSpace, typename ExecSpace::memory_space>::accessible,
                "the regions are found on the host");
  const auto& P = sim.particles();
  const int owned = P.owned, slots = P.total();
  const auto kind = P.kind;
  const auto id = P.id;
  const double dx = sim.scene().particle_spacing;
  const auto& list = sim.neighbour_list();
  detail::LocalPieces pieces(slots);
  for (int a = 0; a < owned; ++a) {
    if (kind(a) != kFluid) continue;
    list.for_each_entry(a, [&](int b, const Vec<Dim>& r) {
      if (kind(b) == kFluid && lattice_neighbours<Dim>(r, dx)) pieces.join(a, b);
    });
  }
  // Each region's smallest id, then the region's number from it.
  Scalars label("poresph::fluid_regions::label", slots);
  for (int a = 0; a < owned; ++a) label(a) = static_cast<double>(id(a));
  detail::spread_minimum(sim, pieces, kind, label);
  std::vector<int> roots;  // owned fluid particles that name their region
  for (int a = 0; a < owned; ++a)
    if (kind(a) == kFluid && label(a) == static_cast<double>(id(a))) roots.push_back(a);
  const auto& comm = sim.communicator();
  std::vector<long long> per_process(comm.size(), 0);
  per_process[comm.rank()] = static_cast<long long>(roots.size());
  comm.sum(per_process.data(), comm.size());
  const long long first = std::accumulate(per_process.begin(), per_process.begin() + comm.rank(), 0LL);
  const long long count = std::accumulate(per_process.begin(), per_process.end(), 0LL);
  // Every process learns every region's smallest id; a region's number is
  // that id's place among them.
  std::vector<double> root_ids(count, 0.0);
  for (size_t k = 0; k < roots.size(); ++k) root_ids[first + k] = static_cast<double>(id(roots[k]));
  comm.sum(root_ids.data(), static_cast<int>(count));
  std::vector<double> sorted = root_ids;
  std::sort(sorted.begin(), sorted.end());
  FluidRegions<typename ExecSpace::memory_space> regions;
  regions.of = Kokkos::View<int*, typename ExecSpace::memory_space>("poresph::fluid_regions", owned);
  regions.sizes.assign(count, 0.0);
  for (int a = 0; a < owned; ++a) {
    if (kind(a) != kFluid) {
      regions.of(a) = -1;
      continue;
    }
    const int r = static_cast<int>(std::lower_bound(sorted.begin(), sorted.end(), label(a)) - sorted.begin());
    regions.of(a) = r;
    regions.sizes[r] += 1;
  }
  comm.sum(regions.sizes.data(), static_cast<int>(count));
  return regions;
}

}  // namespace poresph
