#pragma once
// Initial particles on the square (cubic) lattice of spacing dx, points at
// (i + 1/2) dx. Fluid fills the cell outside the grains; grains and plane
// channel walls get boundary particles 3h deep. Particle ids come from the
// lattice index, so whoever generates a particle gives it the same id.
#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <stdexcept>
#include <vector>

#include "core/Kernel.hpp"
#include "core/Particles.hpp"
#include "geometry/Solid.hpp"
#include "scene/SceneConfig.hpp"

namespace poresph {

template <int Dim>
struct SeedParticle {
  double x[Dim];
  double v[Dim];
  int kind;
  double wall_vector[Dim];
  double wall_scalar;
  long long id;
};

// Lattice points along one direction, boundary layers included, fit an int.
constexpr int kMostLatticePointsAcross = 1 << 30;

// Number of lattice points across a periodic cell side; the side must hold a
// whole number of spacings or the periodic lattice would have a seam.
inline int lattice_points_across(double side, double dx, int d) {
  const double n = side / dx;
  const double rounded = std::round(n);
  // Lattice indices are ints: converting a larger count would wrap (to no
  // particles at all, for one), so it is refused here, before any use.
  if (!(rounded <= kMostLatticePointsAcross)) {
    std::ostringstream msg;
    msg << "Domain/Cell Size[" << d << "] / Discretization/Particle Spacing = " << side << " / " << dx << " = " << n
        << " lattice points across: more than " << kMostLatticePointsAcross << ", the most PoreSPH indexes";
    throw std::invalid_argument(msg.str());
  }
  if (rounded < 1 || std::abs(n - rounded) > 1e-6 * rounded) {
    std::ostringstream msg;
    msg << "Domain/Cell Size[" << d << "] = " << side << " is not a whole multiple of Discretization/Particle Spacing = "
        << dx << " (ratio " << std::setprecision(12) << n << ")";
    throw std::invalid_argument(msg.str());
  }
  return static_cast<int>(rounded);
}

// Boundary layers at spacing dx with depth (j + 1/2) dx <= 3h.
inline int boundary_layers(double dx, double h) {
  return static_cast<int>(std::floor(kSupportRadiusInH * h / dx - 0.5 + 1e-9)) + 1;
}

// Fills the lattice: fluid wherever a point is outside the solid; boundary
// particles in the solid's shell, 3h deep below its surface
// (geometry/Solid.hpp), and in the channel walls; nothing deeper.
template <int Dim>
std::vector<SeedParticle<Dim>> fill_lattice(const SceneConfig& scene, const double (&lo)[Dim], const double (&hi)[Dim]);

// The whole cell (one process).
template <int Dim>
std::vector<SeedParticle<Dim>> fill_lattice(const SceneConfig& scene) {
  double lo[Dim], hi[Dim];
  for (int d = 0; d < Dim; ++d) lo[d] = -1e300, hi[d] = 1e300;
  return fill_lattice<Dim>(scene, lo, hi);
}

// Only the lattice points inside the box [lo, hi): every process generates
// its own particles, and none holds the whole problem.
template <int Dim>
std::vector<SeedParticle<Dim>> fill_lattice(const SceneConfig& scene, const double (&lo)[Dim], const double (&hi)[Dim]) {
  const double dx = scene.particle_spacing;
  const double h = scene.smoothing_length_ratio * dx;
  const double shell = kSupportRadiusInH * h;
  // Points on a surface or on the shell's inner edge, up to rounding, belong to the shell.
  const double on_surface = 1e-9 * dx;
  std::array<int, Dim> first{}, count{};
  for (int d = 0; d < Dim; ++d) count[d] = lattice_points_across(scene.cell_size[d], dx, d);
  const bool channel = scene.walls == WallType::Channel;
  const int fluid_rows = count[1];
  if (channel) {
    const int layers = boundary_layers(dx, h);
    first[1] = -layers;
    count[1] += 2 * layers;
  }
  // Global lattice: ids (a 64-bit count of every lattice point). Local range: what this box generates.
  double lattice_points = 1;  // in floating point: its overflow check is a comparison
  for (int d = 0; d < Dim; ++d) lattice_points *= count[d];
  if (lattice_points > 9.2e18)
    throw std::invalid_argument("the lattice has more points than a 64-bit count holds: coarsen "
                                "Discretization/Particle Spacing");
  auto global_id = [&](const int (&index)[Dim]) {
    long long k = 0;
    for (int d = Dim - 1; d >= 0; --d) k = k * count[d] + (index[d] - first[d]);
    return k;
  };
  LatticeBlock<Dim> block;
  block.dx = dx;
  block.shell = shell;
  block.on_surface = on_surface;
  block.total = 1;
  for (int d = 0; d < Dim; ++d) {
    block.first[d] = first[d];
    block.count[d] = count[d];
    const double a = std::max(lo[d], (first[d] - 1.0) * dx), b = std::min(hi[d], (first[d] + count[d] + 1.0) * dx);
    const int begin = std::max(first[d], static_cast<int>(std::ceil(a / dx - 0.5)));
    const int end = std::min(first[d] + count[d], static_cast<int>(std::ceil(b / dx - 0.5)));
    block.local_first[d] = begin;
    block.local_count[d] = std::max(0, end - begin);
    block.total *= block.local_count[d];  // bounded by the whole lattice's count, checked above
  }
  const std::vector<SolidMark<Dim>> marks = mark_solid(scene, block);

  std::vector<SeedParticle<Dim>> seeds;
  seeds.reserve(static_cast<size_t>(block.total));
  for (long long flat = 0; flat < block.total; ++flat) {
    int index[Dim];
    long long rest = flat;
    for (int d = 0; d < Dim; ++d) {
      index[d] = block.local_first[d] + static_cast<int>(rest % block.local_count[d]);
      rest /= block.local_count[d];
    }
    SeedParticle<Dim> s{};
    for (int d = 0; d < Dim; ++d) s.x[d] = (index[d] + 0.5) * dx;
    s.id = global_id(index);
    s.kind = kFluid;
    if (channel && (index[1] < 0 || index[1] >= fluid_rows)) {
      const bool lower = index[1] < 0;
      s.kind = kWallBoundary;
      s.wall_vector[1] = lower ? 1.0 : -1.0;
      s.wall_scalar = lower ? -s.x[1] : s.x[1] - scene.cell_size[1];
      s.v[0] = lower ? scene.lower_wall_velocity : scene.upper_wall_velocity;
    } else if (!marks.empty() && marks[flat].kind == SolidMark<Dim>::kBuried) {
      continue;
    } else if (!marks.empty()) {  // a boundary particle's surface, or a fluid particle's own
      const auto& mark = marks[flat];
      s.kind = mark.kind;
      for (int d = 0; d < Dim; ++d) s.wall_vector[d] = mark.wall_vector[d];
      s.wall_scalar = mark.wall_scalar;
    }
    seeds.push_back(s);
  }
  return seeds;
}

// Copies seeds into owned slots [0, n) with uniform initial density rho0 and
// mass rho0 dx^Dim.
template <int Dim, class ExecSpace>
void load_seeds(const std::vector<SeedParticle<Dim>>& seeds, double rho0, double dx,
                Particles<Dim, typename ExecSpace::memory_space>& P) {
  // Particles are indexed by int on each process.
  if (seeds.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
    throw std::invalid_argument("one process would hold " + std::to_string(seeds.size()) +
                                " particles, more than it can index (2^31 - 1): run on more processes");
  const int n = static_cast<int>(seeds.size());
  P.reserve(n);
  P.owned = n;
  P.ghosts = 0;
  const double mass = rho0 * std::pow(dx, Dim);
  auto x = Kokkos::create_mirror_view(P.x), v = Kokkos::create_mirror_view(P.v);
  auto rho = Kokkos::create_mirror_view(P.rho), m = Kokkos::create_mirror_view(P.m);
  auto kind = Kokkos::create_mirror_view(P.kind);
  auto id = Kokkos::create_mirror_view(P.id);
  auto wall_vector = Kokkos::create_mirror_view(P.wall_vector);
  auto wall_scalar = Kokkos::create_mirror_view(P.wall_scalar);
  for (int i = 0; i < n; ++i) {
    const auto& s = seeds[i];
    for (int d = 0; d < Dim; ++d) {
      x(i, d) = s.x[d];
      v(i, d) = s.v[d];
      if (P.has_surfaces) wall_vector(i, d) = s.wall_vector[d];
    }
    rho(i) = rho0;
    m(i) = mass;
    kind(i) = s.kind;
    id(i) = s.id;
    if (P.has_surfaces) wall_scalar(i) = s.wall_scalar;
  }
  Kokkos::deep_copy(P.x, x); Kokkos::deep_copy(P.v, v);
  Kokkos::deep_copy(P.rho, rho); Kokkos::deep_copy(P.m, m);
  Kokkos::deep_copy(P.kind, kind); Kokkos::deep_copy(P.id, id);
  if (P.has_surfaces) { Kokkos::deep_copy(P.wall_vector, wall_vector); Kokkos::deep_copy(P.wall_scalar, wall_scalar); }
}

}  // namespace poresph
