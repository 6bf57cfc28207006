#include "geometry/Solid.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "geometry/Grains.hpp"

namespace poresph {

double solid_porosity(const SceneConfig& scene) {
  if (scene.image.voxels)
    return static_cast<double>(scene.image.counts.pore) / static_cast<double>(scene.image.voxels->count());
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
  return warnings;
}

}  // namespace poresph
