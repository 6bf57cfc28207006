#include "geometry/Percolation.hpp"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <stdexcept>

namespace poresph {

bool pore_percolates(const VoxelImage& image, const std::vector<int>& solid_values, int axis,
                     const std::array<bool, 3>& periodic) {
  const auto is_solid_value = solid_value_table(solid_values);
  std::vector<char> open(image.values.size());
  for (size_t n = 0; n < open.size(); ++n) open[n] = !is_solid_value[image.values[n]];
  return open_percolates(image.shape, image.dimension, open, axis, periodic);
}

bool open_percolates(const std::array<long long, 3>& shape, int dimension, const std::vector<char>& open, int axis,
                     const std::array<bool, 3>& periodic) {
  if (axis < 0 || axis >= dimension) throw std::invalid_argument("open_percolates: no such axis");
  const size_t count = open.size();
  // Each pore voxel's cell along `axis` as its cluster was reached: the
  // unwrapped coordinate is i + lap * n. A voxel reached again on another
  // lap is joined to its own periodic image, which is the path asked for.
  constexpr int kUnvisited = INT_MIN;
  std::vector<int> lap(count, kUnvisited);
  std::vector<size_t> stack;
  const std::array<long long, 3> stride{{1, shape[0], shape[0] * shape[1]}};
  for (size_t seed = 0; seed < count; ++seed) {
    if (!open[seed] || lap[seed] != kUnvisited) continue;
    bool low_face = false, high_face = false;  // a bounded axis: the cluster touches both ends
    lap[seed] = 0;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const size_t n = stack.back();
      stack.pop_back();
      const long long at[3] = {static_cast<long long>(n) % shape[0], static_cast<long long>(n) / shape[0] % shape[1],
                               static_cast<long long>(n) / (shape[0] * shape[1])};
      low_face = low_face || at[axis] == 0;
      high_face = high_face || at[axis] == shape[axis] - 1;
      for (int d = 0; d < dimension; ++d)
        for (int step : {-1, 1}) {
          long long c = at[d] + step;
          int next_lap = lap[n];
          if (c < 0 || c >= shape[d]) {
            if (!periodic[d]) continue;
            c = c < 0 ? shape[d] - 1 : 0;
            if (d == axis) next_lap += step;
          }
          const size_t m = static_cast<size_t>(static_cast<long long>(n) + (c - at[d]) * stride[d]);
          if (!open[m]) continue;
          if (lap[m] == kUnvisited) {
            lap[m] = next_lap;
            stack.push_back(m);
          } else if (lap[m] != next_lap) {
            return true;
          }
        }
    }
    if (!periodic[axis] && low_face && high_face) return true;
  }
  return false;
}

double widest_path_width(const std::vector<double>& distance, const std::array<long long, 3>& shape, int dimension,
                         int axis, const std::array<bool, 3>& periodic) {
  // The largest t for which the voxels at least t from the solid percolate,
  // found by bisection among the distances that occur.
  std::vector<double> levels;
  for (double d : distance)
    if (d > 0) levels.push_back(d);
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  std::vector<char> open(distance.size());
  auto percolates_at = [&](double t) {
    for (size_t n = 0; n < open.size(); ++n) open[n] = distance[n] >= t;
    return open_percolates(shape, dimension, open, axis, periodic);
  };
  if (levels.empty() || !percolates_at(levels.front())) return 0.0;
  size_t lo = 0, hi = levels.size();  // levels[lo] percolates; levels[hi] (if any) does not
  while (hi - lo > 1) {
    const size_t mid = lo + (hi - lo) / 2;
    (percolates_at(levels[mid]) ? lo : hi) = mid;
  }
  return 2 * levels[lo];
}

}  // namespace poresph
