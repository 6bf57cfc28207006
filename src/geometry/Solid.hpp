#pragma once
// The solid of a scene, whatever describes it: grains (circles, spheres) or
// a segmented image (a signed distance field from its voxels). Everything
// that needs the solid asks here: which lattice points are fluid, boundary
// or buried (the lattice), how porous the cell is and how narrow its pores
// (the checks), and, in kernels, how deep a point lies inside (SolidMap:
// fluid kept out, the gridded output). The physics sees boundary particles
// only, each carrying its own surface, and never asks what made it.
//
// Grain boundary particles carry their grain (offset to the centre and
// radius: the no-slip distances are exact on a circle or sphere). Image
// boundary particles carry the tangent plane of the surface nearest them
// (unit normal into the pore and depth below the surface), and fixed fluid
// particles near an image surface their own normal and distance to it.
#include <Kokkos_Core.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "core/Math.hpp"
#include "core/Particles.hpp"
#include "geometry/DistanceField.hpp"
#include "geometry/GrainMap.hpp"
#include "geometry/Grains.hpp"
#include "scene/SceneConfig.hpp"

namespace poresph {

// This process's block of the particle lattice (points at (i + 1/2) dx):
// global indices local_first .. local_first + local_count - 1 along each
// direction, of a lattice count points across (first = its lowest index,
// below 0 where channel walls add layers).
template <int Dim>
struct LatticeBlock {
  double dx = 0;
  double shell = 0;       // depth of the boundary layer inside a solid, 3h
  double on_surface = 0;  // points this close to a surface, or to the shell's inner edge, count as on it
  int first[Dim] = {}, count[Dim] = {};
  int local_first[Dim] = {}, local_count[Dim] = {};
  long long total = 0;  // local points

  long long flat_index(const int (&index)[Dim]) const {
    long long k = 0;
    for (int d = Dim - 1; d >= 0; --d) k = k * local_count[d] + (index[d] - local_first[d]);
    return k;
  }
  bool in_local(const int (&index)[Dim]) const {
    for (int d = 0; d < Dim; ++d)
      if (index[d] < local_first[d] || index[d] >= local_first[d] + local_count[d]) return false;
    return true;
  }
};

// What the solid makes of a lattice point: fluid (outside it; near an
// image's surface, with its own normal and distance to it), a boundary
// particle of the given kind with its surface, or nothing (buried deeper
// than the boundary layer).
template <int Dim>
struct SolidMark {
  static constexpr int kBuried = -1;
  int kind = kFluid;
  double wall_vector[Dim] = {};
  double wall_scalar = 0;
};

// Grains: each grain's bounding box is scanned (periodically wrapped), so
// the cost grows with the solid volume, not with grains x lattice points.
// Where shells overlap, a point belongs to the grain whose surface is nearest.
template <int Dim>
void mark_grain_shells(const std::vector<Grain>& grains, const std::array<bool, 3>& periodic,
                       const LatticeBlock<Dim>& block, std::vector<SolidMark<Dim>>& marks) {
  const double dx = block.dx;
  std::vector<double> depth(marks.size(), 0.0);
  for (const Grain& grain : grains)
    for_each_point_of_grain<Dim>(grain, dx, block.on_surface, periodic, block.count,
                                 [&](const int (&index)[Dim], const double (&from_centre)[Dim], double dist) {
      for (int d = 0; d < Dim; ++d)
        if (!periodic[d] && (index[d] < block.first[d] || index[d] >= block.first[d] + block.count[d])) return;
      if (!block.in_local(index)) return;
      const long long k = block.flat_index(index);
      SolidMark<Dim>& mark = marks[k];
      const double below_surface = grain.radius - dist;
      if (below_surface > block.shell + block.on_surface) {
        mark.kind = SolidMark<Dim>::kBuried;
      } else if (mark.kind != SolidMark<Dim>::kBuried && (mark.kind == kFluid || below_surface < depth[k])) {
        mark.kind = kGrainBoundary;
        depth[k] = below_surface;
        for (int d = 0; d < Dim; ++d) mark.wall_vector[d] = from_centre[d];
        mark.wall_scalar = grain.radius;
      }
    });
}

// The axes along which an image's field wraps: the cell's periodic ones
// that the voxels held span whole.
inline std::array<bool, 3> image_field_periodic(const ImageConfig& image, const std::array<bool, 3>& periodic) {
  std::array<bool, 3> wraps{};
  for (int d = 0; d < 3; ++d) wraps[d] = periodic[d] && image.piece_wraps[d];
  return wraps;
}

// An image: each point reads the signed distance to the surface found
// between the voxels (surface_distance); inside the solid down to the
// shell's depth it is a boundary particle of a sampled surface
// (kSampledBoundary) with the tangent plane there (normal from the
// distance's gradient, depth = -distance). Fixed fluid particles within 3h
// of the surface carry their own normal and distance, so that the no-slip
// distances are measured from their own foot on the surface, as on a grain
// (physics/NoSlip.hpp); moving ones (Particle Motion = lagrangian) would
// leave theirs behind and use the boundary particle's plane. Measured
// against the same grains (docs/validation.md, section 5).
template <int Dim>
void mark_image_shells(const ImageConfig& image, const std::array<bool, 3>& periodic, bool fluid_surfaces,
                       const LatticeBlock<Dim>& block, std::vector<SolidMark<Dim>>& marks) {
  const auto field = host_distance_field<Dim>(*image.distance, image.voxels->shape, image.voxel_size,
                                              image_field_periodic(image, periodic), image.piece_first);
  for (long long flat = 0; flat < block.total; ++flat) {
    double x[Dim];
    long long rest = flat;
    for (int d = 0; d < Dim; ++d) {
      x[d] = (block.local_first[d] + static_cast<int>(rest % block.local_count[d]) + 0.5) * block.dx;
      rest /= block.local_count[d];
    }
    const double distance = field.value(x);
    SolidMark<Dim>& mark = marks[flat];
    if (distance > block.on_surface) {
      // A fluid point within reach of the boundary particles keeps its own
      // normal and distance for their no-slip distances, while it stays here.
      if (fluid_surfaces && distance < block.shell) {
        field.normal(x, mark.wall_vector);
        mark.wall_scalar = distance;
      }
      continue;
    }
    if (-distance > block.shell + block.on_surface) {
      mark.kind = SolidMark<Dim>::kBuried;
      continue;
    }
    mark.kind = kSampledBoundary;
    field.normal(x, mark.wall_vector);
    mark.wall_scalar = -distance;
  }
}

// The solid's marks on a block: empty when the scene has no solid.
template <int Dim>
std::vector<SolidMark<Dim>> mark_solid(const SceneConfig& scene, const LatticeBlock<Dim>& block) {
  std::vector<SolidMark<Dim>> marks;
  if (scene.grains.empty() && !scene.image.voxels) return marks;
  marks.resize(static_cast<size_t>(block.total));
  mark_grain_shells(scene.grains, scene.periodic, block, marks);
  if (scene.image.voxels)
    mark_image_shells(scene.image, scene.periodic, scene.particle_motion == ParticleMotion::Fixed, block, marks);
  return marks;
}

// The solid in kernels: the grains near a point, the image's distance, or a
// channel's walls (the solid below y = 0 and above y = channel_height).
template <int Dim, class MemorySpace>
struct SolidMap {
  GrainMap<Dim, MemorySpace> grains;
  DistanceField<Dim, MemorySpace> image;
  bool has_grains = false, has_image = false, has_channel = false;
  double channel_height = 0;

  bool empty() const { return !has_grains && !has_image && !has_channel; }

  // The solid x lies deepest inside (a grain's index; 0 for the image or a
  // channel wall; -1 if none), the depth below its surface, and the unit
  // normal there, pointing out of the solid.
  KOKKOS_INLINE_FUNCTION int deepest(const double* x, double& depth, double* normal) const {
    int deepest = -1;
    depth = 0;
    if (has_channel) {
      const double below = -x[1], above = x[1] - channel_height;
      if (below > 0 || above > 0) {
        deepest = 0;
        depth = below > 0 ? below : above;
        for (int d = 0; d < Dim; ++d) normal[d] = 0.0;
        normal[1] = below > 0 ? 1.0 : -1.0;
      }
    }
    if (has_grains)
      grains.for_each_grain_near(x, [&](int g) {
        double r[Dim], dist_sq = 0;
        grains.offset_from_centre(x, g, r);
        for (int d = 0; d < Dim; ++d) dist_sq += r[d] * r[d];
        const double radius = grains.grains(g, Dim);
        if (dist_sq >= radius * radius) return;  // outside
        const double dist = math::sqrt(dist_sq);
        if (radius - dist <= depth) return;
        deepest = g;
        depth = radius - dist;
        // At the very centre every way out is as short: along x.
        for (int d = 0; d < Dim; ++d) normal[d] = dist > 0 ? r[d] / dist : (d == 0 ? 1.0 : 0.0);
      });
    if (has_image) {
      const double distance = image.value(x);
      if (distance < 0 && -distance > depth) {
        deepest = 0;
        depth = -distance;
        image.normal(x, normal);
      }
    }
    return deepest;
  }
};

template <int Dim, class MemorySpace>
SolidMap<Dim, MemorySpace> make_solid_map(const SceneConfig& scene, double grain_grid_width) {
  SolidMap<Dim, MemorySpace> map;
  map.has_grains = !scene.grains.empty();
  if (map.has_grains) map.grains = make_grain_map<Dim, MemorySpace>(scene, grain_grid_width);
  map.has_channel = scene.walls == WallType::Channel;
  map.channel_height = scene.cell_size[1];
  map.has_image = static_cast<bool>(scene.image.voxels);
  if (map.has_image)
    map.image = device_distance_field<Dim, MemorySpace>(*scene.image.distance, scene.image.voxels->shape,
                                                        scene.image.voxel_size,
                                                        image_field_periodic(scene.image, scene.periodic),
                                                        scene.image.piece_first);
  return map;
}

// Fraction of the cell that is pore: from the grains' geometry, or the
// image's pore voxels.
double solid_porosity(const SceneConfig& scene);

// The narrowest pore the flow must pass: the narrowest throat between
// grains, or for an image the width at which its widest pore path along the
// driven axes narrows most (ImageConfig::bottleneck). 0: none.
double narrowest_pore(const SceneConfig& scene);

// Refuses pores narrower than one particle spacing (they hold no fluid
// particle, so the flow through them would be lost) and returns warnings
// for those under three (the permeability through them is underestimated).
std::vector<std::string> check_pores(const SceneConfig& scene);

// An image's pore (fraction of its pore voxels) that no ball of diameter
// `width` lying in the pore covers: its passages narrower than that, on
// the flow's path or off it (side throats, wedges by contacts, crevices).
// check_pores warns when more than kNarrowPoreWarning of the pore is
// narrower than 3 spacings: a rough surface's crevices alone stay under it.
double pore_fraction_narrower_than(const SceneConfig& scene, double width);
constexpr double kNarrowPoreWarning = 0.01;

}  // namespace poresph
