#include "geometry/Solid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "geometry/DistanceTransform.hpp"
#include "geometry/Grains.hpp"
#include "geometry/Lattice.hpp"
#include "geometry/Percolation.hpp"
#include "parallel/Communicator.hpp"

namespace poresph {

double solid_porosity(const SceneConfig& scene) {
  if (scene.image.voxels)  // over all the pieces, where each process holds its own
    return static_cast<double>(scene.image.counts.pore) /
           static_cast<double>(scene.image.counts.pore + scene.image.counts.solid);
  return porosity(scene.grains, scene);
}

double narrowest_pore(const SceneConfig& scene) {
  if (scene.image.voxels) {
    double narrowest = 0;
    for (int d = 0; d < scene.dimension; ++d) {
      const double width = scene.image.bottleneck[d];
      if (width > 0 && (narrowest == 0 || width < narrowest)) narrowest = width;
    }
    return narrowest;
  }
  double largest_side = 0;
  for (int d = 0; d < scene.dimension; ++d) largest_side = std::max(largest_side, scene.cell_size[d]);
  // The narrowest throat, searched among ever wider gaps: grains are binned
  // by the gap asked for, so a small one keeps the search linear.
  ThroatSurvey survey;
  for (double widest = largest_side * 1e-3; survey.narrowest.empty() && widest < 4 * largest_side; widest *= 4)
    survey = narrow_throats(scene.grains, scene, widest, 1);
  return survey.narrowest.empty() ? 0.0 : survey.narrowest.front().gap;
}

namespace {

// Lattice points above which the pore path is not traced (5 bytes a point,
// before the scene's memory check, which asks some 400 bytes a point).
constexpr double kMostPointsToTrace = 5e7;

// Lattice points along each axis of a grain scene (1 beyond its dimension).
std::array<long long, 3> lattice_shape(const SceneConfig& scene) {
  std::array<long long, 3> shape{{1, 1, 1}};
  for (int d = 0; d < scene.dimension; ++d)
    shape[d] = lattice_points_across(scene.cell_size[d], scene.particle_spacing, d);
  return shape;
}

// f(flat index, x fastest) for every lattice point (i + 1/2) dx of the
// cell that lies in `grain` (on its surface included, as the boundary
// particles are made), its periodic images folded in.
template <int Dim, class F>
void for_each_point_in(const SceneConfig& scene, const std::array<long long, 3>& shape, const Grain& grain, F&& f) {
  int count[Dim];
  for (int d = 0; d < Dim; ++d) count[d] = static_cast<int>(shape[d]);
  for_each_point_of_grain<Dim>(grain, scene.particle_spacing, 1e-9 * scene.particle_spacing, scene.periodic, count,
                               [&](const int (&index)[Dim], const double (&)[Dim], double) {
                                 size_t flat = 0, stride = 1;
                                 for (int d = 0; d < Dim; ++d) {
                                   if (index[d] < 0 || index[d] >= count[d]) return;  // outside a wall
                                   flat += static_cast<size_t>(index[d]) * stride;
                                   stride *= static_cast<size_t>(count[d]);
                                 }
                                 f(flat);
                               });
}
template <class F>
void for_each_point_in(const SceneConfig& scene, const std::array<long long, 3>& shape, const Grain& grain, F&& f) {
  if (scene.dimension == 2)
    for_each_point_in<2>(scene, shape, grain, f);
  else
    for_each_point_in<3>(scene, shape, grain, f);
}

// The fluid points of a grain scene's lattice (outside every grain), x
// fastest; empty where there are too many to trace.
std::vector<char> grain_fluid_points(const SceneConfig& scene, const std::array<long long, 3>& shape) {
  const double points = static_cast<double>(shape[0]) * static_cast<double>(shape[1]) * static_cast<double>(shape[2]);
  if (points > kMostPointsToTrace) return {};
  std::vector<char> open(static_cast<size_t>(points), 1);
  for (const Grain& grain : scene.grains) for_each_point_in(scene, shape, grain, [&](size_t flat) { open[flat] = 0; });
  return open;
}

// The grains that hold no lattice point: smaller than the spacing, they
// make no boundary particle, and the flow does not see them.
std::vector<const Grain*> grains_without_points(const SceneConfig& scene) {
  const auto shape = lattice_shape(scene);
  std::vector<const Grain*> unseen;
  for (const Grain& grain : scene.grains) {
    if (grain.radius >= scene.particle_spacing) continue;  // a ball of radius dx holds a point
    bool any = false;
    for_each_point_in(scene, shape, grain, [&](size_t) { any = true; });
    if (!any) unseen.push_back(&grain);
  }
  return unseen;
}

}  // namespace

std::vector<std::string> check_pores(const SceneConfig& scene) {
  if (!scene.image.voxels) {
    // The throats first: one narrower than a spacing is refused by name,
    // which says more than the closed path it makes.
    auto warnings = check_throats(scene.grains, scene);
    // Every driven axis (each in turn for the tensor) needs a fluid path
    // across the cell, or the run would spend its steps finding k = 0: the
    // fluid points, joined across faces, traced as an image's pore voxels
    // are (geometry/Percolation.hpp). Grains that touch close throats that
    // the throat check, which looks at gaps, counts as contacts: a square
    // array of touching discs leaves only pockets at its corners. No fluid
    // at all is refused as such by the scene check (app/SceneCheck.cpp).
    const auto shape = lattice_shape(scene);
    const auto open = scene.grains.empty() ? std::vector<char>() : grain_fluid_points(scene, shape);
    if (std::find(open.begin(), open.end(), 1) != open.end())
      for (int axis = 0; axis < scene.dimension; ++axis) {
        const bool driven = scene.periodic[axis] && (scene.permeability_tensor || scene.body_force[axis] != 0);
        if (driven && !open_percolates(shape, scene.dimension, open, axis, scene.periodic))
          throw std::invalid_argument(
              std::string("no pore path crosses the cell along ") + "xyz"[axis] +
              (scene.permeability_tensor ? " (Permeability/Tensor drives every axis)" : ", the driven axis") +
              ": the fluid points between the grains, joined across lattice faces, hold no path through the "
              "cell that way (grains touching one another or their periodic images close it), so no flow gets "
              "through");
      }
    const auto unseen = grains_without_points(scene);
    if (!unseen.empty()) {
      std::ostringstream msg;
      const bool one = unseen.size() == 1;
      msg << unseen.size() << (one ? " grain (" : " grains (") << unseen.front()->origin << ", radius "
          << unseen.front()->radius << (one ? "" : ", ...") << (one ? ") holds" : ") hold")
          << " no lattice point at Discretization/Particle Spacing = " << scene.particle_spacing
          << (one ? ": it makes" : ": they make")
          << " no boundary particle, so the flow passes unseen what the porosity counts. Refine the spacing or "
             "leave such grains out";
      warnings.push_back(msg.str());
    }
    return warnings;
  }
  const double dx = scene.particle_spacing;
  std::vector<std::string> warnings;
  for (int d = 0; d < scene.dimension; ++d) {
    const double width = scene.image.bottleneck[d];
    if (width <= 0 || width >= 3 * dx) continue;
    std::ostringstream msg;
    msg << "Image/File '" << scene.image.file << "': its widest pore path along " << "xyz"[d] << " narrows to "
        << width << " (" << width / scene.image.voxel_size << " voxels, " << width / dx << " particle spacings)";
    if (width < dx) {
      msg << ": narrower than one spacing, it holds no fluid particle and the flow through it would be lost. "
             "Refine Discretization/Particle Spacing";
      throw std::invalid_argument(msg.str());
    }
    msg << ": fewer than 3 spacings across, so the permeability is underestimated";
    warnings.push_back(msg.str());
  }
  // Side throats, wedges and crevices off the widest path: the pore that
  // no ball three spacings across, lying in the pore, covers.
  const double narrow = pore_fraction_narrower_than(scene, 3 * dx);
  if (narrow > kNarrowPoreWarning) {
    std::ostringstream msg;
    msg.precision(3);
    msg << "Image/File '" << scene.image.file << "': " << 100 * narrow
        << " % of its pore volume lies in passages narrower than 3 particle spacings (no ball 3 spacings across "
           "fits there): the permeability through them is underestimated; a finer Discretization/Particle Spacing "
           "resolves them";
    warnings.push_back(msg.str());
  }
  return warnings;
}

double pore_fraction_narrower_than(const SceneConfig& scene, double width) {
  const auto& image = scene.image;
  const auto& voxels = *image.voxels;
  const auto& distance = *image.distance;
  const double radius = 0.5 * width / image.voxel_size;  // in voxels
  // Centres of the balls that fit (at least `radius` from the walls), and
  // each voxel's distance to the nearest of them: a voxel within a radius
  // of one (and a voxel more, for the voxel centres' sampling) is covered.
  // A process holding a piece counts the voxels of its box; its halo holds
  // the centres within reach of them (scene/ImageScene.cpp).
  std::vector<char> centre(distance.size());
  for (size_t n = 0; n < distance.size(); ++n) centre[n] = distance[n] >= radius * image.voxel_size;
  const auto to_centre =
      squared_distance_transform(voxels.shape, voxels.dimension, image_field_periodic(image, scene.periodic), centre);
  const double reach_sq = (radius + 1) * (radius + 1);
  VoxelBox owned = image.owned;
  if (owned.empty()) owned.hi = voxels.shape;  // the whole image
  long long counts[2] = {0, 0};  // pore, and pore no ball covers
  for (long long k = owned.lo[2]; k < owned.hi[2]; ++k)
    for (long long j = owned.lo[1]; j < owned.hi[1]; ++j)
      for (long long i = owned.lo[0]; i < owned.hi[0]; ++i) {
        const size_t n = voxels.index(i - image.piece_first[0], j - image.piece_first[1], k - image.piece_first[2]);
        counts[0] += distance[n] > 0;
        counts[1] += distance[n] > 0 && to_centre[n] > reach_sq;
      }
  Communicator().sum(counts, 2);
  return counts[0] > 0 ? static_cast<double>(counts[1]) / static_cast<double>(counts[0]) : 0.0;
}

}  // namespace poresph
