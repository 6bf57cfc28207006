#pragma once
// A scalar operator on a periodic lattice of points, some of them unknowns
// (fluid) and some not (solid): the graph Laplacian with 2 Dim nearest
// neighbours, a solid neighbour counted on the diagonal (Dirichlet), and its
// multigrid by aggregation of 2^Dim blocks of points, with Galerkin coarse
// operators (again such lattices) and piecewise-constant transfer.
//
// The steady solver preconditions with it: the velocity block is near a
// compact Laplacian, and the pressure operator DG near the wide one (stride
// 2), which splits into 2^Dim compact ones on the sub-lattices of spacing 2
// (docs/steady_solver.md). Both are solved here on the whole lattice, which
// every process holds (solver/LatticePreconditioner.hpp gathers it).
#include <Kokkos_Core.hpp>
#include <Teuchos_LAPACK.hpp>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace poresph {

// Real: the scalar the levels hold. The steady solver's preconditioners
// take float: a preconditioner inside a flexible Krylov method whose inner
// solves stop at 1e-2 has no use for double's digits, and a lattice larger
// than the cache is swept at the speed of memory, where float halves the
// traffic (docs/steady_solver.md, "The cycle made lean").
template <int Dim, class ExecSpace, class Real = float>
class LatticeMultigrid {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using View = Kokkos::View<double*, MemorySpace>;  // what callers give and take
  using Field = Kokkos::View<Real*, MemorySpace>;   // what the levels hold
  using Couplings = Kokkos::View<Real* [Dim], MemorySpace>;

  LatticeMultigrid() = default;

  // shape: points per axis; active(i) = 1 for an unknown (x fastest). A
  // lattice with no solid has the constant as null vector, which the
  // coarsest level's pseudo-inverse leaves out.
  LatticeMultigrid(const ExecSpace& space, const std::array<int, Dim>& shape, const std::vector<char>& active)
      : space_(space) {
    Level fine = make_level(shape);
    auto diag = Kokkos::create_mirror_view(fine.diag);
    auto up = Kokkos::create_mirror_view(fine.up);
    for (long long i = 0; i < fine.size; ++i) {
      if (!active[i]) continue;
      diag(i) = 2 * Dim;
      for (int d = 0; d < Dim; ++d) up(i, d) = active[neighbour(fine, i, d, +1)] ? 1.0 : 0.0;
    }
    Kokkos::deep_copy(fine.diag, diag);
    Kokkos::deep_copy(fine.up, up);
    take_inverse_diag(fine);
    fine.unit_couplings = true;
    levels_.push_back(fine);
    while (levels_.back().size > kCoarsest) {
      bool coarser = false;
      for (int d = 0; d < Dim; ++d) coarser = coarser || levels_.back().shape[d] > 1;
      if (!coarser) break;
      levels_.push_back(coarsen(levels_.back()));
    }
    coarsest_inverse_ = pseudo_inverse(levels_.back());
  }

  long long size() const { return levels_.empty() ? 0 : levels_.front().size; }
  int levels() const { return static_cast<int>(levels_.size()); }

  // x = one cycle for L x = b from x = 0 (two Gauss-Seidel sweeps by colours
  // before and after each coarse correction; a V on the finest level and a W
  // below, cycle_from), b and x over all points of the finest lattice: a
  // fixed linear operator, whatever the cycle before it left.
  void cycle(const View& b, const View& x) const {
    convert(b, levels_[0].b);
    cycle_down();
    cycle_up();
    convert(levels_[0].x, x);
  }

  // The same cycle in two halves, for several multigrids on lattices of one
  // shape that change their coarse corrections together, the right-hand side
  // written onto finest_b() by the caller (in place, once: off the unknowns
  // it must stay 0): cycle_down() runs the cycle to the correction of the
  // second level, coarse_correction() (empty with one level) may then be
  // changed, cycle_up() finishes with the result in finest_x() (0 off the
  // unknowns).
  void cycle_down() const {
    Kokkos::deep_copy(space_, levels_[0].x, Real(0));
    if (levels_.size() == 1) {
      cycle_from(0);
      return;
    }
    descend(0);
    cycle_from(1);
  }
  Field coarse_correction() const { return levels_.size() > 1 ? levels_[1].x : Field(); }
  void cycle_up() const {
    if (levels_.size() > 1) ascend(0, 1.0);
  }
  Field finest_b() const { return levels_[0].b; }
  Field finest_x() const { return levels_[0].x; }

  // y = L x on the finest lattice.
  void apply(const View& x, const View& y) const {
    if (levels_[0].unit_couplings)
      apply_level_with<true>(levels_[0], x, y);
    else
      apply_level_with<false>(levels_[0], x, y);
  }

 private:
  template <class From, class To>
  void convert(const From& from, const To& to) const {
    using Value = typename To::value_type;
    static const std::string label = "poresph::multigrid::convert";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, to.extent(0)),
        KOKKOS_LAMBDA(long long i) { to(i) = static_cast<Value>(from(i)); });
    space_.fence();
  }

  static constexpr long long kCoarsest = 64;
  static constexpr double kOvercorrection = 2.0;
  struct Level {
    std::array<int, Dim> shape{};
    long long size = 0;
    Field diag, inverse_diag, x, b;  // inverse_diag: 1 / diag, 0 off the unknowns
    Couplings up;  // to the +e_d neighbour; the -e_d coupling is the neighbour's up
    // The finest level's couplings are 1 between two unknowns and 0 else,
    // and x is 0 off the unknowns (no sweep or correction writes there): so
    // a coupling times x is x, and the loops there need not load the couplings.
    bool unit_couplings = false;
  };

  Level make_level(const std::array<int, Dim>& shape) const {
    Level level;
    level.shape = shape;
    level.size = 1;
    for (int d = 0; d < Dim; ++d) level.size *= shape[d];
    level.diag = Field("multigrid_diag", level.size);
    level.inverse_diag = Field("multigrid_inverse_diag", level.size);
    level.x = Field("multigrid_x", level.size);
    level.b = Field("multigrid_b", level.size);
    level.up = Couplings("multigrid_up", level.size);
    return level;
  }

  KOKKOS_INLINE_FUNCTION static long long neighbour_of(const std::array<int, Dim>& shape, long long i, int axis,
                                                       int step) {
    long long stride = 1;
    for (int d = 0; d < axis; ++d) stride *= shape[d];
    const int coordinate = static_cast<int>((i / stride) % shape[axis]);
    const int moved = (coordinate + step + shape[axis]) % shape[axis];
    return i + (moved - coordinate) * stride;
  }
  static long long neighbour(const Level& level, long long i, int axis, int step) {
    return neighbour_of(level.shape, i, axis, step);
  }

  // Aggregates of 2^Dim points (fewer at an odd end); Galerkin with
  // piecewise-constant P: a coarse coupling sums the fine couplings between
  // the two aggregates, a coarse diagonal the fine entries within one.
  Level coarsen(const Level& fine) const {
    std::array<int, Dim> shape;
    for (int d = 0; d < Dim; ++d) shape[d] = (fine.shape[d] + 1) / 2;
    Level coarse = make_level(shape);
    auto fdiag = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fine.diag);
    auto fup = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fine.up);
    auto cdiag = Kokkos::create_mirror_view(coarse.diag);
    auto cup = Kokkos::create_mirror_view(coarse.up);
    Kokkos::deep_copy(cdiag, 0.0);
    Kokkos::deep_copy(cup, 0.0);
    for (long long i = 0; i < fine.size; ++i) {
      if (fdiag(i) == 0) continue;
      const long long I = aggregate(fine, coarse, i);
      cdiag(I) += fdiag(i);
      for (int d = 0; d < Dim; ++d) {
        if (fup(i, d) == 0) continue;
        const long long J = aggregate(fine, coarse, neighbour(fine, i, d, +1));
        if (J == I)
          cdiag(I) -= 2 * fup(i, d);
        else
          cup(I, d) += fup(i, d);
      }
    }
    Kokkos::deep_copy(coarse.diag, cdiag);
    Kokkos::deep_copy(coarse.up, cup);
    take_inverse_diag(coarse);
    return coarse;
  }
  void take_inverse_diag(const Level& level) const {
    const auto diag = level.diag, inverse = level.inverse_diag;
    static const std::string label = "poresph::multigrid::inverse_diag";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, level.size),
        KOKKOS_LAMBDA(long long i) { inverse(i) = diag(i) == 0 ? Real(0) : Real(1) / diag(i); });
    space_.fence();
  }

  static long long aggregate(const Level& fine, const Level& coarse, long long i) {
    long long I = 0, stride = 1, fine_stride = 1;
    for (int d = 0; d < Dim; ++d) {
      const int c = static_cast<int>((i / fine_stride) % fine.shape[d]);
      I += (c / 2) * stride;
      stride *= coarse.shape[d];
      fine_stride *= fine.shape[d];
    }
    return I;
  }

  // A line of points along x: its first point, the parity of its other
  // coordinates, and the offsets to its neighbours along the other axes
  // (periodic), the same for every point of the line.
  struct Line {
    long long first;
    int parity;
    long long below[Dim], above[Dim];
  };
  KOKKOS_INLINE_FUNCTION static Line line_of(const std::array<int, Dim>& shape, long long line) {
    Line l;
    l.first = line * shape[0];
    l.parity = 0;
    long long rest = line, stride = shape[0];
    l.below[0] = l.above[0] = 0;
    for (int d = 1; d < Dim; ++d) {
      const int c = static_cast<int>(rest % shape[d]);
      rest /= shape[d];
      l.parity += c;
      l.above[d] = c + 1 == shape[d] ? -(shape[d] - 1) * stride : stride;
      l.below[d] = c == 0 ? (shape[d] - 1) * stride : -stride;
      stride *= shape[d];
    }
    return l;
  }
  // The sum of couplings x_j at point i of line l, whose neighbours along x
  // are left and right (periodic): what L x subtracts from diag x, and what
  // a Gauss-Seidel update adds to b. With Unit (Level::unit_couplings) the
  // same sum, term for term, without loading the couplings. Summed in
  // double, whatever x holds.
  template <bool Unit, class X>
  KOKKOS_INLINE_FUNCTION static double couplings(const Couplings& up, const X& x, const Line& l, long long i,
                                                 long long left, long long right) {
    if constexpr (Unit) {
      double sum = double(x(right)) + x(left);
      for (int d = 1; d < Dim; ++d) sum += double(x(i + l.above[d])) + x(i + l.below[d]);
      return sum;
    } else {
      double sum = double(up(i, 0)) * x(right) + double(up(left, 0)) * x(left);
      for (int d = 1; d < Dim; ++d)
        sum += double(up(i, d)) * x(i + l.above[d]) + double(up(i + l.below[d], d)) * x(i + l.below[d]);
      return sum;
    }
  }

  // (L x)_i at point c of line l (n points along x, periodic), in double.
  template <bool Unit, class X>
  KOKKOS_INLINE_FUNCTION static double product_at(const Field& diag, const Couplings& up, const X& x, const Line& l,
                                                  int c, int n) {
    const long long i = l.first + c;
    const long long left = c == 0 ? i + n - 1 : i - 1, right = c + 1 == n ? i - (n - 1) : i + 1;
    return double(diag(i)) * x(i) - couplings<Unit>(up, x, l, i, left, right);
  }

  template <bool Unit, class X, class Y>
  void apply_level_with(const Level& level, const X& x, const Y& y) const {
    using Value = typename Y::value_type;
    const auto diag = level.diag;
    const auto up = level.up;
    const auto shape = level.shape;
    const long long lines = level.size / shape[0];
    static const std::string label = "poresph::multigrid::apply";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, lines), KOKKOS_LAMBDA(long long line) {
          const Line l = line_of(shape, line);
          const int n = shape[0];
          for (int c = 0; c < n; ++c) {
            const long long i = l.first + c;
            y(i) = diag(i) == 0 ? Value(0) : static_cast<Value>(product_at<Unit>(diag, up, x, l, c, n));
          }
        });
    space_.fence();
  }

  // One Gauss-Seidel sweep by colours (the parity of the coordinates'
  // sum: independent points of a 2 Dim + 1 stencil on an even lattice), in
  // colour order 0, 1 or 1, 0.
  void smooth(const Level& level, bool forward) const {
    if (level.unit_couplings)
      smooth_with<true>(level, forward);
    else
      smooth_with<false>(level, forward);
  }
  // An update is (b_i + couplings) times the inverse diagonal, which is 0
  // off the unknowns (x stays 0 there), so the loop has no branch and no
  // division: the multigrid's cycles are bound by the latency of each
  // update, not by memory (docs/steady_solver.md). The two ends of a line,
  // whose neighbours wrap around, are done apart from its interior.
  template <bool Unit>
  void smooth_with(const Level& level, bool forward) const {
    const auto inverse_diag = level.inverse_diag;
    const auto up = level.up;
    const auto shape = level.shape;
    const auto x = level.x, b = level.b;
    const long long lines = level.size / shape[0];
    for (int k = 0; k < 2; ++k) {
      const int colour = forward ? k : 1 - k;
      static const std::string label = "poresph::multigrid::smooth";
      Kokkos::parallel_for(
          label, Kokkos::RangePolicy<ExecSpace>(space_, 0, lines), KOKKOS_LAMBDA(long long line) {
            const Line l = line_of(shape, line);
            const int n = shape[0];
            auto update = [&](long long i, long long left, long long right) {
              x(i) = static_cast<Real>((b(i) + couplings<Unit>(up, x, l, i, left, right)) * inverse_diag(i));
            };
            const int first = (colour + l.parity) % 2;
            if (n == 1) {
              if (first == 0) update(l.first, l.first, l.first);
              return;
            }
            if (first == 0) update(l.first, l.first + n - 1, l.first + 1);
            const int end = n - 1;  // the last point: not in the interior loop
            for (int c = first == 0 ? 2 : 1; c < end; c += 2) {
              const long long i = l.first + c;
              update(i, i - 1, i + 1);
            }
            if ((end - first) % 2 == 0) update(l.first + end, l.first + end - 1, l.first);
          });
      space_.fence();
    }
  }

  // A V-cycle on the finest level, a W-cycle below it: from the second level
  // down, the coarse problem is solved twice (the second time for what the
  // first correction left) and that correction is over-weighted by
  // kOvercorrection. Piecewise-constant aggregation makes the coarse
  // operator about twice too stiff on smooth modes (a piecewise-constant
  // function has about twice the energy of the smooth one it stands for), so
  // each coarse correction falls about half short, and a V-cycle compounds
  // that over the levels: around a dozen discs its rate went from 0.70 at
  // 64 points a side to 0.98 at 1,024 (4 to 8 levels); this cycle gives
  // 0.62 to 0.82 (test LatticeMultigridKeepsItsRateAcrossLevels), for 15 to
  // 35 % more time a cycle in 2D and 3 to 8 % in 3D (docs/steady_solver.md).
  // The finest level is not over-weighted: its correction is the one the
  // sign patterns' weights act on (solver/LatticePreconditioner.hpp).
  void cycle_from(size_t l) const {
    if (l + 1 == levels_.size()) {
      solve_coarsest();
      return;
    }
    descend(l);
    cycle_from(l + 1);
    if (l >= 1) {
      prolong(l, 1.0);
      restrict_residual(l, false);
      cycle_from(l + 1);
    }
    ascend(l, l >= 1 ? kOvercorrection : 1.0);
  }

  // Pre-smoothing on level l, then its residual restricted.
  void descend(size_t l) const {
    const Level& level = levels_[l];
    smooth(level, true);
    smooth(level, true);
    restrict_residual(l, true);
  }
  // Level l's residual b - L x restricted to level l + 1's right-hand side
  // (the aggregate's sum of residuals), the coarse x set to 0, the residual
  // computed where it is summed. By coarse lines along x: the fine lines of
  // a line's aggregates are found once, not each point's indices by integer
  // divisions (docs/steady_solver.md). After a forward sweep (smoothed) on
  // a level whose sides are all even, the colour swept last has a zero
  // residual to round-off: each of its points was solved for with
  // neighbours all of the other colour, which have not moved since. So
  // only the other colour's residual is computed, half the points. (Along
  // an odd side the colours meet across the periodic end, and every point
  // is computed.)
  void restrict_residual(size_t l, bool smoothed) const {
    if (levels_[l].unit_couplings)
      restrict_with<true>(l, smoothed);
    else
      restrict_with<false>(l, smoothed);
  }
  template <bool Unit>
  void restrict_with(size_t l, bool smoothed) const {
    const Level& level = levels_[l];
    const Level& coarse = levels_[l + 1];
    const auto x = level.x, b = level.b, diag = level.diag;
    const auto up = level.up;
    const auto cb = coarse.b;
    const auto fine_shape = level.shape, coarse_shape = coarse.shape;
    bool even = true;
    for (int d = 0; d < Dim; ++d) even = even && fine_shape[d] % 2 == 0;
    const int settled = smoothed && even ? 1 : -1;  // the colour whose residual is zero, if any
    Kokkos::deep_copy(space_, coarse.x, Real(0));
    space_.fence();
    constexpr int kUpper = 1 << (Dim - 1);  // an aggregate's fine lines: a bit per axis past x
    static const std::string label_restrict = "poresph::multigrid::restrict";
    Kokkos::parallel_for(
        label_restrict, Kokkos::RangePolicy<ExecSpace>(space_, 0, coarse.size / coarse_shape[0]),
        KOKKOS_LAMBDA(long long line) {
          Line fine_line[kUpper];
          bool line_inside[kUpper];
          for (int upper = 0; upper < kUpper; ++upper) {
            long long rest = line, fine = 0, stride = 1;
            bool inside = true;
            for (int d = 1; d < Dim; ++d) {
              const int c = 2 * static_cast<int>(rest % coarse_shape[d]) + ((upper >> (d - 1)) & 1);
              rest /= coarse_shape[d];
              inside = inside && c < fine_shape[d];
              fine += c * stride;
              stride *= fine_shape[d];
            }
            line_inside[upper] = inside;
            if (inside) fine_line[upper] = line_of(fine_shape, fine);
          }
          const int n = fine_shape[0];
          for (int c0 = 0; c0 < coarse_shape[0]; ++c0) {
            double sum = 0;
            for (int corner = 0; corner < (1 << Dim); ++corner) {  // bit d: the corner's step along axis d
              const int c = 2 * c0 + (corner & 1);
              if (!line_inside[corner >> 1] || c >= n) continue;
              const Line& fl = fine_line[corner >> 1];
              const long long i = fl.first + c;
              if (diag(i) == 0 || (c + fl.parity) % 2 == settled) continue;
              sum += b(i) - product_at<Unit>(diag, up, x, fl, c, n);
            }
            cb(line * coarse_shape[0] + c0) = static_cast<Real>(sum);
          }
        });
    space_.fence();
  }

  // The coarse correction added, weighed, and post-smoothing.
  void ascend(size_t l, double weight) const {
    prolong(l, weight);
    smooth(levels_[l], false);
    smooth(levels_[l], false);
  }
  // Level l + 1's x times weight added to level l's (piecewise constant), by
  // fine lines along x.
  void prolong(size_t l, double weight) const {
    const Level& level = levels_[l];
    const Level& coarse = levels_[l + 1];
    const auto diag = level.diag, x = level.x, cx = coarse.x;
    const auto fine_shape = level.shape, coarse_shape = coarse.shape;
    static const std::string label_prolong = "poresph::multigrid::prolong";
    Kokkos::parallel_for(
        label_prolong, Kokkos::RangePolicy<ExecSpace>(space_, 0, level.size / fine_shape[0]),
        KOKKOS_LAMBDA(long long line) {
          long long rest = line, coarse_line = 0, stride = 1;
          for (int d = 1; d < Dim; ++d) {
            coarse_line += (rest % fine_shape[d]) / 2 * stride;
            rest /= fine_shape[d];
            stride *= coarse_shape[d];
          }
          const long long first = line * fine_shape[0], coarse_first = coarse_line * coarse_shape[0];
          for (int c = 0; c < fine_shape[0]; ++c)
            if (diag(first + c) != 0) x(first + c) += static_cast<Real>(weight * cx(coarse_first + c / 2));
        });
    space_.fence();
  }

  // The coarsest level (kCoarsest points at most) solved exactly: x = L^+ b
  // by its pseudo-inverse, which the W-cycle asks for 2^(levels - 2) times a
  // cycle. Fifty Gauss-Seidel sweeps did nearly the same, in 100 kernel
  // launches a visit: a quarter of a cycle's updates on a lattice of 200²
  // (docs/steady_solver.md). The pseudo-inverse, because a lattice with no
  // solid, or a pocket of one that none touches, has a null space.
  using Dense = Kokkos::View<Real**, MemorySpace>;
  static Dense pseudo_inverse(const Level& level) {
    const int n = static_cast<int>(level.size);
    auto diag = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), level.diag);
    auto up = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), level.up);
    std::vector<double> a(static_cast<size_t>(n) * n, 0.0);  // column-major, symmetric
    for (int i = 0; i < n; ++i) {
      a[i + static_cast<size_t>(n) * i] += diag(i);
      for (int d = 0; d < Dim; ++d) {
        const int j = static_cast<int>(neighbour(level, i, d, +1));
        a[i + static_cast<size_t>(n) * j] -= up(i, d);
        a[j + static_cast<size_t>(n) * i] -= up(i, d);
      }
    }
    std::vector<double> eigenvalues(n), work(std::max(1, 3 * n));
    int info = 0;
    Teuchos::LAPACK<int, double>().SYEV('V', 'U', n, a.data(), n, eigenvalues.data(), work.data(),
                                         static_cast<int>(work.size()), &info);
    if (info != 0)
      throw std::runtime_error("LatticeMultigrid: LAPACK's dsyev failed on the coarsest level (info " +
                               std::to_string(info) + ")");
    Dense inverse("multigrid_coarsest_inverse", n, n);
    auto host = Kokkos::create_mirror_view(inverse);
    Kokkos::deep_copy(host, Real(0));
    const double largest = n > 0 ? std::fabs(eigenvalues[n - 1]) : 0.0;
    for (int k = 0; k < n; ++k) {
      if (!(eigenvalues[k] > 1e-10 * largest)) continue;  // the null space (and round-off about it)
      const double* v = a.data() + static_cast<size_t>(n) * k;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) host(i, j) += static_cast<Real>(v[i] * v[j] / eigenvalues[k]);
    }
    Kokkos::deep_copy(inverse, host);
    return inverse;
  }
  void solve_coarsest() const {
    const Level& level = levels_.back();
    const auto inverse = coarsest_inverse_;
    const auto x = level.x, b = level.b;
    const int n = static_cast<int>(level.size);
    static const std::string label = "poresph::multigrid::solve_coarsest";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, n), KOKKOS_LAMBDA(int i) {
          double sum = 0;
          for (int j = 0; j < n; ++j) sum += double(inverse(i, j)) * b(j);
          x(i) = static_cast<Real>(sum);
        });
    space_.fence();
  }

  ExecSpace space_;
  std::vector<Level> levels_;
  Dense coarsest_inverse_;
};

}  // namespace poresph
