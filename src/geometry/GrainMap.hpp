#pragma once
// Which grains can touch a point, found in constant time: the unit cell is
// cut into a coarse grid once (grains do not move), and every grid cell lists
// the grains whose surface, or any periodic image of it, reaches into it.
// Kernels ask for the grains near a particle without looping over all of
// them, so a packing of thousands of grains costs the same per particle as
// one grain.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/Math.hpp"
#include "scene/SceneConfig.hpp"

namespace poresph {

template <int Dim, class MemorySpace>
struct GrainMap {
  Kokkos::View<double* [Dim + 1], MemorySpace> grains;  // centre, radius
  Kokkos::View<int*, MemorySpace> begin;                // grid cell c lists grain_index[begin(c) .. begin(c+1))
  Kokkos::View<int*, MemorySpace> grain_index;
  double cell_side[Dim] = {};
  double width[Dim] = {};  // of a grid cell
  int count[Dim] = {};
  bool periodic[Dim] = {};

  bool empty() const { return grains.extent(0) == 0; }

  KOKKOS_INLINE_FUNCTION int grid_cell(const double* x) const {
    int c = 0;
    for (int d = Dim - 1; d >= 0; --d) {
      double y = x[d];
      if (periodic[d]) y -= cell_side[d] * math::floor(y / cell_side[d]);
      int k = static_cast<int>(y / width[d]);
      k = k < 0 ? 0 : k >= count[d] ? count[d] - 1 : k;  // outside a wall: its nearest grid cell
      c = c * count[d] + k;
    }
    return c;
  }

  // x - centre of grain g, to the nearest periodic image.
  KOKKOS_INLINE_FUNCTION void offset_from_centre(const double* x, int g, double* r) const {
    for (int d = 0; d < Dim; ++d) {
      r[d] = x[d] - grains(g, d);
      if (periodic[d]) r[d] -= cell_side[d] * math::floor(r[d] / cell_side[d] + 0.5);
    }
  }

  // The grain whose centre lies at x - offset (a boundary particle's own
  // grain, from its stored offset to the centre), or -1.
  KOKKOS_INLINE_FUNCTION int grain_with_offset(const double* x, const double* offset, double tolerance) const {
    int found = -1;
    for_each_grain_near(x, [&](int g) {
      double r[Dim], mismatch = 0;
      offset_from_centre(x, g, r);
      for (int d = 0; d < Dim; ++d) mismatch += (r[d] - offset[d]) * (r[d] - offset[d]);
      if (mismatch <= tolerance * tolerance) found = g;
    });
    return found;
  }

  // Calls f(g) for every grain g that may contain x.
  template <class F>
  KOKKOS_INLINE_FUNCTION void for_each_grain_near(const double* x, F&& f) const {
    const int c = grid_cell(x);
    for (int k = begin(c); k < begin(c + 1); ++k) f(grain_index(k));
  }
};

// Grid cells about `target_width` wide (at least one per direction).
template <int Dim, class MemorySpace>
GrainMap<Dim, MemorySpace> make_grain_map(const SceneConfig& scene, double target_width) {
  GrainMap<Dim, MemorySpace> map;
  int cells = 1;
  for (int d = 0; d < Dim; ++d) {
    map.cell_side[d] = scene.cell_size[d];
    map.periodic[d] = scene.periodic[d];
    map.count[d] = std::max(1, static_cast<int>(scene.cell_size[d] / target_width));
    map.width[d] = scene.cell_size[d] / map.count[d];
    cells *= map.count[d];
  }
  const int ngrains = static_cast<int>(scene.grains.size());
  map.grains = decltype(map.grains)("grains", ngrains);
  auto grains = Kokkos::create_mirror_view(map.grains);
  for (int g = 0; g < ngrains; ++g) {
    for (int d = 0; d < Dim; ++d) grains(g, d) = scene.grains[g].centre[d];
    grains(g, Dim) = scene.grains[g].radius;
  }
  Kokkos::deep_copy(map.grains, grains);

  // A grain reaches a grid cell if the cell's nearest point to some image of
  // the centre lies within the radius. Scan each grain's bounding box only.
  std::vector<std::vector<int>> lists(cells);
  for (int g = 0; g < ngrains; ++g) {
    const auto& grain = scene.grains[g];
    int first[Dim], last[Dim];
    for (int d = 0; d < Dim; ++d) {
      first[d] = static_cast<int>(std::floor((grain.centre[d] - grain.radius) / map.width[d]));
      last[d] = static_cast<int>(std::floor((grain.centre[d] + grain.radius) / map.width[d]));
      if (!map.periodic[d]) {  // periodic: the range runs over images and wraps below
        first[d] = std::max(first[d], 0);
        last[d] = std::min(last[d], map.count[d] - 1);
      }
    }
    int index[Dim];
    for (int d = 0; d < Dim; ++d) index[d] = first[d];
    while (true) {
      double dist_sq = 0;
      int c = 0;
      for (int d = Dim - 1; d >= 0; --d) {
        const double lo = index[d] * map.width[d], hi = lo + map.width[d];
        const double nearest = std::clamp(grain.centre[d], lo, hi);
        dist_sq += (grain.centre[d] - nearest) * (grain.centre[d] - nearest);
        const int wrapped = ((index[d] % map.count[d]) + map.count[d]) % map.count[d];
        c = c * map.count[d] + wrapped;
      }
      if (dist_sq <= grain.radius * grain.radius &&
          (lists[c].empty() || lists[c].back() != g))  // a periodic image may meet the same cell twice
        lists[c].push_back(g);
      int d = 0;
      while (d < Dim && ++index[d] > last[d]) index[d] = first[d], ++d;
      if (d == Dim) break;
    }
  }
  map.begin = decltype(map.begin)("grain_map_begin", cells + 1);
  auto begin = Kokkos::create_mirror_view(map.begin);
  begin(0) = 0;
  for (int c = 0; c < cells; ++c) begin(c + 1) = begin(c) + static_cast<int>(lists[c].size());
  map.grain_index = decltype(map.grain_index)("grain_map_index", begin(cells));
  auto index = Kokkos::create_mirror_view(map.grain_index);
  for (int c = 0; c < cells; ++c)
    std::copy(lists[c].begin(), lists[c].end(), index.data() + begin(c));
  Kokkos::deep_copy(map.begin, begin);
  Kokkos::deep_copy(map.grain_index, index);
  return map;
}

}  // namespace poresph
