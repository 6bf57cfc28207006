#pragma once
// Recursive coordinate bisection of the unit cell by Zoltan2, weighted by
// the particles each part will hold (grain interiors hold none), at the
// start or, for a load balance that follows the run, anew.
#include <vector>

#include "scene/SceneConfig.hpp"
#include "parallel/Communicator.hpp"
#include "parallel/Decomposition.hpp"

namespace poresph {

template <int Dim>
Decomposition<Dim> rcb_decomposition(const SceneConfig& scene, const Communicator& comm);

// The cell divided anew among the processes of `comm` at the particles'
// present places: each process gives its own particles' coordinates (Dim a
// particle), ids and weights, and every part holds an equal sum of weight.
template <int Dim>
Decomposition<Dim> rcb_decomposition_of_particles(const SceneConfig& scene, std::vector<double>& coordinates,
                                                  std::vector<long long>& ids, const std::vector<double>& weights,
                                                  const Communicator& comm);

}  // namespace poresph
