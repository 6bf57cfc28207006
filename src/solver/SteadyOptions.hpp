#pragma once
// What a steady solve is asked for (Solver/ in the parameters,
// solver/SteadySolver.hpp); a plain struct, so that the scene can carry it.

namespace poresph {

// What preconditions the inner solves of DG (Solver/DG Preconditioner):
// the wide lattice Laplacian's cycle, local solves on blocks, or the cycle
// until the DG solves stall at their cap, then the blocks (2D).
enum class DgPreconditioner { Lattice, Schwarz, Auto };
// Its blocks: 8 points a side, each extended by 2. On a 2D blobs image
// these took the fewest outer iterations of blocks of 4 or 8 and overlaps
// of 1 or 2 (docs/steady_solver.md, "What fails on a blobs image").
constexpr int kSchwarzBlock = 8, kSchwarzOverlap = 2;
// The doubles its factors take per lattice point at most (all fluid): an
// extended block's points squared over the block's own.
inline double schwarz_factor_values(int dim) {
  double extended = 1, own = 1;
  for (int d = 0; d < dim; ++d) extended *= kSchwarzBlock + 2 * kSchwarzOverlap, own *= kSchwarzBlock;
  return extended * extended / own;
}

struct SteadyOptions {
  double tolerance = 1e-4;         // Solver/Tolerance: on ||F - e (e . F)|| / ||F at rest||
  // Solver/Permeability Tolerance: the last Newton step must also have moved
  // the superficial velocity (so k) by less than this fraction of itself.
  double permeability_tolerance = 1e-3;
  double linear_tolerance = 1e-8;  // Solver/Linear Tolerance: the least a Newton step's solve is asked for
  int max_nonlinear_iterations = 10;
  int max_linear_iterations = 1000;  // per Newton step
  int restart = 30;        // of the outer GMRES (a Newton step's)
  int inner_restart = 30;  // of the inner solves (at most their cap)
  double inner_tolerance = 0;  // Solver/Inner Tolerance; 0: by the dimension (SteadySolver)
  int max_inner_iterations = 100;      // the inner solves' cap to start with
  int raised_inner_iterations = 1600;  // what a stalled linear solve may raise it to (x4 at a time)
  DgPreconditioner dg_preconditioner = DgPreconditioner::Auto;
};

// The doubles the steady solver's vectors take for nv velocity and nq
// density unknowns, with outer and inner Krylov bases of outer_basis and
// inner_basis vectors (solver/Fgmres.hpp): the outer basis, its work
// vector, the step and right-hand side (of the bordered unknowns: one
// more per region of the fluid on process 0, `borders`); one inner basis
// at a time, counted at the velocity block's size (the larger), and its
// work vector; the system's fields (its state,
// residual and scratch, the two partial residuals of G and D alone) and
// the preconditioner's (diag(A)^-1 and LSC's weighed scaling among them).
// SteadySolver reports it with the bases as large as they grew, the memory
// estimate before a run (app/SceneCheck.cpp) with their whole restart.
inline double steady_vector_values(double outer_basis, double inner_basis, double nv, double nq, double borders = 1) {
  const double bordered = nv + nq + borders;
  return (outer_basis + 3) * bordered + (inner_basis + 1) * nv + 9 * (nv + nq) + 3 * nv + 7 * nq;
}

}  // namespace poresph
