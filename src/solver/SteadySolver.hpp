#pragma once
// Steady fixed-particle flow by solving F(y) = 0 (solver/SteadySystem.hpp)
// instead of marching in pseudo-time: Newton's method, each step's linear
// system solved by flexible GMRES with a block preconditioner built from the
// same rate evaluations (docs/steady_solver.md).
//
// The bordered Newton system. SPH continuity is not conservative at walls,
// so the steady state the march reaches keeps a uniform density drift
// lambda: the rates are zero up to d q / dt = lambda. Each Newton step
// solves J u + E lambda = -F, E^T u = 0, with a column of E per region of
// the fluid (solver/FluidRegions.hpp: pockets sealed by solid or by a wall
// thinner than the kernel's reach keep their own mass and drift), each the
// region's density rows, normalised: each region's mean density stays
// where it is. The border unknowns are the last rows of process 0.
//
// The preconditioner is block upper-triangular, [[A, G], [0, S]]^-1, with
// A the velocity block, G the pressure gradient (velocity rows, density
// columns), D continuity (density rows, velocity columns) and S = -D A^-1 G
// approximated by the least-squares commutator (LSC, Elman et al. 2006):
// S^-1 ~ -(DG)^-1 (D Q^-1 A Q^-1 G) (DG)^-1, DG = D Q^-1 G, Q = diag(A)
// with the rows next to walls weighed down (wall_weighted_scaling).
// The inner solves ((DG)^-1, A^-1) are GMRES to a loose tolerance,
// preconditioned by lattice Laplacians (solver/LatticePreconditioner.hpp:
// the wide one for DG, the compact one for A), or for DG by local solves on
// blocks (solver/SchwarzPreconditioner.hpp; Solver/DG Preconditioner, whose
// default switches to them in 2D where the wide one's DG solves stall).
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "core/Math.hpp"
#include "core/MemoryAvailable.hpp"
#include "core/Vec.hpp"
#include "solver/Fgmres.hpp"
#include "solver/FluidRegions.hpp"
#include "solver/LatticePreconditioner.hpp"
#include "solver/SchwarzPreconditioner.hpp"
#include "solver/SteadyOptions.hpp"
#include "solver/SteadySystem.hpp"

namespace poresph {

// What a solve did; summary.json's `solver`.
struct SteadyReport {
  bool converged = false;
  bool interrupted = false;  // a stop signal came: the state is the last Newton iterate
  int nonlinear_iterations = 0;
  long long linear_iterations = 0;
  long long inner_iterations = 0;
  // What the unsettled Newton steps' inner solves were asked for at the
  // end: Solver/Inner Tolerance (by the dimension), or less once a linear
  // solve stalled.
  double inner_tolerance = 0;
  long long rate_evaluations = 0;          // of all the pair terms
  long long partial_rate_evaluations = 0;  // of the pressure or the continuity term alone
  double residual = std::numeric_limits<double>::quiet_NaN();
  // How far the last Newton step moved the superficial velocity, relative
  // (1 after a first step from rest; NaN before any step).
  double last_step_change = std::numeric_limits<double>::quiet_NaN();
  double setup_seconds = 0, solve_seconds = 0;
  double bytes_per_particle = 0;  // what the solver allocates, over the particles (fluid and boundary)
  int fluid_regions = 0;          // the borders: regions of the fluid that keep their own mass
  bool dg_by_blocks = false;      // the DG solves ended preconditioned by local solves on blocks (Schwarz)
  int restart = 0;                // the outer solve's cycles at the end (raised from Solver/Krylov Restart)
};

// Where a solve stands, for the progress line.
struct SteadyProgress {
  int nonlinear_iterations = 0;
  long long linear_iterations = 0;
  double residual = 0;          // of the nonlinear system, relative
  double linear_residual = 0;   // of the Newton step being solved
  double linear_tolerance = 0;  // what that step's linear solve is asked for: it ends at residual x this
  int inner_cap = 0;            // the inner solves' cap now (raised from Solver/Max Inner Iterations)
  int restart = 0;              // the outer solve's cycles now (raised from Solver/Krylov Restart)
  bool dg_by_blocks = false;    // the DG solves preconditioned by local solves on blocks now
};

// Per region of the fluid (FluidRegions::of), the sum of q over its particles, in one pass.
template <class Regions, class Values>
struct RegionSums {
  using value_type = double[];
  unsigned value_count;
  Regions region;
  Values q;
  KOKKOS_INLINE_FUNCTION void operator()(int i, value_type sums) const {
    if (region(i) >= 0) sums[region(i)] += q(i);
  }
};

template <int Dim, class ExecSpace>
class SteadySolver {
 public:
  using System = SteadySystem<Dim, ExecSpace>;
  using View = typename System::View;
  using Clock = std::chrono::steady_clock;
  using RegionSums = poresph::RegionSums<Kokkos::View<int*, typename ExecSpace::memory_space>, View>;
  // The preconditioner's products: near J is enough, at one rate evaluation each.
  static constexpr auto kForward = System::Accuracy::Forward;
  // G and D alone (a pair loop with one term, or the exact linear products)
  // and the velocity block's Stokes part (the viscous and no-slip terms;
  // without convection, which at the Reynolds numbers of pore flow moves
  // the block little: the outer products keep it), each cheaper than the
  // whole rates, and the Stokes part a linear product where G and D are.
  static constexpr auto kGradient = System::RateTerms::Pressure;
  static constexpr auto kDivergence = System::RateTerms::Continuity;
  static constexpr auto kVelocity = System::RateTerms::Viscous;
  static constexpr int kBacktracks = 3;
  // The DG preconditioner's sharpening (solver/LatticeSharpening.hpp): the
  // beta that measured fewest inner iterations, 0 to 8 tried (docs/steady_solver.md).
  static constexpr double kDgSharpening = Dim == 2 ? 2.0 : 4.0;
  // Solver/DG Preconditioner = schwarz: the blocks of SteadyOptions.hpp,
  // each solved exactly with 1e-4 of its largest diagonal entry added to
  // its diagonal. A narrow passage's weak mode that two blocks cut
  // differently is amplified differently by each; the shift bounds that.
  // Of 1e-8, 1e-4 and 1e-3 on three 2D blobs images, 1e-4 took the least
  // time on the largest, the others within 0.5 s (docs/steady_solver.md).
  static constexpr double kSchwarzShift = 1e-4;
  // The inner solves' tolerance where Solver/Inner Tolerance = 0. In 2D
  // DG and its preconditioner differ by at most 50 between the corners of
  // the zone, so a DG solve's residual follows its error, and a looser
  // solve costs the outer solve few iterations: 0.05 took problem III at
  // 0.0025 L in 0.75 of the time of 0.01. In 3D they differ by up to
  // 2,840: a residual of 0.05 leaves weak modes the outer solve needs, and
  // cost the simple cubic and fcc arrays and a blobs image more outer
  // iterations than it saved inner ones (docs/steady_solver.md, "The inner
  // tolerance by the dimension").
  static constexpr double kDefaultInnerTolerance = Dim == 2 ? 5e-2 : 1e-2;
  // The inner tolerance of a Newton step taken only to settle k, and the
  // least a stalled linear solve tightens a looser one to (below).
  static constexpr double kSettlingInnerTolerance = 1e-2;
  static constexpr int kRestartRaise = 4, kMostRestarts = 16;
  // Below this, a velocity row's share of wall drag (wall_weighted_scaling)
  // is the forward difference's rounding (a bulk row's: about 1e-15).
  static constexpr double kDragShareFloor = 1e-6;

  // should_stop: asked after every linear and inner iteration (all processes agree);
  // progress: told after every linear iteration and Newton step.
  SteadySolver(typename System::Sim& sim, const ExecSpace& space, const SteadyOptions& options,
               std::function<bool()> should_stop, std::function<void(const SteadyProgress&)> progress)
      : sim_(sim), space_(space), vectors_{space, sim.communicator()}, options_(options),
        should_stop_(std::move(should_stop)), progress_(std::move(progress)) {}

  // After solve(): LSC's Q^-1 (wall_weighted_scaling) and how many velocity
  // rows a wall's drag reaches (weighed below 1), over all processes.
  const View& lsc_scaling() const { return lsc_scaling_; }
  long long wall_rows() const { return wall_rows_; }

  SteadyReport solve() {
    SteadyReport report;
    const auto start = Clock::now();
    System system(sim_, space_);
    const auto& ops = system.vectors();
    regions_ = find_fluid_regions(sim_);
    const int borders = regions_.count();
    borders_here_ = sim_.communicator().rank() == 0 ? borders : 0;
    const int nv = system.owned() * Dim, nq = system.owned(), n = nv + nq + borders_here_;
    border_weights_ = View("steady_border_weights", borders);
    border_weights_host_ = Kokkos::create_mirror_view(border_weights_);
    report.fluid_regions = borders;
    outer_rows_ = n;
    inner_cap_ = options_.max_inner_iterations;
    restart_ = options_.restart;
    step_inner_tolerance_ = inner_tolerance_asked();
    settling_step_ = false;
    work_residual_q_ = View("steady_residual_q_drift_free", nq);
    setup_preconditioner(system);
    const double reference = rest_residual(system);
    report.setup_seconds = seconds_since(start);

    View rhs("steady_rhs", n), step("steady_step", n);
    auto part = [&](const View& full, int from, int to) {
      return View(Kokkos::subview(full, std::make_pair(from, to)));
    };
    double residual = relative_residual(system, reference), previous_residual = residual, retry_tolerance = 0;
    // Converged: the residual below the tolerance, and k settled, since a
    // residual alone does not hold k where DG has weak modes that carry it:
    // on a 64² image of passages one particle wide, a solve to a residual of
    // 1e-5 left k 27 % from the exact Newton step, its last step having
    // moved k by 42 %; on the shipped scenes the last step moves it by 4e-4
    // or less (docs/steady_solver.md, "k settled").
    double flow_change = std::numeric_limits<double>::quiet_NaN();
    auto converged = [&]() {
      return residual <= options_.tolerance && flow_change < options_.permeability_tolerance;
    };
    SteadyProgress status;
    status.residual = residual;
    status.inner_cap = inner_cap_;
    while (!converged() && report.nonlinear_iterations < options_.max_nonlinear_iterations &&
           std::isfinite(residual)) {
      // rhs = -F (the border rows: 0)
      ops.fill(rhs, 0.0);
      ops.update(-1.0, system.residual_v(), 0.0, part(rhs, 0, nv));
      ops.update(-1.0, system.residual_q(), 0.0, part(rhs, nv, nv + nq));
      ops.fill(step, 0.0);
      KrylovOptions krylov;
      // How far to solve the step (Eisenstat & Walker 1996, choice 2): no
      // further than takes the residual to a tenth of the tolerance were the
      // equations linear, nor than the last step's nonlinear reduction
      // squared says Newton can use; the first step to 1e-3, since Newton's
      // first step from rest misses what the Jacobian at rest lacks by about
      // that: convection, and the density's share of the viscous and pressure
      // terms (1/rho, p/rho^2). On problem III at 0.005 L a first step
      // solved to 5e-5 left a residual of 4.6e-4, and 1.4e-4 without
      // convection: solved further, it only costs iterations.
      const double reduction =
          report.nonlinear_iterations == 0 ? 1e-3 : 0.9 * std::pow(residual / previous_residual, 2);
      krylov.tolerance = std::min(
          0.1, std::max({options_.linear_tolerance, 0.1 * options_.tolerance / residual, reduction}));
      // After a step that lowered nothing: the same step solved a hundred times further.
      if (retry_tolerance > 0) krylov.tolerance = retry_tolerance;
      krylov.max_iterations = options_.max_linear_iterations;
      krylov.restart = restart_;
      krylov.cycle_length = [this] { return restart_; };
      status.linear_tolerance = krylov.tolerance;
      CapWatch watch{0, 1.0, dg_solves_, capped_dg_solves_};
      // A step taken only to settle k (the residual already below the
      // tolerance) that cannot halve its linear residual over a restart
      // cycle with the inner cap as high as it goes ends the solve: on such
      // a pore space the steps crawl (docs/steady_solver.md, "k settled").
      // Its inner solves are asked for 0.01 at most (inner_tolerance).
      const bool settling = residual <= options_.tolerance;
      settling_step_ = settling;
      bool cannot_settle = false;
      krylov.after_iteration = [&](int iterations, double linear_residual) {
        cannot_settle = cannot_settle || (settling && cycle_without_halving(watch, iterations, linear_residual) &&
                                          inner_cap_ >= options_.raised_inner_iterations);
        watch_inner_cap(watch, iterations, linear_residual);
        if (switch_to_schwarz_) build_schwarz(system), switch_to_schwarz_ = false;
        status.linear_iterations = report.linear_iterations + iterations;
        status.linear_residual = linear_residual;
        status.inner_cap = inner_cap_;
        status.restart = restart_;
        status.dg_by_blocks = schwarz_.available();
        if (progress_) progress_(status);
        return cannot_settle || (should_stop_ && should_stop_());
      };
      const auto result = fgmres(
          ops, [&](const View& in, const View& out) { apply_bordered(system, in, out); },
          [&](const View& in, const View& out) { precondition(system, in, out); }, rhs, step, krylov,
          outer_workspace_);
      report.linear_iterations += result.iterations;
      outer_basis_ = std::max(outer_basis_, result.basis_vectors);
      if (result.abandoned && !cannot_settle) {
        report.interrupted = true;
        break;
      }
      // The step, halved while it does not lower the residual (at most
      // kBacktracks times): near the round-off of the differenced Jacobian a
      // full step can add more in modes the residual hardly sees than it
      // removes. A step that lowers nothing is undone, and the solve ends.
      ++report.nonlinear_iterations;
      previous_residual = residual;
      const auto flow_before = sim_.superficial_velocity();
      const View step_v = part(step, 0, nv), step_q = part(step, nv, nv + nq);
      system.move_state(step_v, step_q);
      residual = relative_residual(system, reference);
      for (int halving = 0; halving < kBacktracks && !(residual < previous_residual); ++halving) {
        ops.update(0.0, step, -0.5, step);  // back by half of what was taken
        system.move_state(step_v, step_q);
        residual = relative_residual(system, reference);
        ops.update(0.0, step, -1.0, step);
      }
      const bool stalled = !(residual < previous_residual);
      if (stalled) {
        ops.update(0.0, step, -1.0, step);  // undo what is left of the step
        system.move_state(step_v, step_q);
        residual = relative_residual(system, reference);
      } else {
        // A step cut short (cannot_settle) says less than the full step before it.
        const double change = relative_change(flow_before, sim_.superficial_velocity());
        flow_change = cannot_settle && !std::isnan(flow_change) ? std::max(flow_change, change) : change;
      }
      status.nonlinear_iterations = report.nonlinear_iterations;
      status.residual = residual;
      status.linear_residual = 0;
      if (progress_) progress_(status);
      // A step solved loosely can miss by more than it gains; solved to the
      // linear tolerance and still stalled, the solve is as far as it goes.
      retry_tolerance = 0;
      if (cannot_settle) break;
      if (stalled) {
        if (krylov.tolerance <= options_.linear_tolerance) break;
        retry_tolerance = std::max(options_.linear_tolerance, 1e-2 * krylov.tolerance);
      }
    }
    // The rates in the simulation are of the state it is left in (a checkpoint keeps them).
    if (report.interrupted) system.take_state();
    report.residual = residual;
    report.last_step_change = flow_change;
    report.converged = converged() && !report.interrupted;
    report.inner_iterations = inner_iterations_;
    report.inner_tolerance = step_inner_tolerance_;
    report.dg_by_blocks = schwarz_.available();
    report.restart = restart_;
    report.rate_evaluations = system.rate_evaluations();
    report.partial_rate_evaluations = system.partial_rate_evaluations();
    report.solve_seconds = seconds_since(start) - report.setup_seconds;
    // The vectors with the Krylov bases as large as they grew, the gathered
    // lattices, and the simulation's linear products (their sites and slots).
    const double vectors = steady_vector_values(outer_basis_, inner_basis_, nv, nq, borders_here_);
    const double lattices =
        wide_.values_held() + compact_.values_held() + schwarz_.values_held() + sim_.linear_product_values();
    const double bytes = sim_.communicator().sum(8.0 * (vectors + lattices));
    const double particles = static_cast<double>(sim_.fluid_particles() + sim_.boundary_particles());
    report.bytes_per_particle = bytes / particles;
    return report;
  }

 private:
  // Where a linear solve stood when the inner cap was last looked at.
  struct CapWatch {
    int iteration;
    double residual;
    long long dg_solves, capped_dg_solves;
  };
  // |after - before| / |after|: 0 where both are 0 (no flow), infinite where only after is.
  static double relative_change(const Vec<Dim>& before, const Vec<Dim>& after) {
    const Vec<Dim> moved = after - before;
    const double change = dot(moved, moved), size = dot(after, after);
    if (size == 0) return change == 0 ? 0.0 : std::numeric_limits<double>::infinity();
    return std::sqrt(change / size);
  }
  // What Solver/Inner Tolerance asks of the inner solves (0: by the dimension).
  double inner_tolerance_asked() const {
    return options_.inner_tolerance > 0 ? options_.inner_tolerance : kDefaultInnerTolerance;
  }
  // What the inner solves are asked for now. A step that settles k asks for
  // 0.01 or less: one to 0.05 resolves DG's weak modes too little to show
  // how far k still is. On the 64² image of one-voxel passages ("k
  // settled") the settling steps at 0.05 crawled until one moved k by less
  // than Solver/Permeability Tolerance, 28 % from the exact step, where at
  // 0.01 the solve ends unsettled (exit status 4).
  double inner_tolerance() const {
    return settling_step_ ? std::min(step_inner_tolerance_, kSettlingInnerTolerance) : step_inner_tolerance_;
  }
  // Whether a whole restart cycle of outer iterations has passed since the
  // watch was last set without halving the linear residual.
  bool cycle_without_halving(const CapWatch& watch, int iteration, double residual) const {
    return iteration - watch.iteration >= restart_ && residual > 0.5 * watch.residual;
  }

  // The inner solves made more exact when over a restart cycle of outer
  // iterations the linear residual has not halved, by what ends them: if
  // at least half of the DG solves in the cycle ended at the inner cap, the
  // cap is raised x4 (at most to Solver/Raised Inner Iterations); else an
  // inner tolerance looser than 0.01 is divided by 5 (not below 0.01) for
  // the rest of the solve. On an image whose narrow passages or pockets give
  // DG weak local modes, loose or capped DG solves leave them unresolved and
  // the outer solve stalls (docs/steady_solver.md, "What fails on a blobs
  // image", "The inner tolerance by the dimension": a 96² image at two
  // particles a voxel took 1,018 linear iterations at 0.05, 192 with the
  // rule). Tightening solves that the cap ends only makes them dearer: with
  // both changed on every stall the same image at one particle a voxel took
  // 78,043 inner iterations, 20,202 with the rule. Where the outer solve
  // moves, both stay. Where neither is left, or once the DG solves are on
  // blocks (local-exact already), the outer cycles are lengthened instead
  // (longer_cycles_allowed). FGMRES allows a preconditioner that changes
  // from one iteration to the next; all processes see the same counts.
  void watch_inner_cap(CapWatch& watch, int iteration, double residual) {
    if (iteration - watch.iteration < restart_) return;
    const long long solves = dg_solves_ - watch.dg_solves, capped = capped_dg_solves_ - watch.capped_dg_solves;
    const bool stalled = cycle_without_halving(watch, iteration, residual);
    const bool cap_binds = solves > 0 && 2 * capped >= solves && inner_cap_ < options_.raised_inner_iterations;
    if (stalled && cap_binds && switch_to_schwarz_allowed())
      switch_to_schwarz_ = true;
    else if (stalled && schwarz_.available() && longer_cycles_allowed())
      restart_ *= kRestartRaise;
    else if (stalled && cap_binds)
      inner_cap_ = static_cast<int>(std::min<long long>(options_.raised_inner_iterations, 4LL * inner_cap_));
    else if (stalled && inner_tolerance() > kSettlingInnerTolerance)
      step_inner_tolerance_ = std::max(kSettlingInnerTolerance, 0.2 * step_inner_tolerance_);
    else if (stalled && longer_cycles_allowed())
      restart_ *= kRestartRaise;
    watch = {iteration, residual, dg_solves_, capped_dg_solves_};
  }

  // The outer solve's cycles lengthened x4 (at most to kMostRestarts times
  // Solver/Krylov Restart), where nothing inner is left to make more exact:
  // on an image with passages a particle wide, DG keeps many eigenvalues
  // near zero even with the blocks, the loose DG solves leave them to the
  // outer solve, and each restart throws away what it has learnt of them.
  // A 128² image (porosity 0.5, sigma 2) took 600 s over one Newton step
  // with cycles of 30; with the cycles raised to 480 it converged in 476 s,
  // with cycles of 300 from the start in 278 s (docs/steady_solver.md,
  // "Longer outer cycles"). The longer bases (two vectors an iteration)
  // must fit in a quarter of what every process can still allocate.
  bool longer_cycles_allowed() const {
    if (restart_ * kRestartRaise > kMostRestarts * options_.restart) return false;
    const double added = 8.0 * 2.0 * (kRestartRaise - 1) * restart_ * static_cast<double>(outer_rows_);
    return fits_on_every_process(added, 0.25);
  }

  // Solver/DG Preconditioner = auto in 2D, before the switch: a stall with
  // capped DG solves switches the DG solves to local solves on blocks
  // instead of raising their cap (docs/steady_solver.md, "Local solves for
  // DG"), where the blocks' factors fit in half of what every process can
  // still allocate (at most schwarz_factor_values a fluid particle; the
  // memory check before the run counts them for 'schwarz' only).
  bool switch_to_schwarz_allowed() const {
    if (Dim != 2 || options_.dg_preconditioner != DgPreconditioner::Auto || schwarz_.available()) return false;
    const double factors =
        8.0 * schwarz_factor_values(Dim) * static_cast<double>(sim_.fluid_particles()) / sim_.communicator().size();
    return fits_on_every_process(factors, 0.5);
  }

  // Whether `bytes` more fit in `share` of what every process can still
  // allocate (all processes get the same answer).
  bool fits_on_every_process(double bytes, double share) const {
    return !sim_.communicator().any(!(bytes < share * memory_available_bytes()));
  }

  static double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

  // E^T q: per region, the sum of q over its density rows over sqrt(its size).
  std::vector<double> border_dot(const View& q) const {
    std::vector<double> sums(regions_.count(), 0.0);
    if (sums.empty()) return sums;
    static const std::string label = "poresph::steady::border_dot";
    if (sums.size() == 1) {  // one region, the usual case: a scalar sum, cheaper than an array's
      const auto region = regions_.of;
      Kokkos::parallel_reduce(
          label, Kokkos::RangePolicy<ExecSpace>(space_, 0, q.extent(0)),
          KOKKOS_LAMBDA(int i, double& sum) { sum += region(i) >= 0 ? q(i) : 0.0; }, sums[0]);
    } else {
      const RegionSums of{static_cast<unsigned>(sums.size()), regions_.of, q};
      Kokkos::parallel_reduce(label, Kokkos::RangePolicy<ExecSpace>(space_, 0, q.extent(0)), of, sums.data());
    }
    sim_.communicator().sum(sums.data(), static_cast<int>(sums.size()));
    for (size_t r = 0; r < sums.size(); ++r) sums[r] /= std::sqrt(regions_.sizes[r]);
    return sums;
  }
  // q += sign E alpha
  void add_border(const std::vector<double>& alpha, const View& q, double sign = 1.0) const {
    if (alpha.empty()) return;
    for (size_t r = 0; r < alpha.size(); ++r) border_weights_host_(r) = sign * alpha[r] / std::sqrt(regions_.sizes[r]);
    Kokkos::deep_copy(space_, border_weights_, border_weights_host_);
    const auto region = regions_.of;
    const auto weight = border_weights_;
    static const std::string label = "poresph::steady::add_border";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, q.extent(0)), KOKKOS_LAMBDA(int i) {
          if (region(i) >= 0) q(i) += weight(region(i));
        });
    space_.fence();
  }
  // q -= E (E^T q): each region's mean out. Returns E^T q.
  std::vector<double> remove_border(const View& q) const {
    const auto removed = border_dot(q);
    add_border(removed, q, -1.0);
    return removed;
  }
  // The border unknowns lambda, held by process 0 in the last rows.
  std::vector<double> read_border(const View& full) const {
    std::vector<double> values(regions_.count(), 0.0);
    if (borders_here_ > 0) {
      const auto tail = Kokkos::subview(full, std::make_pair(full.extent(0) - borders_here_, full.extent(0)));
      const auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tail);
      for (int r = 0; r < borders_here_; ++r) values[r] = host(r);
    }
    if (!values.empty()) sim_.communicator().sum(values.data(), static_cast<int>(values.size()));
    return values;
  }
  void write_border(const View& full, const std::vector<double>& values) const {
    if (borders_here_ == 0) return;
    const auto tail = Kokkos::subview(full, std::make_pair(full.extent(0) - borders_here_, full.extent(0)));
    const auto host = Kokkos::create_mirror_view(tail);
    for (int r = 0; r < borders_here_; ++r) host(r) = values[r];
    Kokkos::deep_copy(tail, host);
  }

  // ||F - E (E^T F)|| over the same at rest (v = 0, rho = rho0): the drifts removed.
  double relative_residual(const System& system, double reference) const {
    return drift_free_norm(system) / reference;
  }
  // ||F - E (E^T F)||, the drifts taken out before squaring: a drift far
  // larger than what is left would otherwise cancel it in |F|^2 - drift^2.
  double drift_free_norm(const System& system) const {
    const auto& ops = system.vectors();
    const View q = work_residual_q_;
    ops.copy(system.residual_q(), q);
    remove_border(q);
    return std::sqrt(ops.dot(system.residual_v(), system.residual_v()) + ops.dot(q, q));
  }

  // The residual's size at rest, what "relative" is relative to: the same
  // for a cold start, a warm start and a restart.
  double rest_residual(System& system) {
    const auto& ops = system.vectors();
    const int nv = system.owned() * Dim, nq = system.owned();
    View dv("steady_to_rest_v", nv), dq("steady_to_rest_q", nq);
    ops.update(-1.0, velocity_of(system), 0.0, dv);
    const double rest_q = sim_.derived().sound_speed;  // (c / rho0) rho0
    const auto base_q = density_of(system);
    const auto fluid = system.fluid_mask();
    static const std::string label = "poresph::steady::to_rest";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, nq),
        KOKKOS_LAMBDA(int i) { dq(i) = fluid(i) * (rest_q - base_q(i)); });
    space_.fence();
    system.move_state(dv, dq);
    const double norm = drift_free_norm(system);
    ops.update(-1.0, dv, 0.0, dv);
    ops.update(-1.0, dq, 0.0, dq);
    system.move_state(dv, dq);
    return norm > 0 ? norm : 1.0;
  }
  View velocity_of(System& system) const {
    const auto P = sim_.particles();
    View v("steady_velocity", system.owned() * Dim);
    static const std::string label = "poresph::steady::velocity_of";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, system.owned()), KOKKOS_LAMBDA(int i) {
          for (int d = 0; d < Dim; ++d) v(i * Dim + d) = P.v(i, d);
        });
    space_.fence();
    return v;
  }
  View density_of(System& system) const {
    const auto P = sim_.particles();
    const double to_q = sim_.derived().sound_speed / sim_.scene().density;
    View q("steady_density", system.owned());
    static const std::string label = "poresph::steady::density_of";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, system.owned()),
        KOKKOS_LAMBDA(int i) { q(i) = to_q * P.rho(i); });
    space_.fence();
    return q;
  }

  // out = [[J, e], [e^T, 0]] in
  void apply_bordered(System& system, const View& in, const View& out) {
    const int nv = system.owned() * Dim, nq = system.owned();
    const View in_v(Kokkos::subview(in, std::make_pair(0, nv))), in_q(Kokkos::subview(in, std::make_pair(nv, nv + nq)));
    const View out_v(Kokkos::subview(out, std::make_pair(0, nv))),
        out_q(Kokkos::subview(out, std::make_pair(nv, nv + nq)));
    system.apply(&in_v, &in_q, out_v, out_q);
    add_border(read_border(in), out_q);
    write_border(out, border_dot(in_q));
  }

  void setup_preconditioner(System& system) {
    // Local solves from an earlier solve() took that solve's system: afresh
    // for this one ('schwarz'), or once this one stalls ('auto').
    schwarz_ = SchwarzPreconditioner<Dim, ExecSpace>();
    const int nv = system.owned() * Dim, nq = system.owned();
    diagonal_inverse_ = system.velocity_diagonal(kForward, kVelocity);
    const auto inverse = diagonal_inverse_;
    static const std::string label = "poresph::steady::invert_diagonal";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, nv),
        KOKKOS_LAMBDA(int i) { inverse(i) = inverse(i) != 0 ? 1.0 / inverse(i) : 0.0; });
    space_.fence();
    lsc_scaling_ = wall_weighted_scaling(system);
    work_v_ = View("steady_work_v", nv), work_v2_ = View("steady_work_v2", nv), work_v3_ = View("steady_work_v3", nv);
    work_q_ = View("steady_work_q", nq), work_q2_ = View("steady_work_q2", nq);
    work_q_component_in_ = View("steady_component_in", nq), work_q_component_out_ = View("steady_component_out", nq);
    // One set of inner bases for the density and velocity blocks' solves,
    // which never run at once: the velocity block's length.
    inner_workspace_ = KrylovWorkspace<ExecSpace>(nv);
    // The size of DG (a few power iterations from a smooth start), for the
    // shift that makes it invertible (below).
    const auto& ops = system.vectors();
    View x("steady_power", nq), y("steady_power_y", nq);
    const auto Px = sim_.particles().x;
    const auto fluid = system.fluid_mask();
    const double length = sim_.scene().cell_size[0];
    static const std::string label_start = "poresph::steady::power_start";
    Kokkos::parallel_for(
        label_start, Kokkos::RangePolicy<ExecSpace>(space_, 0, nq),
        KOKKOS_LAMBDA(int i) { x(i) = fluid(i) * (1.0 + math::cos(6.283185307179586 * 3 * Px(i, 0) / length)); });
    space_.fence();
    double estimate = 0;
    for (int k = 0; k < 8; ++k) {
      const double norm = ops.norm(x);
      if (!(norm > 0)) break;
      ops.update(0.0, x, 1.0 / norm, x);
      apply_dg(system, x, y);
      estimate = ops.dot(x, y);
      ops.copy(y, x);
    }
    // DG has each region's constant as a right null vector and left ones that
    // are not constant, so DG p = r has a solution only for r in its range.
    // The DG solves work on vectors whose region means are zero (solve_dg),
    // where the right null vectors are gone; a shift far below the smallest
    // nonzero eigenvalue keeps DG + s I invertible whatever is left.
    dg_shift_ = 1e-10 * estimate;

    // The lattice Laplacians that precondition the inner solves, each scaled
    // to its operator on a smooth mode s: c = s . L^-1 (K s) / s . s.
    const auto lattice = lattice_points();
    const double dx = sim_.scene().particle_spacing;
    if (options_.dg_preconditioner == DgPreconditioner::Schwarz) {
      build_schwarz(system);
    } else {
      wide_ = LatticePreconditioner<Dim, ExecSpace>(space_, sim_.communicator(), Px, fluid, nq, lattice, dx, 2);
      wide_.set_sharpening(kDgSharpening);
    }
    compact_ = LatticePreconditioner<Dim, ExecSpace>(space_, sim_.communicator(), Px, fluid, nq, lattice, dx, 1);
    Kokkos::parallel_for(
        label_start, Kokkos::RangePolicy<ExecSpace>(space_, 0, nq),
        KOKKOS_LAMBDA(int i) { x(i) = fluid(i) * math::cos(6.283185307179586 * Px(i, 0) / length); });
    space_.fence();
    const double smooth = ops.dot(x, x);
    if (compact_.available() && smooth > 0) {
      // The velocity block on the smooth mode in x (component 0).
      View sv("steady_smooth_v", nv);
      to_component(x, sv, 0);
      system.apply(&sv, nullptr, work_v_, View(), kForward, kVelocity);
      from_component(work_v_, y, 0);
      compact_.apply(y, work_q_);
      compact_scale_ = ops.dot(x, work_q_) / smooth;
    }
    if (wide_.available()) measure_pattern_weights(system, x, y);
  }

  // Points per axis of the cell's lattice at the particle spacing.
  std::array<int, Dim> lattice_points() const {
    std::array<int, Dim> lattice;
    const double dx = sim_.scene().particle_spacing;
    for (int d = 0; d < Dim; ++d) lattice[d] = static_cast<int>(std::lround(sim_.scene().cell_size[d] / dx));
    return lattice;
  }

  // Restricted additive Schwarz for the DG solves (Solver/DG Preconditioner
  // = schwarz, or auto once the lattice cycle's DG solves stall). DG couples
  // points through two pair loops, each reaching twice the kernel's support
  // (3h) where a wall's pressure or velocity is extrapolated from the fluid.
  void build_schwarz(System& system) {
    const int reach = static_cast<int>(std::ceil(12.0 * sim_.scene().smoothing_length_ratio - 1e-9));
    schwarz_ = SchwarzPreconditioner<Dim, ExecSpace>(
        space_, sim_.communicator(), sim_.particles().x, system.fluid_mask(), system.owned(), lattice_points(),
        sim_.scene().particle_spacing, kSchwarzBlock, kSchwarzOverlap, reach, kSchwarzShift,
        [this, &system](const View& in, const View& out) { apply_dg(system, in, out); });
    wide_ = LatticePreconditioner<Dim, ExecSpace>();  // replaced, where it was built
  }

  // LSC's Q^-1: diag(A)^-1 with each velocity row weighed by 1 / (1 + t_i),
  // t_i = |(A u)_i| / |A_ii| for u a uniform flow along the row's component:
  // the share of the row's diagonal that is wall drag (0 in the bulk, where
  // a uniform flow feels nothing). LSC rests on a commutator that holds in
  // the bulk and fails at Dirichlet walls (Elman & Tuminaro 2009), so the
  // rows next to walls are fitted less. Against diag(A) alone (and fixed
  // weights on the rows past a threshold, docs/steady_solver.md): 44 % fewer
  // inner iterations on problem III at 0.0025 L, 8 % on a face-centred
  // pack; on the sparse simple cubic array 22 % more at 20 a side, 7 % fewer
  // at 40. One product of A per component.
  View wall_weighted_scaling(System& system) {
    const int nv = system.owned() * Dim, nq = system.owned();
    View scaling("steady_lsc_scaling", nv), uniform("steady_uniform_v", nv), response("steady_uniform_response", nv),
        response_q("steady_uniform_response_q", nq);
    Kokkos::deep_copy(space_, scaling, diagonal_inverse_);
    const auto fluid = system.fluid_mask();
    const auto inverse = diagonal_inverse_;
    wall_rows_ = 0;
    for (int component = 0; component < Dim; ++component) {
      static const std::string label_uniform = "poresph::steady::uniform_flow";
      Kokkos::parallel_for(
          label_uniform, Kokkos::RangePolicy<ExecSpace>(space_, 0, nq), KOKKOS_LAMBDA(int i) {
            for (int d = 0; d < Dim; ++d) uniform(i * Dim + d) = d == component ? fluid(i) : 0.0;
          });
      space_.fence();
      system.apply(&uniform, nullptr, response, response_q, kForward, kVelocity);
      long long touched = 0;
      static const std::string label_weigh = "poresph::steady::weigh_wall_rows";
      Kokkos::parallel_reduce(
          label_weigh, Kokkos::RangePolicy<ExecSpace>(space_, 0, nq),
          KOKKOS_LAMBDA(int i, long long& count) {
            const int row = i * Dim + component;
            const double drag_share = math::fabs(response(row) * inverse(row));
            if (fluid(i) == 0 || !(drag_share > kDragShareFloor)) return;
            scaling(row) /= 1.0 + drag_share;
            ++count;
          },
          touched);
      wall_rows_ += touched;
    }
    wall_rows_ = sim_.communicator().sum(wall_rows_);
    return scaling;
  }

  // DG against the wide Laplacian L on each sign pattern m of the lattice
  // times a smooth mode (a cosine along each axis in turn; the geometric mean
  // over the axes, since DG near a pattern is anisotropic):
  // c_m = x . L^-1 DG x / x . x. The SPH gradient is weaker on the patterns
  // than on smooth fields (at the corner of the Brillouin zone by about 14
  // in 2D, 250 in 3D; docs/steady_solver.md), L is not, so L alone
  // overestimates DG there by c_0 / c_m (measured: 140 and 1,600 at the
  // corner). The preconditioner's coarse correction of pattern m is weighed
  // by (c_0 / c_m)^(1/2): the power that measured fewest inner iterations in
  // 2D and 3D (0.25 to 1 tried); the full ratio over-corrects the modes near
  // the coarse level's cut-off. wide_scale_ = c_0 as before. A pattern that
  // cannot be measured (no fluid on it) keeps the weight 1.
  void measure_pattern_weights(System& system, const View& x, const View& y) {
    const auto& ops = system.vectors();
    const auto Px = sim_.particles().x;
    const auto fluid = system.fluid_mask();
    const double dx = sim_.scene().particle_spacing;
    Kokkos::Array<int, Dim> bit;
    for (int d = 0; d < Dim; ++d) bit[d] = wide_.pattern_bit(d);
    std::vector<double> sizes(wide_.patterns(), 0.0);
    for (int m = 0; m < wide_.patterns(); ++m) {
      int measured = 0;
      for (int axis = 0; axis < Dim; ++axis) {
        const double length = sim_.scene().cell_size[axis];
        static const std::string label = "poresph::steady::pattern_mode";
        Kokkos::parallel_for(
            label, Kokkos::RangePolicy<ExecSpace>(space_, 0, system.owned()), KOKKOS_LAMBDA(int i) {
              int parity = 0;
              for (int d = 0; d < Dim; ++d)
                if (bit[d] >= 0 && ((m >> bit[d]) & 1)) parity += static_cast<int>(math::floor(Px(i, d) / dx));
              const double sign = parity % 2 == 0 ? 1.0 : -1.0;
              x(i) = fluid(i) * sign * math::cos(6.283185307179586 * Px(i, axis) / length);
            });
        space_.fence();
        const double norm = ops.dot(x, x);
        if (!(norm > 0)) continue;
        apply_dg(system, x, y);
        wide_.apply(y, work_q_);
        const double size = ops.dot(x, work_q_) / norm;
        if (!(size > 0)) continue;
        sizes[m] += std::log(size);
        ++measured;
      }
      sizes[m] = measured > 0 ? std::exp(sizes[m] / measured) : 0.0;
    }
    if (!(sizes[0] > 0)) return;
    std::vector<double> weights(sizes.size());
    for (size_t m = 0; m < sizes.size(); ++m) weights[m] = std::sqrt(sizes[0] / (sizes[m] > 0 ? sizes[m] : sizes[0]));
    wide_.set_pattern_weights(weights);
    wide_scale_ = sizes[0];
  }

  // Component d of a velocity vector (i * Dim + d) as a scalar one, and back.
  void from_component(const View& v, const View& s, int d) const {
    static const std::string label = "poresph::steady::from_component";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, s.extent(0)), KOKKOS_LAMBDA(int i) { s(i) = v(i * Dim + d); });
    space_.fence();
  }
  void to_component(const View& s, const View& v, int d) const {
    static const std::string label = "poresph::steady::to_component";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, s.extent(0)), KOKKOS_LAMBDA(int i) { v(i * Dim + d) = s(i); });
    space_.fence();
  }

  // The inner solves' preconditioners: the wide lattice Laplacian for DG,
  // the compact one per component for the velocity block (none and Jacobi
  // if a scale could not be measured: no fluid on this smooth mode).
  void precondition_dg(const View& in, const View& out) const {
    if (schwarz_.available()) {
      schwarz_.apply(in, out);
      return;
    }
    if (!wide_.available() || wide_scale_ == 0) {
      Kokkos::deep_copy(space_, out, in);
      space_.fence();
      return;
    }
    wide_.apply(in, out);
    vectors_.update(0.0, out, 1.0 / wide_scale_, out);
  }
  void precondition_velocity(const View& in, const View& out) const {
    if (!compact_.available() || compact_scale_ == 0) {
      Kokkos::deep_copy(space_, out, in);
      space_.fence();
      multiply(diagonal_inverse_, out);
      return;
    }
    for (int d = 0; d < Dim; ++d) {
      from_component(in, work_q_component_in_, d);
      compact_.apply(work_q_component_in_, work_q_component_out_);
      to_component(work_q_component_out_, out, d);
    }
    vectors_.update(0.0, out, 1.0 / compact_scale_, out);
  }

  // out = D Q^-1 G q
  void apply_dg(System& system, const View& q, const View& out) {
    system.apply(nullptr, &q, work_v_, View(), kForward, kGradient);
    multiply(lsc_scaling_, work_v_);
    system.apply(&work_v_, nullptr, View(), out, kForward, kDivergence);
  }
  // out = D Q^-1 A Q^-1 G q
  void apply_dag(System& system, const View& q, const View& out) {
    system.apply(nullptr, &q, work_v_, View(), kForward, kGradient);
    multiply(lsc_scaling_, work_v_);
    system.apply(&work_v_, nullptr, work_v2_, View(), kForward, kVelocity);
    multiply(lsc_scaling_, work_v2_);
    system.apply(&work_v2_, nullptr, View(), out, kForward, kDivergence);
  }
  void multiply(const View& factor, const View& x) const {
    static const std::string label = "poresph::steady::multiply";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, x.extent(0)), KOKKOS_LAMBDA(int i) { x(i) *= factor(i); });
    space_.fence();
  }

  // What the preconditioner's inner solves are asked for.
  KrylovOptions inner_krylov() const {
    KrylovOptions krylov;
    krylov.tolerance = inner_tolerance();
    krylov.max_iterations = inner_cap_;
    krylov.restart = std::min(options_.inner_restart, inner_cap_);
    // A stop signal is answered within an inner iteration, not at the end of
    // the outer one: an outer iteration of a million particles takes tens of
    // seconds, and mpirun kills the ranks about 2 s after it forwards a
    // SIGTERM. An abandoned inner solve leaves a rough preconditioned vector,
    // and the outer solve then stops at its own check.
    krylov.after_iteration = [this](int, double) { return should_stop_ && should_stop_(); };
    return krylov;
  }

  // p ~ (DG)^-1 r: GMRES on DG + s I to the inner tolerance, kept to the
  // vectors whose mean on each region of the fluid is zero (r, each product
  // and each preconditioned vector have theirs removed): a region's level
  // is the border's to set, and a pocket that a wall's pressure couples
  // weakly to the flow gives DG a near-null mode there that the solve need
  // not resolve. Against removing the means after the solve only: the DG
  // solves of the square array c = 0.2 took 1,027 inner iterations instead
  // of 2,493; a 96² image with a pocket behind a thin wall 46.6 s instead
  // of 76.6 (docs/steady_solver.md).
  void solve_dg(System& system, const View& r, const View& p) {
    const auto& ops = system.vectors();
    const KrylovOptions krylov = inner_krylov();
    ops.fill(p, 0.0);
    const double shift = dg_shift_;
    remove_border(r);
    const auto result = fgmres(
        ops,
        [&](const View& in, const View& out) {
          apply_dg(system, in, out);
          ops.update(shift, in, 1.0, out);
          remove_border(out);
        },
        [&](const View& in, const View& out) {
          precondition_dg(in, out);
          remove_border(out);
        },
        r, p, krylov, inner_workspace_);
    inner_iterations_ += result.iterations;
    ++dg_solves_;
    if (!result.converged && result.iterations >= inner_cap_) ++capped_dg_solves_;
    inner_basis_ = std::max(inner_basis_, result.basis_vectors);
    // p, a sum of preconditioned vectors, has zero region means already.
  }

  // v ~ A^-1 r: GMRES with the compact lattice Laplacian to the inner tolerance.
  void solve_velocity(System& system, const View& r, const View& v) {
    const auto& ops = system.vectors();
    const KrylovOptions krylov = inner_krylov();
    ops.fill(v, 0.0);
    const auto result = fgmres(
        ops, [&](const View& in, const View& out) { system.apply(&in, nullptr, out, View(), kForward, kVelocity); },
        [&](const View& in, const View& out) { precondition_velocity(in, out); }, r, v, krylov, inner_workspace_);
    inner_iterations_ += result.iterations;
    inner_basis_ = std::max(inner_basis_, result.basis_vectors);
  }

  // out = P^-1 in, block upper-triangular with LSC (see the top of the file).
  void precondition(System& system, const View& in, const View& out) {
    const auto& ops = system.vectors();
    const int nv = system.owned() * Dim, nq = system.owned();
    const View in_v(Kokkos::subview(in, std::make_pair(0, nv))), in_q(Kokkos::subview(in, std::make_pair(nv, nv + nq)));
    const View out_v(Kokkos::subview(out, std::make_pair(0, nv))),
        out_q(Kokkos::subview(out, std::make_pair(nv, nv + nq)));
    // The uniform part of each region's density residual is its drift's.
    ops.copy(in_q, work_q_);
    const auto drift = remove_border(work_q_);
    // p = -(DG)^-1 (DAG) (DG)^-1 r_q
    solve_dg(system, work_q_, work_q2_);
    apply_dag(system, work_q2_, work_q_);
    solve_dg(system, work_q_, out_q);
    ops.update(0.0, out_q, -1.0, out_q);
    // Each region's mean density change is its border row's.
    add_border(read_border(in), out_q);
    // v = A^-1 (r_v - G p)
    system.apply(nullptr, &out_q, work_v2_, View(), kForward, kGradient);
    ops.copy(in_v, work_v3_);
    ops.update(-1.0, work_v2_, 1.0, work_v3_);
    solve_velocity(system, work_v3_, out_v);
    write_border(out, drift);
  }

  typename System::Sim& sim_;
  ExecSpace space_;
  KrylovVectors<ExecSpace> vectors_;  // for the preconditioners, which have no system at hand
  SteadyOptions options_;
  std::function<bool()> should_stop_;
  std::function<void(const SteadyProgress&)> progress_;
  FluidRegions<typename ExecSpace::memory_space> regions_;
  int borders_here_ = 0;  // border rows on this process: all on process 0
  View border_weights_;   // add_border's, per region
  typename View::HostMirror border_weights_host_;
  double dg_shift_ = 0;
  LatticePreconditioner<Dim, ExecSpace> wide_, compact_;
  SchwarzPreconditioner<Dim, ExecSpace> schwarz_;  // DG's, with Solver/DG Preconditioner = schwarz (or auto, switched)
  bool switch_to_schwarz_ = false;                 // asked for by watch_inner_cap, done after the iteration
  double wide_scale_ = 0, compact_scale_ = 0;
  long long inner_iterations_ = 0;
  int inner_cap_ = 0;                               // what an inner solve may take now
  int restart_ = 0;                                 // the outer solve's cycles now
  long long outer_rows_ = 0;                        // of the outer solve's vectors on this process
  double step_inner_tolerance_ = 0;  // what inner solves are asked for in a step that does not settle k
  bool settling_step_ = false;       // whether the Newton step being solved settles k
  long long dg_solves_ = 0, capped_dg_solves_ = 0;  // DG solves, and those that ended at the cap
  int outer_basis_ = 0, inner_basis_ = 0;  // the most vectors a solve's bases held
  KrylovWorkspace<ExecSpace> outer_workspace_, inner_workspace_;  // bases kept from solve to solve
  long long wall_rows_ = 0;  // velocity rows a wall's drag reaches, all processes
  View diagonal_inverse_, lsc_scaling_, work_v_, work_v2_, work_v3_, work_q_, work_q2_, work_q_component_in_,
      work_q_component_out_, work_residual_q_;
};

}  // namespace poresph
