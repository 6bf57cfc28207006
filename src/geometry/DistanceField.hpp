#pragma once
// A segmented image's solid as a signed distance, positive in the pore and
// negative in the solid: sampled at voxel centres (surface_distance in
// geometry/DistanceTransform.hpp) and read anywhere in the cell by trilinear
// interpolation, on the host (the lattice, the checks) and in kernels (the
// gridded output, fluid kept out of the solid). It is the image's
// counterpart of a grain's |x - c| - r.
#include <Kokkos_Core.hpp>

#include <array>
#include <memory>
#include <vector>

#include "core/Math.hpp"

namespace poresph {

template <int Dim, class MemorySpace>
struct DistanceField {
  Kokkos::View<const float*, MemorySpace> values;  // at voxel centres, x fastest
  long long shape[Dim] = {};
  // The cell's voxel of values' voxel 0, where a process holds only its
  // piece of the image (0: the whole). A point's voxel is found in the
  // cell's frame and then shifted, so that a piece reads the same bits.
  long long first[Dim] = {};
  double voxel_size = 0;
  bool periodic[Dim] = {};

  bool empty() const { return values.extent(0) == 0; }

  KOKKOS_INLINE_FUNCTION double value(const double* x) const {
    long long lower[Dim];
    double t[Dim];
    for (int d = 0; d < Dim; ++d) {
      const double u = x[d] / voxel_size - 0.5;  // voxel centres at whole u
      const double below = math::floor(u);
      lower[d] = static_cast<long long>(below);
      t[d] = u - below;
    }
    double sum = 0;
    for (int corner = 0; corner < (1 << Dim); ++corner) {
      long long index = 0;
      double weight = 1;
      for (int d = Dim - 1; d >= 0; --d) {
        const int up = (corner >> d) & 1;
        long long i = lower[d] + up - first[d];
        if (periodic[d]) {
          i %= shape[d];
          if (i < 0) i += shape[d];
        } else {
          i = i < 0 ? 0 : i >= shape[d] ? shape[d] - 1 : i;  // beyond the outer voxels: theirs
        }
        index = index * shape[d] + i;
        weight *= up ? t[d] : 1 - t[d];
      }
      sum += weight * values(index);
    }
    return sum;
  }

  // The unit normal into the pore at x: the distance's gradient by central
  // differences kNormalStep voxels either side. The voxels' staircase still
  // tilts a narrower difference: with one or two voxels, normals of boundary
  // particles of a disk of radius 54 voxels stray more than 4 degrees from
  // radial, with four none do (tests/test_image_solid.cpp).
  static constexpr double kNormalStep = 4;
  KOKKOS_INLINE_FUNCTION void normal(const double* x, double* n) const {
    const double step = kNormalStep * voxel_size;
    double y[Dim], length_sq = 0;
    for (int d = 0; d < Dim; ++d) y[d] = x[d];
    for (int d = 0; d < Dim; ++d) {
      y[d] = x[d] + step;
      const double above = value(y);
      y[d] = x[d] - step;
      n[d] = above - value(y);
      y[d] = x[d];
      length_sq += n[d] * n[d];
    }
    const double length = math::sqrt(length_sq);
    for (int d = 0; d < Dim; ++d) n[d] = length > 0 ? n[d] / length : 0.0;
  }
};

// The field over `values` (kept alive by the caller), for host code.
template <int Dim>
DistanceField<Dim, Kokkos::HostSpace> host_distance_field(const std::vector<float>& values,
                                                          const std::array<long long, 3>& shape, double voxel_size,
                                                          const std::array<bool, 3>& periodic,
                                                          const std::array<long long, 3>& first = {}) {
  DistanceField<Dim, Kokkos::HostSpace> field;
  field.values = Kokkos::View<const float*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>(
      values.data(), values.size());
  for (int d = 0; d < Dim; ++d) field.shape[d] = shape[d], field.periodic[d] = periodic[d], field.first[d] = first[d];
  field.voxel_size = voxel_size;
  return field;
}

// The same field copied to MemorySpace, for kernels.
template <int Dim, class MemorySpace>
DistanceField<Dim, MemorySpace> device_distance_field(const std::vector<float>& values,
                                                      const std::array<long long, 3>& shape, double voxel_size,
                                                      const std::array<bool, 3>& periodic,
                                                      const std::array<long long, 3>& first = {}) {
  const auto host = host_distance_field<Dim>(values, shape, voxel_size, periodic, first);
  DistanceField<Dim, MemorySpace> field;
  Kokkos::View<float*, MemorySpace> copy("image_distance", values.size());
  Kokkos::deep_copy(copy, Kokkos::View<const float*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>(
                              values.data(), values.size()));
  field.values = copy;
  for (int d = 0; d < Dim; ++d)
    field.shape[d] = host.shape[d], field.periodic[d] = host.periodic[d], field.first[d] = host.first[d];
  field.voxel_size = voxel_size;
  return field;
}

}  // namespace poresph
