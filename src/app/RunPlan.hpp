#pragma once
// What a run consists of: its stages, in order. A stage is one time loop,
// from its start (a fresh lattice, the end of the stage before it, or a
// checkpoint) to its end (steady k, End Time, Max Steps): a level of the
// resolution ladder (Convergence/Levels, coarse to fine), driven along one
// axis (each in turn with Permeability/Tensor), or the repeat of the finest
// level at half the body force (Permeability/Linearity Check). Stages go
// axis by axis, each axis's levels coarse to fine, so that each stage but
// the first of an axis starts from the stage just before it.
#include <string>
#include <vector>

#include "scene/SceneConfig.hpp"

namespace poresph {

struct Stage {
  int level = 0;          // 0 = coarsest; levels - 1 = the scene's own spacing
  int levels = 1;
  double spacing = 0;
  int drive_axis = -1;    // -1: along the scene's body force; else |F| along this axis
  bool half_force = false;
  bool warm = false;      // starts from the end of the stage before it
  double warm_scale = 1;  // the velocities and pressures it takes are scaled by this
  // Fixed particles: a refined level keeps its start if a finer one follows,
  // and starts from the stage before plus this times what that one changed
  // of its own start (Simulation::warm_start).
  bool keeps_level_start = false;
  double warm_extrapolation = 0;
  std::string suffix;     // of its files: "_x", "_level0", "_x_half_force", ... (io/OutputDirectory.hpp)

  bool finest() const { return level == levels - 1; }
};

// The spacings of the levels, coarse to fine: the finest is the scene's, each
// coarser one Convergence/Refinement Ratio times the next, rounded so that
// every periodic cell side holds a whole number of them. Throws
// std::invalid_argument naming the level where no spacing fits.
std::vector<double> level_spacings(const SceneConfig& scene);

std::vector<Stage> plan_run(const SceneConfig& scene);

// The scene of a stage: its spacing, and its body force.
SceneConfig stage_scene(const SceneConfig& scene, const Stage& stage);

}  // namespace poresph
