#pragma once
// Recursive coordinate bisection of the unit cell by Zoltan2, weighted by
// the particles each part will hold (grain interiors hold none).
#include "scene/SceneConfig.hpp"
#include "parallel/Communicator.hpp"
#include "parallel/Decomposition.hpp"

namespace poresph {

template <int Dim>
Decomposition<Dim> rcb_decomposition(const SceneConfig& scene, const Communicator& comm);

}  // namespace poresph
