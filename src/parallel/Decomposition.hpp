#pragma once
// Which process owns which part of the unit cell: one axis-aligned box per
// rank, the boxes tiling the cell. In a direction bounded by walls the outer
// faces reach to infinity, so that wall particles beyond the cell have owners.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace poresph {

template <int Dim>
struct Box {
  std::array<double, Dim> lo{}, hi{};
  bool contains(const double* x) const {
    for (int d = 0; d < Dim; ++d)
      if (x[d] < lo[d] || x[d] >= hi[d]) return false;
    return true;
  }
};

template <int Dim>
class Decomposition {
 public:
  Decomposition() = default;
  Decomposition(std::vector<Box<Dim>> boxes, const std::array<double, Dim>& cell, const std::array<bool, Dim>& periodic)
      : boxes_(std::move(boxes)), cell_(cell), periodic_(periodic) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    for (auto& b : boxes_)
      for (int d = 0; d < Dim; ++d) {
        if (periodic_[d]) continue;
        if (b.lo[d] <= 0) b.lo[d] = -inf;
        if (b.hi[d] >= cell_[d]) b.hi[d] = inf;
      }
  }

  // Equal boxes on an n_0 x n_1 (x n_2) process grid, or with the given cuts
  // per direction (the paper's adjusted sub-cell boundaries).
  static Decomposition cartesian(const std::array<double, Dim>& cell, const std::array<bool, Dim>& periodic,
                                 const std::array<std::vector<double>, Dim>& cuts) {
    std::vector<Box<Dim>> boxes;
    std::array<int, Dim> n{};
    long long total = 1;
    for (int d = 0; d < Dim; ++d) n[d] = static_cast<int>(cuts[d].size()) - 1, total *= n[d];
    for (long long k = 0; k < total; ++k) {
      Box<Dim> b;
      long long rest = k;
      for (int d = 0; d < Dim; ++d) {
        const int i = static_cast<int>(rest % n[d]);
        rest /= n[d];
        b.lo[d] = cuts[d][i];
        b.hi[d] = cuts[d][i + 1];
      }
      boxes.push_back(b);
    }
    return Decomposition(boxes, cell, periodic);
  }

  static std::vector<double> equal_cuts(double side, int parts) {
    std::vector<double> cuts;
    for (int i = 0; i <= parts; ++i) cuts.push_back(i == parts ? side : side * i / parts);
    return cuts;
  }

  int ranks() const { return static_cast<int>(boxes_.size()); }
  const Box<Dim>& box(int rank) const { return boxes_[rank]; }
  const std::vector<Box<Dim>>& boxes() const { return boxes_; }
  const std::array<double, Dim>& cell() const { return cell_; }
  const std::array<bool, Dim>& periodic() const { return periodic_; }

  // The rank whose box holds x (x inside the cell in periodic directions).
  int owner(const double* x) const {
    for (int r = 0; r < ranks(); ++r)
      if (boxes_[r].contains(x)) return r;
    return -1;
  }

  // Refuses boxes that do not tile the cell, naming the problem.
  void check(int expected_ranks) const {
    if (ranks() != expected_ranks)
      throw std::invalid_argument("the decomposition has " + std::to_string(ranks()) + " boxes for " +
                                  std::to_string(expected_ranks) + " MPI ranks");
    double volume = 0, cell_volume = 1;
    for (int d = 0; d < Dim; ++d) cell_volume *= cell_[d];
    for (const auto& b : boxes_) {
      double v = 1;
      for (int d = 0; d < Dim; ++d) {
        const double lo = std::max(b.lo[d], 0.0), hi = std::min(b.hi[d], cell_[d]);
        if (!(hi > lo)) throw std::invalid_argument("a sub-domain box is empty");
        v *= hi - lo;
      }
      volume += v;
    }
    if (std::abs(volume / cell_volume - 1) > 1e-9)
      throw std::invalid_argument("the sub-domain boxes do not tile the cell");
  }

 private:
  std::vector<Box<Dim>> boxes_;
  std::array<double, Dim> cell_{};
  std::array<bool, Dim> periodic_{};
};

// The paper's process grid: n_0 x n_1 (x n_2) boxes, the grid given
// (Parallel/Process Grid) or else the factorisation of `ranks` whose boxes
// are closest to cubes, cut where given (Parallel/X Cuts, ...) or equally.
template <int Dim>
Decomposition<Dim> grid_decomposition(const std::array<double, Dim>& cell, const std::array<bool, Dim>& periodic,
                                      int ranks, const std::vector<int>& process_grid,
                                      const std::array<std::vector<double>, Dim>& given_cuts) {
  std::array<int, Dim> grid{};
  if (!process_grid.empty()) {
    if (static_cast<int>(process_grid.size()) != Dim)
      throw std::invalid_argument("Parallel/Process Grid needs one count per direction");
    for (int d = 0; d < Dim; ++d) grid[d] = process_grid[d];
  } else {
    // The factorisation of `ranks` whose boxes are closest to cubes.
    double best = std::numeric_limits<double>::infinity();
    std::array<int, Dim> g{};
    auto search = [&](auto&& self, int d, int left) -> void {
      if (d == Dim - 1) {
        g[d] = left;
        double worst = 1;
        for (int a = 0; a < Dim; ++a)
          for (int b = 0; b < Dim; ++b) worst = std::max(worst, (cell[a] / g[a]) / (cell[b] / g[b]));
        if (worst < best) best = worst, grid = g;
        return;
      }
      for (int n = 1; n <= left; ++n)
        if (left % n == 0) g[d] = n, self(self, d + 1, left / n);
    };
    search(search, 0, ranks);
  }
  std::array<std::vector<double>, Dim> cuts;
  int product = 1;
  for (int d = 0; d < Dim; ++d) {
    product *= grid[d];
    cuts[d] = given_cuts[d].empty() ? Decomposition<Dim>::equal_cuts(cell[d], grid[d]) : given_cuts[d];
    if (static_cast<int>(cuts[d].size()) != grid[d] + 1 || cuts[d].front() != 0 || cuts[d].back() != cell[d] ||
        !std::is_sorted(cuts[d].begin(), cuts[d].end()))
      throw std::invalid_argument("Parallel cuts along direction " + std::to_string(d) + " must run from 0 to the "
                                  "cell side in increasing order, one more than the process grid's count");
  }
  if (product != ranks)
    throw std::invalid_argument("Parallel/Process Grid holds " + std::to_string(product) + " processes, the run has " +
                                std::to_string(ranks));
  auto decomposition = Decomposition<Dim>::cartesian(cell, periodic, cuts);
  decomposition.check(ranks);
  return decomposition;
}

}  // namespace poresph
