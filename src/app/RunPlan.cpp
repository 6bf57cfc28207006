#include "app/RunPlan.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "io/OutputDirectory.hpp"

namespace poresph {

std::vector<double> level_spacings(const SceneConfig& scene) {
  const int levels = scene.convergence_levels;
  std::vector<double> spacings(levels);
  spacings[levels - 1] = scene.particle_spacing;
  // Counts along the first side; the other sides must follow in proportion.
  const double finest_count = scene.cell_size[0] / scene.particle_spacing;
  for (int l = levels - 2; l >= 0; --l) {
    const double ratio = std::pow(scene.refinement_ratio, levels - 1 - l);
    const double count = std::max(1.0, std::round(finest_count / ratio));
    const double dx = scene.cell_size[0] / count;
    for (int d = 1; d < scene.dimension; ++d) {
      const double n = scene.cell_size[d] / dx;
      if (std::abs(n - std::round(n)) > 1e-6 * n) {
        std::ostringstream msg;
        msg << "Convergence/Levels = " << levels << ": level " << l << " (spacing " << dx << ", "
            << scene.refinement_ratio << "^" << levels - 1 - l << " times the finest) does not fit Domain/Cell Size["
            << d << "] = " << scene.cell_size[d] << " a whole number of times; choose a spacing or ratio that does";
        throw std::invalid_argument(msg.str());
      }
    }
    if (!(dx > spacings[l + 1] * (1 + 1e-9))) {
      std::ostringstream msg;
      msg << "Convergence/Levels = " << levels << ": level " << l << " would have spacing " << dx
          << ", no coarser than level " << l + 1 << "'s " << spacings[l + 1]
          << " (too many levels for the cell at Convergence/Refinement Ratio = " << scene.refinement_ratio << ")";
      throw std::invalid_argument(msg.str());
    }
    spacings[l] = dx;
  }
  return spacings;
}

std::vector<Stage> plan_run(const SceneConfig& scene) {
  const auto spacings = level_spacings(scene);
  const int levels = static_cast<int>(spacings.size());
  std::vector<int> axes;
  if (scene.permeability_tensor)  // each axis the cell is open along: no flow crosses the channel's walls
    for (int d = 0; d < scene.dimension; ++d) {
      if (scene.periodic[d]) axes.push_back(d);
    }
  else
    axes.push_back(-1);
  std::vector<Stage> stages;
  for (int axis : axes) {
    for (int l = 0; l < levels; ++l) {
      Stage s;
      s.level = l, s.levels = levels, s.spacing = spacings[l], s.drive_axis = axis;
      s.warm = l > 0;
      // The refinement from level l - 1 to l changes the flow by about 1 / r^p
      // of what the one before changed (Richardson, p = 2, the order of the
      // kernel's interpolation error): continuing it gives a start closer to
      // the level's own flow, and only the start: the level still runs to its
      // own steady state (docs/method.md). Needs two levels before it.
      if (scene.particle_motion == ParticleMotion::Fixed) {
        s.keeps_level_start = l > 0 && l < levels - 1;
        const double r = l >= 2 ? spacings[l - 1] / spacings[l] : 0;  // as rounded to the cell
        if (l >= 2) s.warm_extrapolation = 1.0 / (r * r - 1.0);
      }
      s.suffix = stage_suffix(axis, l, levels, false);
      stages.push_back(s);
    }
    if (scene.linearity_check) {
      Stage s = stages.back();
      s.half_force = true;
      // Darcy flow is linear in the force: half the finest flow is where a
      // linear flow ends, and what is left to settle is the inertia.
      s.warm = true, s.warm_scale = 0.5;
      s.keeps_level_start = false, s.warm_extrapolation = 0;  // the same level: nothing to continue
      s.suffix = stage_suffix(axis, s.level, levels, true);
      stages.push_back(s);
    }
  }
  return stages;
}

SceneConfig stage_scene(const SceneConfig& scene, const Stage& stage) {
  SceneConfig s = scene;
  s.particle_spacing = stage.spacing;
  const double force = body_force_magnitude(scene);
  if (stage.drive_axis >= 0) {
    s.body_force = {0, 0, 0};
    s.body_force[stage.drive_axis] = force;
  }
  if (stage.half_force)
    for (double& f : s.body_force) f *= 0.5;
  return s;
}

}  // namespace poresph
