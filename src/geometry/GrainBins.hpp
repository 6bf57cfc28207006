#pragma once
// Grains sorted into bins of the cell, so that the checks of a packing (and
// the random pack generator) look at neighbouring grains only: set-up grows
// with the number of grains, not with its square.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "scene/SceneConfig.hpp"

namespace poresph {

// The grains sorted into bins of the cell at least `width` wide, so that
// every grain whose centre is within `width` of a point (at the nearest
// periodic image) sits in the point's bin or a neighbouring one. The checks
// of a packing then look at neighbours only: set-up grows with the number
// of grains, not with its square (40,000 grains took 86 s pairwise).
class GrainBins {
 public:
  GrainBins(const std::vector<Grain>& grains, const SceneConfig& scene, double width)
      : scene_(scene), dim_(scene.dimension) {
    // No more bins than about four per grain: tiny grains in a large cell
    // would otherwise ask for more bins than memory holds. Wider bins are
    // still correct, only less selective.
    const double most_bins = 4.0 * static_cast<double>(grains.size()) + 1;
    const double per_direction = std::max(1.0, std::floor(std::pow(most_bins, 1.0 / dim_)));
    size_t bins = 1;
    for (int d = 0; d < dim_; ++d) {
      const double fit = width > 0 ? std::floor(scene.cell_size[d] / width) : per_direction;
      count_[d] = static_cast<int>(std::clamp(fit, 1.0, per_direction));
      bins *= count_[d];
    }
    begin_.assign(bins + 1, 0);
    std::vector<size_t> bin_of(grains.size());
    for (size_t g = 0; g < grains.size(); ++g) ++begin_[(bin_of[g] = bin(grains[g].centre)) + 1];
    for (size_t b = 0; b < bins; ++b) begin_[b + 1] += begin_[b];
    members_.resize(grains.size());
    std::vector<size_t> next(begin_.begin(), begin_.end() - 1);
    for (size_t g = 0; g < grains.size(); ++g) members_[next[bin_of[g]]++] = g;  // ascending within a bin
  }

  // f(g) once for every grain in the bins around `point`.
  template <class F>
  void for_each_near(const std::array<double, 3>& point, F&& f) const {
    // Bin indices per direction, each once (with one or two bins along a
    // periodic direction, -1 and +1 wrap onto the same bins).
    int around[3][3] = {}, found[3] = {1, 1, 1};
    for (int d = 0; d < dim_; ++d) {
      const int n = count_[d], k = index(point[d], d);
      found[d] = 0;
      for (int o = -1; o <= 1; ++o) {
        int j = k + o;
        if (scene_.periodic[d]) j = ((j % n) + n) % n;
        else if (j < 0 || j >= n) continue;
        if (std::find(around[d], around[d] + found[d], j) == around[d] + found[d]) around[d][found[d]++] = j;
      }
    }
    for (int a2 = 0; a2 < found[2]; ++a2)
      for (int a1 = 0; a1 < found[1]; ++a1)
        for (int a0 = 0; a0 < found[0]; ++a0) {
          const size_t b = (static_cast<size_t>(around[2][a2]) * count_[1] + around[1][a1]) * count_[0] + around[0][a0];
          for (size_t m = begin_[b]; m < begin_[b + 1]; ++m) f(members_[m]);
        }
  }

 private:
  int index(double x, int d) const {
    double y = x;
    if (scene_.periodic[d]) y -= scene_.cell_size[d] * std::floor(y / scene_.cell_size[d]);
    const double k = std::floor(y / scene_.cell_size[d] * count_[d]);
    return static_cast<int>(std::clamp(k, 0.0, count_[d] - 1.0));  // beyond a wall: the edge bin
  }
  size_t bin(const std::array<double, 3>& x) const {
    size_t b = 0;
    for (int d = dim_ - 1; d >= 0; --d) b = b * count_[d] + index(x[d], d);
    return b;
  }

  const SceneConfig& scene_;
  int dim_;
  std::array<int, 3> count_{{1, 1, 1}};
  std::vector<size_t> begin_, members_;
};

inline double largest_radius(const std::vector<Grain>& grains) {
  double r = 0;
  for (const auto& g : grains) r = std::max(r, g.radius);
  return r;
}

// f(i, j) for every pair i < j whose surfaces, at the nearest periodic
// image, are closer than `reach` (and perhaps a few more): each pair once.
template <class F>
void for_each_close_pair(const std::vector<Grain>& grains, const SceneConfig& scene, double reach, F&& f) {
  const GrainBins bins(grains, scene, 2 * largest_radius(grains) + reach);
  for (size_t i = 0; i < grains.size(); ++i)
    bins.for_each_near(grains[i].centre, [&](size_t j) {
      if (j > i) f(i, j);
    });
}

}  // namespace poresph
