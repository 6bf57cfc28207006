#pragma once
// Runs a scene file shipped in input/ as a user runs it (XML, --set
// overrides, relative grain files) and returns what it measured.
#include <filesystem>
#include <string>
#include <vector>

#include "app/Run.hpp"
#include "io/Parameters.hpp"
#include "scene/SceneBuilder.hpp"

namespace poresph::testing {

// Where run_input writes the run named `output` (the scene's name unless given).
inline std::filesystem::path output_directory(const std::string& output) {
  return std::filesystem::temp_directory_path() / ("poresph-test-" + output);
}

// The output goes to a folder of the temporary directory named after the
// scene, or `output` if given (output_directory); `restart` names a file in
// that folder to continue from (a checkpoint of an earlier run_input).
inline RunReport run_input(const std::string& file, std::vector<std::string> overrides = {},
                           const std::string& output = "", const std::string& restart = "") {
  const std::string path = std::string(PORESPH_INPUT_DIR) + "/" + file;
  overrides.push_back("Run/Progress=never");
  auto parameters = read_parameters(path, overrides);
  const SceneConfig scene = scene_from_parameters(*parameters, std::filesystem::path(path).parent_path().string());
  RunOptions options;
  options.output_dir = output_directory(output.empty() ? scene.name : output).string();
  std::filesystem::create_directories(options.output_dir);
  options.progress_on_terminal = false;
  if (!restart.empty()) options.restart_file = options.output_dir + "/" + restart;
  options.parameters_xml = parameters_to_xml(*parameters);
  return run_scene(scene, options);
}

}  // namespace poresph::testing
