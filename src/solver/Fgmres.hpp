#pragma once
// Flexible GMRES (Saad 1993) on distributed vectors: each process holds its
// own rows in a Kokkos View, and inner products are summed over processes.
// Flexible, because the steady solver's preconditioner is itself a set of
// inexact inner solves that change from one application to the next.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/BlockedSum.hpp"
#include "parallel/Communicator.hpp"

namespace poresph {

// The vector operations a Krylov method needs, as labelled kernels, with the
// inner products summed over the processes of `comm`.
template <class ExecSpace>
struct KrylovVectors {
  using View = Kokkos::View<double*, typename ExecSpace::memory_space>;
  ExecSpace space;
  Communicator comm;

  double dot(const View& a, const View& b) const {
    static const std::string label = "poresph::krylov::dot";
    const double local = blocked_sum(space, label, a.extent(0), KOKKOS_LAMBDA(long long i) { return a(i) * b(i); });
    return comm.sum(local);
  }
  double norm(const View& a) const { return std::sqrt(dot(a, a)); }
  // y += alpha x, then y . z (z may be y), in one pass.
  double update_dot(double alpha, const View& x, const View& y, const View& z) const {
    static const std::string label = "poresph::krylov::update_dot";
    const double local = blocked_sum(
        space, label, y.extent(0), KOKKOS_LAMBDA(long long i) {
          const double updated = y(i) + alpha * x(i);
          y(i) = updated;
          return updated * z(i);
        });
    return comm.sum(local);
  }
  // y = alpha x + beta y; with beta = 0, y is not read (as in BLAS), so
  // that a vector kept from an earlier solve never carries its old values in.
  void update(double alpha, const View& x, double beta, const View& y) const {
    static const std::string label = "poresph::krylov::update";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space, 0, y.extent(0)),
        KOKKOS_LAMBDA(int i) { y(i) = beta == 0 ? alpha * x(i) : alpha * x(i) + beta * y(i); });
    space.fence();
  }
  void fill(const View& y, double value) const {
    Kokkos::deep_copy(space, y, value);
    space.fence();
  }
  void copy(const View& from, const View& to) const {
    Kokkos::deep_copy(space, to, from);
    space.fence();
  }
};

struct KrylovOptions {
  double tolerance = 1e-6;  // on ||b - A x|| / ||b||
  int max_iterations = 500;
  int restart = 30;
  // If set, the length of each cycle as it begins, in place of restart: a
  // caller may lengthen the cycles of a solve that stalls.
  std::function<int()> cycle_length;
  // Called after every iteration with the iteration count and relative
  // residual; returning true abandons the solve (a stop signal).
  std::function<bool(int, double)> after_iteration;
};

struct KrylovResult {
  int iterations = 0;
  double relative_residual = 0;
  bool converged = false;
  bool abandoned = false;
  int basis_vectors = 0;  // of V and Z in the workspace at the end: what the solves held beyond w
};

// The bases V and Z and the work vector w of fgmres, kept from one solve to
// the next: the steady solver's inner solves run three times per outer
// iteration, and bases allocated afresh for each cost a zero fill and the
// page faults of new memory every time (15 % of problem III's solve at
// 0.005 L). A solve of n unknowns uses the first n entries of each vector;
// the vectors are as long as the longest solve asked for so far.
template <class ExecSpace>
class KrylovWorkspace {
 public:
  using View = typename KrylovVectors<ExecSpace>::View;

  // length: the least length of a vector made, so that solves of several
  // sizes (the steady solver's density and velocity blocks) share one set.
  explicit KrylovWorkspace(size_t length = 0) : length_(length) {}

  // Vector j of V (or Z), n long; those beyond the last one asked for are made.
  View basis(bool z, int j, size_t n) { return take(z ? Z_ : V_, j, n, z ? "fgmres_Z" : "fgmres_V"); }
  View work(size_t n) { return take(w_, 0, n, "fgmres_w"); }
  // V and Z vectors held (for the memory report).
  int basis_vectors() const { return static_cast<int>(V_.size() + Z_.size()); }

 private:
  View take(std::vector<View>& vectors, int j, size_t n, const char* label) {
    while (static_cast<int>(vectors.size()) <= j) vectors.push_back(View(std::string(label), std::max(n, length_)));
    if (vectors[j].extent(0) < n) vectors[j] = View(std::string(label), std::max(n, length_));
    return View(Kokkos::subview(vectors[j], std::make_pair(size_t(0), n)));
  }
  size_t length_ = 0;
  std::vector<View> V_, Z_, w_;
};

// Solves A x = b from the x given (right-preconditioned: A M z = b, x = M z).
// apply(in, out): out = A in; precondition(in, out): out = M in. Neither may
// keep references to its arguments.
template <class ExecSpace, class Apply, class Precondition>
KrylovResult fgmres(const KrylovVectors<ExecSpace>& ops, Apply&& apply, Precondition&& precondition,
                    const typename KrylovVectors<ExecSpace>::View& b, const typename KrylovVectors<ExecSpace>::View& x,
                    const KrylovOptions& options, KrylovWorkspace<ExecSpace>& workspace) {
  using View = typename KrylovVectors<ExecSpace>::View;
  KrylovResult result;
  const size_t n = b.extent(0);
  const double norm_b = ops.norm(b);
  if (norm_b == 0) {
    ops.fill(x, 0.0);
    result.converged = true;
    return result;
  }
  int m = options.restart;
  // The bases V (m + 1 vectors) and Z (m) grow as the iterations reach
  // them: a solve that converges in k < m iterations holds 2 k + 1 vectors,
  // not 2 m + 1 (the steady solver's Newton steps take about 12 of a restart
  // of 30, whose bases with the inner solves' took 3.4 kB of the 4.1 kB a
  // particle of the simple cubic array at 40 per side).
  std::vector<View> V, Z;
  auto basis = [&](std::vector<View>& vectors, bool z, int j) -> const View& {
    while (static_cast<int>(vectors.size()) <= j)
      vectors.push_back(workspace.basis(z, static_cast<int>(vectors.size()), n));
    return vectors[j];
  };
  const View w = workspace.work(n);
  std::vector<double> H, g, cs, sn;
  auto h = [&](int i, int j) -> double& { return H[i * m + j]; };

  while (true) {
    if (options.cycle_length) m = std::max(1, options.cycle_length());
    H.resize((m + 1) * m), g.resize(m + 1), cs.resize(m), sn.resize(m);
    // r = b - A x
    apply(x, w);
    ops.copy(b, basis(V, false, 0));
    ops.update(-1.0, w, 1.0, V[0]);
    const double beta = ops.norm(V[0]);
    result.relative_residual = beta / norm_b;
    result.basis_vectors = workspace.basis_vectors();
    if (result.relative_residual <= options.tolerance) {
      result.converged = true;
      return result;
    }
    if (result.iterations >= options.max_iterations) return result;
    ops.update(0.0, V[0], 1.0 / beta, V[0]);
    std::fill(g.begin(), g.end(), 0.0);
    g[0] = beta;
    int k = 0;
    for (; k < m && result.iterations < options.max_iterations; ++k) {
      precondition(V[k], basis(Z, true, k));
      apply(Z[k], w);
      // Modified Gram-Schmidt, each subtraction in one pass with the next
      // inner product (the same arithmetic as the two passes, w read once
      // less).
      h(0, k) = ops.dot(w, V[0]);
      for (int i = 0; i < k; ++i) h(i + 1, k) = ops.update_dot(-h(i, k), V[i], w, V[i + 1]);
      h(k + 1, k) = std::sqrt(ops.update_dot(-h(k, k), V[k], w, w));
      if (h(k + 1, k) > 0) ops.update(1.0 / h(k + 1, k), w, 0.0, basis(V, false, k + 1));
      for (int i = 0; i < k; ++i) {
        const double a = h(i, k), c = h(i + 1, k);
        h(i, k) = cs[i] * a + sn[i] * c;
        h(i + 1, k) = -sn[i] * a + cs[i] * c;
      }
      const double d = std::hypot(h(k, k), h(k + 1, k));
      cs[k] = d > 0 ? h(k, k) / d : 1.0;
      sn[k] = d > 0 ? h(k + 1, k) / d : 0.0;
      h(k, k) = d;
      h(k + 1, k) = 0;
      g[k + 1] = -sn[k] * g[k];
      g[k] = cs[k] * g[k];
      ++result.iterations;
      result.relative_residual = std::abs(g[k + 1]) / norm_b;
      const bool breakdown = d == 0;
      if (options.after_iteration && options.after_iteration(result.iterations, result.relative_residual)) {
        result.abandoned = true;
        ++k;
        break;
      }
      if (result.relative_residual <= options.tolerance || breakdown) {
        ++k;
        break;
      }
    }
    // x += Z y, H y = g (upper triangular, k columns)
    std::vector<double> y(k);
    for (int i = k - 1; i >= 0; --i) {
      double s = g[i];
      for (int j = i + 1; j < k; ++j) s -= h(i, j) * y[j];
      y[i] = h(i, i) != 0 ? s / h(i, i) : 0.0;
    }
    for (int i = 0; i < k; ++i) ops.update(y[i], Z[i], 1.0, x);
    result.basis_vectors = workspace.basis_vectors();
    if (result.abandoned) return result;
    // The next cycle starts from the true residual, which also settles convergence.
  }
}

// The same with bases of its own, for a solve that is not repeated.
template <class ExecSpace, class Apply, class Precondition>
KrylovResult fgmres(const KrylovVectors<ExecSpace>& ops, Apply&& apply, Precondition&& precondition,
                    const typename KrylovVectors<ExecSpace>::View& b, const typename KrylovVectors<ExecSpace>::View& x,
                    const KrylovOptions& options) {
  KrylovWorkspace<ExecSpace> workspace;
  return fgmres(ops, std::forward<Apply>(apply), std::forward<Precondition>(precondition), b, x, options, workspace);
}

}  // namespace poresph
