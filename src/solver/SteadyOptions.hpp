#pragma once
// What a steady solve is asked for (Solver/ in the parameters,
// solver/SteadySolver.hpp); a plain struct, so that the scene can carry it.

namespace poresph {

struct SteadyOptions {
  double tolerance = 1e-6;         // Solver/Tolerance: on ||F - e (e . F)|| / ||F at rest||
  double linear_tolerance = 1e-8;  // Solver/Linear Tolerance: the least a Newton step's solve is asked for
  int max_nonlinear_iterations = 10;
  int max_linear_iterations = 1000;  // per Newton step
  int restart = 30;
  double inner_tolerance = 1e-2;
  int max_inner_iterations = 100;
};

}  // namespace poresph
