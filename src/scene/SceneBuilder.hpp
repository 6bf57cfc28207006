#pragma once
// The scene builder: a validated parameter list (io/Parameters.hpp) made
// into the solver's SceneConfig. It checks what depends on several
// parameters at once (array lengths, walls against periodicity, what is
// measured), makes the solid (grains from a file, inline or a random pack;
// or a segmented image, scene/ImageScene.hpp), and checks the grains,
// the pore throats and the spacing across them. io/ reads; this builds.
#include <Teuchos_ParameterList.hpp>

#include <string>

#include "scene/SceneConfig.hpp"

namespace poresph {

// The validated list as the solver's plain configuration. Relative file
// names are taken from `scene_directory`. Throws ParameterError (naming the
// parameter) for anything the scene asks that cannot be built.
SceneConfig scene_from_parameters(const Teuchos::ParameterList& list, const std::string& scene_directory = "");

}  // namespace poresph
