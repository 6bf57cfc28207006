#pragma once
// The gridded view porous-media users ask for: velocity and pressure at the
// nodes of a regular grid of the cell, interpolated from the fluid particles
// with the SPH kernel and Shepard's normalisation,
//   f(x) = sum_j (m_j/rho_j) f_j W(x - x_j) / sum_j (m_j/rho_j) W(x - x_j),
// which keeps a uniform field exact next to grains, where the kernel support
// is only partly filled with fluid. Nodes inside the solid are solid: zero
// velocity and pressure, and solid = 1.
#include <Kokkos_Core.hpp>

#include "core/CellList.hpp"
#include "core/Kernel.hpp"
#include "core/Math.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"
#include "geometry/Solid.hpp"

namespace poresph {

// This process's block of a grid with nodes at (i + 1/2) spacing along each
// direction: nodes first .. first + count - 1, x fastest.
template <int Dim>
struct GridBlock {
  long long first[Dim] = {};
  long long count[Dim] = {};
  double spacing[Dim] = {};
  long long nodes() const {
    long long n = 1;
    for (int d = 0; d < Dim; ++d) n *= count[d];
    return n;
  }
  KOKKOS_INLINE_FUNCTION Vec<Dim> position(long long node) const {
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) {
      x[d] = (first[d] + node % count[d] + 0.5) * spacing[d];
      node /= count[d];
    }
    return x;
  }
};

// Shepard's interpolation of the fluid particles' velocity and pressure
// above rest_pressure at x, written to velocity[0..Dim) and pressure;
// returns false (and leaves them alone) where no fluid is within reach.
template <int Dim, class ParticleArrays, class Cells>
KOKKOS_INLINE_FUNCTION bool shepard_fluid_at(const ParticleArrays& Q, const Cells& cells,
                                             const QuinticKernel<Dim>& kernel, const Vec<Dim>& x,
                                             double rest_pressure, double* velocity, double& pressure) {
  double weight_sum = 0, velocity_sum[Dim] = {}, pressure_sum = 0;
  cells.for_each_candidate(x, [&](int j) {
    if (Q.kind(j) != kFluid) return;
    double r_sq = 0;
    for (int d = 0; d < Dim; ++d) r_sq += (x[d] - Q.x(j, d)) * (x[d] - Q.x(j, d));
    if (r_sq >= kernel.cutoff_sq) return;
    const double w = Q.m(j) / Q.rho(j) * kernel.value(math::sqrt(r_sq));
    weight_sum += w;
    for (int d = 0; d < Dim; ++d) velocity_sum[d] += w * Q.v(j, d);
    pressure_sum += w * (Q.p(j) - rest_pressure);
  });
  if (weight_sum <= 0) return false;
  for (int d = 0; d < Dim; ++d) velocity[d] = velocity_sum[d] / weight_sum;
  pressure = pressure_sum / weight_sum;
  return true;
}

// Columns of `values` per node: velocity (Dim), pressure, solid.
template <int Dim, class ExecSpace>
void interpolate_to_grid(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                         const CellList<Dim, ExecSpace>& cells, const QuinticKernel<Dim>& kernel,
                         const SolidMap<Dim, typename ExecSpace::memory_space>& solid, const GridBlock<Dim>& block,
                         const Kokkos::View<double**, typename ExecSpace::memory_space>& values) {
  const auto Q = P;
  const bool has_solid = !solid.empty();
  static const std::string label_interpolate_to_grid = "poresph::interpolate_to_grid";
  Kokkos::parallel_for(
      label_interpolate_to_grid, Kokkos::RangePolicy<ExecSpace>(space, 0, block.nodes()),
      KOKKOS_LAMBDA(long long node) {
        const Vec<Dim> x = block.position(node);
        for (int c = 0; c < Dim + 2; ++c) values(node, c) = 0.0;
        double depth, normal[Dim];
        if (has_solid && solid.deepest(x.c, depth, normal) >= 0) {
          values(node, Dim + 1) = 1.0;
          return;
        }
        double velocity[Dim], pressure;
        if (!shepard_fluid_at<Dim>(Q, cells, kernel, x, 0.0, velocity, pressure)) return;
        for (int d = 0; d < Dim; ++d) values(node, d) = velocity[d];
        values(node, Dim) = pressure;
      });
}

// The same Shepard interpolation of the fluid's velocity and pressure at n
// arbitrary points (a finer level's particles, Simulation::warm_start), the
// pressure as p - rest_pressure; a point without fluid in reach gets zeros.
// Columns of `values`: velocity (Dim), pressure.
template <int Dim, class ExecSpace, class PointView>
void interpolate_fluid_at(const ExecSpace& space, const Particles<Dim, typename ExecSpace::memory_space>& P,
                          const CellList<Dim, ExecSpace>& cells, const QuinticKernel<Dim>& kernel,
                          const PointView& points, int n, double rest_pressure,
                          const Kokkos::View<double**, typename ExecSpace::memory_space>& values) {
  const auto Q = P;
  static const std::string label = "poresph::interpolate_fluid_at";
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(space, 0, n), KOKKOS_LAMBDA(int i) {
        double velocity[Dim] = {}, pressure = 0;  // zeros where no fluid is in reach
        shepard_fluid_at<Dim>(Q, cells, kernel, row<Dim>(points, i), rest_pressure, velocity, pressure);
        for (int d = 0; d < Dim; ++d) values(i, d) = velocity[d];
        values(i, Dim) = pressure;
      });
}

}  // namespace poresph
