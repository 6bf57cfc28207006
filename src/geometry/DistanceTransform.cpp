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
// `from[p]` receives the q that gives d(p) (-1 where there is none).
void transform_line(const std::vector<double>& f, std::vector<double>& d, std::vector<long long>& v,
                    std::vector<double>& z, std::vector<long long>& from) {
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
    for (long long p = 0; p < m; ++p) d[p] = kInfinity, from[p] = -1;
    return;
  }
  k = 0;
  for (long long p = 0; p < m; ++p) {
    while (z[k + 1] < static_cast<double>(p)) ++k;
    const double offset = static_cast<double>(p - v[k]);
    d[p] = offset * offset + f[v[k]];
    from[p] = v[k];
  }
}

}  // namespace

std::vector<double> squared_distance_transform(const std::array<long long, 3>& shape, int dimension,
                                               const std::array<bool, 3>& periodic, const std::vector<char>& site,
                                               std::vector<long long>* nearest) {
  const long long count = shape[0] * shape[1] * shape[2];
  if (static_cast<long long>(site.size()) != count)
    throw std::invalid_argument("squared_distance_transform: one site flag a voxel expected");
  std::vector<double> d(static_cast<size_t>(count));
  for (long long n = 0; n < count; ++n) d[n] = site[n] ? 0.0 : kInfinity;
  // The nearest site of each voxel, carried through the passes: after the
  // pass along an axis, a voxel's nearest is that of the voxel on its line
  // whose parabola won.
  if (nearest) {
    nearest->resize(static_cast<size_t>(count));
    for (long long n = 0; n < count; ++n) (*nearest)[n] = site[n] ? n : -1;
  }
  std::vector<long long> line_nearest;
  const std::array<long long, 3> stride{{1, shape[0], shape[0] * shape[1]}};
  for (int axis = 0; axis < dimension; ++axis) {
    const long long n = shape[axis];
    // A periodic line is unrolled to three periods and read in the middle
    // one: the nearest copy of any minimiser is within half a period.
    const long long copies = periodic[axis] ? 3 : 1, m = copies * n;
    std::vector<double> f(m), out(m), z(m + 1);
    std::vector<long long> v(m), from(m);
    line_nearest.resize(n);
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    for (long long ib = 0; ib < shape[b]; ++ib)
      for (long long ia = 0; ia < shape[a]; ++ia) {
        const long long start = ia * stride[a] + ib * stride[b];
        for (long long q = 0; q < m; ++q) f[q] = d[start + (q % n) * stride[axis]];
        transform_line(f, out, v, z, from);
        const long long first = periodic[axis] ? n : 0;
        for (long long p = 0; p < n; ++p) d[start + p * stride[axis]] = out[first + p];
        if (!nearest) continue;
        for (long long p = 0; p < n; ++p) {
          const long long q = from[first + p];
          line_nearest[p] = q < 0 ? -1 : (*nearest)[start + (q % n) * stride[axis]];
        }
        for (long long p = 0; p < n; ++p) (*nearest)[start + p * stride[axis]] = line_nearest[p];
      }
  }
  return d;
}

std::vector<double> signed_distance(const VoxelImage& image, const std::vector<int>& solid_values, double voxel_size,
                                    const std::array<bool, 3>& periodic) {
  const auto is_solid_value = solid_value_table(solid_values);
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

namespace {

// How a bounded axis is continued past its end voxels for an average.
enum class Beyond { Slope, Repeat };

// Every line of `values` along `axis` averaged by 1/4, 1/2, 1/4: across the
// face along a periodic axis; a bounded one continues its end voxels'
// slope (which the average then keeps) or repeats them.
void average_along(std::vector<double>& values, const std::array<long long, 3>& shape, int axis,
                   const std::array<bool, 3>& periodic, Beyond beyond) {
  const std::array<long long, 3> stride{{1, shape[0], shape[0] * shape[1]}};
  const long long n = shape[axis];
  const bool slope = beyond == Beyond::Slope;
  if (n < (slope ? 3 : 1)) return;  // too short a line to continue a slope along
  std::vector<double> line(n);
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  for (long long ib = 0; ib < shape[b]; ++ib)
    for (long long ia = 0; ia < shape[a]; ++ia) {
      const long long start = ia * stride[a] + ib * stride[b];
      for (long long p = 0; p < n; ++p) line[p] = values[start + p * stride[axis]];
      const double first = periodic[axis] ? line[n - 1] : slope ? 2 * line[0] - line[1] : line[0];
      const double last = periodic[axis] ? line[0] : slope ? 2 * line[n - 1] - line[n - 2] : line[n - 1];
      for (long long p = 0; p < n; ++p) {
        const double below = p > 0 ? line[p - 1] : first, above = p < n - 1 ? line[p + 1] : last;
        values[start + p * stride[axis]] = 0.25 * below + 0.5 * line[p] + 0.25 * above;
      }
    }
}

}  // namespace

std::vector<float> smoothed_at_voxel_scale(std::vector<double> d, const std::array<long long, 3>& shape,
                                           int dimension, const std::array<bool, 3>& periodic) {
  for (int axis = 0; axis < dimension; ++axis) average_along(d, shape, axis, periodic, Beyond::Slope);
  return std::vector<float>(d.begin(), d.end());
}

std::vector<float> surface_distance(const VoxelImage& image, const std::vector<int>& solid_values, double voxel_size,
                                    const std::array<bool, 3>& periodic, const VoxelFrame* frame) {
  const int dim = image.dimension;
  const auto& shape = image.shape;
  const long long count = image.count();
  const std::array<long long, 3> stride{{1, shape[0], shape[0] * shape[1]}};
  const auto is_solid_value = solid_value_table(solid_values);

  // 1. The pore indicator blurred twice by 1/4, 1/2, 1/4 along each axis
  //    (a bounded axis repeats its end voxels).
  std::vector<double> phi(static_cast<size_t>(count));
  for (long long n = 0; n < count; ++n) phi[n] = is_solid_value[image.values[n]] ? 0.0 : 1.0;
  for (int pass = 0; pass < 2; ++pass)
    for (int axis = 0; axis < dim; ++axis) average_along(phi, shape, axis, periodic, Beyond::Repeat);

  // The neighbour of voxel `at` one step along an axis (-1: beyond a bounded side).
  auto neighbour = [&](long long at, const long long (&index)[3], int axis, int step) -> long long {
    long long c = index[axis] + step;
    if (c < 0 || c >= shape[axis]) {
      if (!periodic[axis]) return -1;
      c = c < 0 ? shape[axis] - 1 : 0;
    }
    return at + (c - index[axis]) * stride[axis];
  };
  auto index_of = [&](long long at, long long (&index)[3]) {
    index[0] = at % shape[0];
    index[1] = at / shape[0] % shape[1];
    index[2] = at / (shape[0] * shape[1]);
  };
  // Where a voxel lies in the cell: the whole image's own index, or a piece's shifted and wrapped.
  const VoxelFrame cell = frame ? *frame : VoxelFrame{{}, shape, periodic};
  auto cell_index = [&](const long long (&index)[3], long long (&in_cell)[3]) {
    for (int d = 0; d < 3; ++d) {
      const long long c = index[d] + cell.first[d];
      in_cell[d] = cell.periodic[d] ? (c % cell.shape[d] + cell.shape[d]) % cell.shape[d] : c;
    }
  };

  // 2. Surface points: where phi crosses 1/2 between two face neighbours,
  //    the crossing by linear interpolation between their centres, with the
  //    normal (into the pore) interpolated from their gradients. A point is
  //    kept with the lower voxel of its pair (first[v] .. first[v + 1]);
  //    both voxels become sites of the feature transform below.
  auto gradient_at = [&](long long at, std::array<double, 3>& g) {
    long long index[3];
    index_of(at, index);
    for (int d = 0; d < dim; ++d) {
      const long long lo = neighbour(at, index, d, -1), hi = neighbour(at, index, d, 1);
      const double up = hi >= 0 ? phi[hi] : phi[at], down = lo >= 0 ? phi[lo] : phi[at];
      g[d] = (up - down) / ((hi >= 0) + (lo >= 0));
    }
  };
  std::vector<long long> first(static_cast<size_t>(count) + 1, 0);
  std::vector<std::array<double, 3>> foot, normal;
  std::vector<char> site(static_cast<size_t>(count), 0);
  for (long long at = 0; at < count; ++at) {
    first[at] = static_cast<long long>(foot.size());
    long long index[3];
    index_of(at, index);
    for (int d = 0; d < dim; ++d) {
      const long long hi = neighbour(at, index, d, 1);
      if (hi < 0 || (phi[at] - 0.5) * (phi[hi] - 0.5) > 0 || phi[at] == phi[hi]) continue;
      const double t = (phi[at] - 0.5) / (phi[at] - phi[hi]);
      // The point in the cell's voxel coordinates (a piece's voxels shifted
      // to where they lie in the cell), so that a piece computes the whole
      // image's bits.
      std::array<double, 3> f{}, g_at{}, g_hi{}, u{};
      long long in_cell[3];
      cell_index(index, in_cell);
      for (int e = 0; e < dim; ++e) f[e] = in_cell[e] + 0.5;
      f[d] += t;
      gradient_at(at, g_at);
      gradient_at(hi, g_hi);
      double length_sq = 0;
      for (int e = 0; e < dim; ++e) {
        u[e] = (1 - t) * g_at[e] + t * g_hi[e];
        length_sq += u[e] * u[e];
      }
      if (length_sq == 0) continue;
      for (int e = 0; e < dim; ++e) u[e] /= std::sqrt(length_sq);
      foot.push_back(f);
      normal.push_back(u);
      site[at] = site[hi] = 1;
    }
  }
  first[count] = static_cast<long long>(foot.size());
  if (foot.empty())  // no level crossing survives the blur: the voxel staircase's own distance
    return smoothed_at_voxel_scale(signed_distance(image, solid_values, voxel_size, periodic), shape, dim, periodic);

  // 3. Every voxel's nearest surface voxel (the feature transform), then
  //    among the surface points around it the nearest, and the distance to
  //    that point's tangent plane: exact for a plane, and on a curve off
  //    only by the curve's departure from its tangent over the sampling.
  std::vector<long long> nearest;
  squared_distance_transform(shape, dim, periodic, site, &nearest);
  std::vector<float> distance(static_cast<size_t>(count));
  for (long long at = 0; at < count; ++at) {
    long long index[3], centre[3], here[3];
    index_of(at, index);
    index_of(nearest[at], centre);
    cell_index(index, here);
    double best_sq = std::numeric_limits<double>::infinity(), best = 0;
    const int reach[3] = {1, dim > 1 ? 1 : 0, dim > 2 ? 1 : 0};
    for (int k = -reach[2]; k <= reach[2]; ++k)
      for (int j = -reach[1]; j <= reach[1]; ++j)
        for (int i = -reach[0]; i <= reach[0]; ++i) {
          long long q = 0;
          bool inside = true;
          const int offset[3] = {i, j, k};
          for (int d = dim - 1; d >= 0; --d) {
            long long c = centre[d] + offset[d];
            if (c < 0 || c >= shape[d]) {
              if (!periodic[d]) inside = false;
              c = (c % shape[d] + shape[d]) % shape[d];
            }
            q = q * shape[d] + c;
          }
          if (!inside) continue;
          for (long long point = first[q]; point < first[q + 1]; ++point) {
            const auto& f = foot[point];
            double r[3] = {0, 0, 0}, r_sq = 0, along = 0;
            for (int d = 0; d < dim; ++d) {
              r[d] = here[d] + 0.5 - f[d];
              if (cell.periodic[d]) r[d] -= cell.shape[d] * std::floor(r[d] / cell.shape[d] + 0.5);  // nearest image
              r_sq += r[d] * r[d];
              along += r[d] * normal[point][d];
            }
            if (r_sq < best_sq) best_sq = r_sq, best = along;
          }
        }
    distance[at] = static_cast<float>(best * voxel_size);
  }
  return distance;
}

}  // namespace poresph
