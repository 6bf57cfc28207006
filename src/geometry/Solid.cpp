#include "geometry/Solid.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "geometry/DistanceTransform.hpp"
#include "geometry/Grains.hpp"
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

std::vector<std::string> check_pores(const SceneConfig& scene) {
  if (!scene.image.voxels) return check_throats(scene.grains, scene);
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
