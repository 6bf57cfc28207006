#pragma once
// A segmented image as PoreSPH holds it: one value a voxel, whatever the
// file it came from (io/ImageReader.hpp). Voxel (i, j, k) covers
// [i, i+1) x [j, j+1) x [k, k+1) voxel sizes from the cell's origin, so y
// grows upwards and a 2D image is one layer (nz = 1).
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace poresph {

struct VoxelImage {
  int dimension = 2;
  std::array<long long, 3> shape{{0, 0, 1}};  // nx, ny, nz; nz = 1 in 2D
  // Bits a value was stored with (8 or 16; 1, 2 and 4-bit PNGs are read as
  // 8): a solid value beyond 2^bits - 1 names no voxel of this image.
  int bits = 8;
  std::vector<std::uint16_t> values;  // x fastest, then y, then z

  long long count() const { return shape[0] * shape[1] * shape[2]; }
  std::size_t index(long long i, long long j, long long k = 0) const {
    return static_cast<std::size_t>(i + shape[0] * (j + shape[1] * k));
  }
  std::uint16_t at(long long i, long long j, long long k = 0) const { return values[index(i, j, k)]; }
};

// The voxels of the cell a box covers: [lo, hi) along each axis, in the
// cell's voxels (after Image/Mirror).
struct VoxelBox {
  std::array<long long, 3> lo{}, hi{{0, 0, 1}};
  bool empty() const { return hi[0] <= lo[0] || hi[1] <= lo[1] || hi[2] <= lo[2]; }
};

// "120 x 80" or "64 x 64 x 32": for messages.
inline std::string shape_text(const std::array<long long, 3>& shape, int dimension) {
  std::string text;
  for (int d = 0; d < dimension; ++d) text += (d ? " x " : "") + std::to_string(shape[d]);
  return text;
}
inline std::string shape_text(const VoxelImage& image) { return shape_text(image.shape, image.dimension); }

// The image followed by its mirror image along `axis`: twice as long there,
// and periodic along it whatever the sample's two faces look like (voxel
// n + m is voxel n - 1 - m), as LBM codes make a non-periodic sample
// periodic along the driven axis.
inline VoxelImage mirrored(const VoxelImage& image, int axis) {
  if (axis < 0 || axis >= image.dimension)
    throw std::invalid_argument("cannot mirror a " + std::to_string(image.dimension) + "D image along axis " +
                                std::to_string(axis));
  VoxelImage out = image;
  out.shape[axis] *= 2;
  out.values.assign(static_cast<std::size_t>(out.count()), 0);
  const long long n = image.shape[axis];
  for (long long k = 0; k < out.shape[2]; ++k)
    for (long long j = 0; j < out.shape[1]; ++j)
      for (long long i = 0; i < out.shape[0]; ++i) {
        std::array<long long, 3> from{{i, j, k}};
        if (from[axis] >= n) from[axis] = 2 * n - 1 - from[axis];
        out.values[out.index(i, j, k)] = image.at(from[0], from[1], from[2]);
      }
  return out;
}

// A table over every 16-bit value, 1 where the value is one of
// `solid_values`: one look-up a voxel, however many values are solid.
inline std::vector<char> solid_value_table(const std::vector<int>& solid_values) {
  std::vector<char> solid(1 << 16, 0);
  for (int v : solid_values)
    if (v >= 0 && v < (1 << 16)) solid[v] = 1;
  return solid;
}

// Solid and pore voxels, the solid ones being those whose value is listed.
struct VoxelCounts {
  long long solid = 0, pore = 0;
};
inline VoxelCounts count_voxels(const VoxelImage& image, const std::vector<int>& solid_values) {
  const auto solid = solid_value_table(solid_values);
  VoxelCounts counts;
  for (std::uint16_t v : image.values) counts.solid += solid[v];
  counts.pore = image.count() - counts.solid;
  return counts;
}

// How much an image's two faces across `axis` differ, against neighbouring
// layers inside: the fraction of voxels whose phase (solid or pore)
// differs between layer 0 and layer n - 1, which a periodic cell puts side
// by side, and the largest such fraction of two neighbouring layers
// inside. A sample cut from a larger one is not periodic: its faces differ
// as two unrelated layers do (about 2 porosity (1 - porosity)), far more
// than any neighbours inside; a periodic image's faces are neighbours like
// any others.
struct FaceMismatch {
  double faces = 0, inside = 0;
};
inline FaceMismatch face_mismatch(const VoxelImage& image, const std::vector<int>& solid_values, int axis) {
  const auto solid = solid_value_table(solid_values);
  const long long n = image.shape[axis];
  FaceMismatch result;
  if (n < 2) return result;
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const double layer = static_cast<double>(image.shape[a] * image.shape[b]);
  auto differing = [&](long long first, long long second) {
    long long count = 0;
    std::array<long long, 3> p{}, q{};
    for (long long ib = 0; ib < image.shape[b]; ++ib)
      for (long long ia = 0; ia < image.shape[a]; ++ia) {
        p[axis] = first, q[axis] = second;
        p[a] = q[a] = ia, p[b] = q[b] = ib;
        count += solid[image.at(p[0], p[1], p[2])] != solid[image.at(q[0], q[1], q[2])];
      }
    return count / layer;
  };
  result.faces = differing(0, n - 1);
  for (long long i = 0; i + 1 < n; ++i) result.inside = std::max(result.inside, differing(i, i + 1));
  return result;
}

}  // namespace poresph
