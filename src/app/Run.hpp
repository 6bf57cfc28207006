#pragma once
// Runs a scene from start to end and reports it: the time loop, the
// diagnostics sampled along the way, the progress line and summary.json.
#include <string>

#include "io/SceneConfig.hpp"
#include "io/Summary.hpp"

namespace poresph {

struct RunOptions {
  std::string output_dir;
  bool progress_on_terminal = true;  // stdout is a terminal
};

// Runs the scene on the default host execution space and returns the
// summary (also written to output_dir/summary.json).
JsonObject run_scene(const SceneConfig& scene, const RunOptions& options);

}  // namespace poresph
