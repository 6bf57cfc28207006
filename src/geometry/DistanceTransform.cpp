#include "geometry/DistanceTransform.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace poresph {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// d(p) = min_q (p - q)^2 + f(q) for p, q in [0, m): the lower envelope of the
// parabolas rooted at the finite f(q). `v` and `z` are scratch of m and
// m + 1 entries (the envelope's parabolas and where each takes over).
void transform_line(const std::vector<double>& f, std::vector<double>& d, std::vector<long long>& v,
                    std::vector<double>& z) {
  const long long m = static_cast<long long>(f.size());
  long long k = -1;
  for (long long q = 0; q < m; ++q) {
    if (f[q] == kInfinity) continue;  // no parabola: inf - inf would spoil the intersections
    double s = -kInfinity;
    while (k >= 0) {
      const long long r = v[k];
      s = ((f[q] + static_cast<double>(q * q)) - (f[r] + static_cast<double>(r * r))) / (2.0 * (q - r));
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = k == 0 ? -kInfinity : s;
    z[k + 1] = kInfinity;
  }
  if (k < 0) {  // no site on this line
    for (long long p = 0; p < m; ++p) d[p] = kInfinity;
    return;
  }
  k = 0;
  for (long long p = 0; p < m; ++p) {
    while (z[k + 1] < static_cast<double>(p)) ++k;
    const double offset = static_cast<double>(p - v[k]);
    d[p] = offset * offset + f[v[k]];
  }
}

}  // namespace

std::vector<double> squared_distance_transform(const std::array<long long, 3>& shape, int dimension,
                                               const std::array<bool, 3>& periodic, const std::vector<char>& site) {
  const long long count = shape[0] * shape[1] * shape[2];
  if (static_cast<long long>(site.size()) != count)
    throw std::invalid_argument("squared_distance_transform: one site flag a voxel expected");
  std::vector<double> d(static_cast<size_t>(count));
  for (long long n = 0; n < count; ++n) d[n] = site[n] ? 0.0 : kInfinity;
  const std::array<long long, 3> stride{{1, shape[0], shape[0] * shape[1]}};
  for (int axis = 0; axis < dimension; ++axis) {
    const long long n = shape[axis];
    // A periodic line is unrolled to three periods and read in the middle
    // one: the nearest copy of any minimiser is within half a period.
    const long long copies = periodic[axis] ? 3 : 1, m = copies * n;
    std::vector<double> f(m), out(m), z(m + 1);
    std::vector<long long> v(m);
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    for (long long ib = 0; ib < shape[b]; ++ib)
      for (long long ia = 0; ia < shape[a]; ++ia) {
        const long long start = ia * stride[a] + ib * stride[b];
        for (long long q = 0; q < m; ++q) f[q] = d[start + (q % n) * stride[axis]];
        transform_line(f, out, v, z);
        const long long first = periodic[axis] ? n : 0;
        for (long long p = 0; p < n; ++p) d[start + p * stride[axis]] = out[first + p];
      }
  }
  return d;
}

std::vector<double> signed_distance(const VoxelImage& image, const std::vector<int>& solid_values, double voxel_size,
                                    const std::array<bool, 3>& periodic) {
  std::vector<char> is_solid_value(1 << 16, 0);
  for (int v : solid_values)
    if (v >= 0 && v < (1 << 16)) is_solid_value[v] = 1;
  const size_t count = image.values.size();
  std::vector<char> solid(count), pore(count);
  for (size_t n = 0; n < count; ++n) {
    solid[n] = is_solid_value[image.values[n]];
    pore[n] = !solid[n];
  }
  const auto to_solid = squared_distance_transform(image.shape, image.dimension, periodic, solid);
  const auto to_pore = squared_distance_transform(image.shape, image.dimension, periodic, pore);
  std::vector<double> distance(count);
  for (size_t n = 0; n < count; ++n)
    distance[n] = voxel_size * (solid[n] ? -(std::sqrt(to_pore[n]) - 0.5) : std::sqrt(to_solid[n]) - 0.5);
  return distance;
}

}  // namespace poresph
