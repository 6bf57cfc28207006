#pragma once
// Surface tension between two fluid phases on fixed particles: the
// continuum surface force sigma kappa n / rho of Morris (2000), "Simulating
// surface tension with smoothed particle hydrodynamics" (also Adami, Hu &
// Adams 2010, J. Comput. Phys. 229, 5011), with n the SPH gradient of a
// colour function c and kappa = -div(n / |n|).
//
// Fixed particles never change phase, so c, n and kappa are functions of
// the scene alone: this file computes them once, at set-up, for the owned
// particles of a periodic lattice, and the step adds the result like a
// body force (app/Simulation.cpp). It evaluates the colour of any lattice
// point it needs through the caller's function of the point's index
// (periodic images included), on a block of the lattice around the owned
// points: no ghosts, the same values on any number of processes.
//
// The choices, measured on the 2D drop (docs/method.md, perf/laplace_model.py):
// - the force's normal n_h is the colour gradient with the flow's kernel h,
//   the operator the pressure term applies to p: a uniform kappa is then
//   balanced by the pressure exactly, and only kappa's variation along the
//   interface drives currents;
// - kappa is taken from normals of a kernel twice as wide (h_c = 2h) and
//   the filter |n| > 0.01 / h_c (Morris's epsilon = 0.01 / h: it drops the
//   particles at the edge of the colour's transition, whose normal is the
//   ratio of two round-off-sized numbers);
// - kappa is then averaged over a kernel of h_s = 6h weighted by |n|
//   (a particle of the interface counts by how much colour changes there):
//   a lattice interface is a staircase, and the curvature of one particle
//   follows the stairs, not the surface they approximate.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/Kernel.hpp"
#include "core/Vec.hpp"
#include "physics/PairTerms.hpp"

namespace poresph {

constexpr double kCurvatureKernelRatio = 2.0;    // h_c / h
constexpr double kNormalFilter = 0.01;           // |n| h_c above which a normal counts (Morris's epsilon h)
constexpr double kCurvatureSmoothingRatio = 6.0; // h_s / h

// What set-up computes at each owned point: the force's normal n_h, the
// curvature kappa at the point (0 where its normal is filtered out) and
// the curvature averaged along the interface, which the force takes.
template <int Dim>
struct InterfacePoint {
  Vec<Dim> normal;
  double curvature = 0;
  double smoothed_curvature = 0;
};

namespace surface_detail {

template <int Dim>
struct Stencil {
  std::vector<std::array<long long, Dim>> offsets;  // lattice offsets b - a within the support, 0 excluded
  std::vector<Vec<Dim>> r;                          // x_a - x_b
  std::vector<double> F, W;                         // (1/r) dW/dr and W
  double W0 = 0;
  long long reach = 0;                              // largest |offset| along an axis
};

template <int Dim>
Stencil<Dim> stencil(double h, double dx) {
  const QuinticKernel<Dim> kernel(h);
  Stencil<Dim> s;
  s.reach = static_cast<long long>(std::ceil(kernel.cutoff / dx));
  s.W0 = kernel.value(0.0);
  const long long width = 2 * s.reach + 1;
  long long total = 1;
  for (int d = 0; d < Dim; ++d) total *= width;
  for (long long k = 0; k < total; ++k) {
    std::array<long long, Dim> o{};
    long long rest = k;
    double r2 = 0;
    for (int d = 0; d < Dim; ++d, rest /= width) o[d] = rest % width - s.reach, r2 += double(o[d] * o[d]) * dx * dx;
    const double r = std::sqrt(r2);
    if (r == 0 || !(r < kernel.cutoff)) continue;
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) x[d] = -static_cast<double>(o[d]) * dx;
    s.offsets.push_back(o);
    s.r.push_back(x);
    s.F.push_back(kernel.derivative_over_r(r));
    s.W.push_back(kernel.value(r));
  }
  return s;
}

// A block of the lattice, [first, first + count) per axis, row-major.
template <int Dim>
struct Block {
  std::array<long long, Dim> first{}, count{};
  std::size_t size() const {
    std::size_t n = 1;
    for (int d = 0; d < Dim; ++d) n *= static_cast<std::size_t>(count[d]);
    return n;
  }
  std::size_t index(const std::array<long long, Dim>& i) const {
    std::size_t k = 0;
    for (int d = 0; d < Dim; ++d) k = k * count[d] + static_cast<std::size_t>(i[d] - first[d]);
    return k;
  }
  std::array<long long, Dim> point(std::size_t k) const {
    std::array<long long, Dim> i{};
    for (int d = Dim - 1; d >= 0; --d) i[d] = first[d] + static_cast<long long>(k % count[d]), k /= count[d];
    return i;
  }
  // Whether i lies at least margin inside the block.
  bool holds(const std::array<long long, Dim>& i, long long margin) const {
    for (int d = 0; d < Dim; ++d)
      if (i[d] < first[d] + margin || i[d] >= first[d] + count[d] - margin) return false;
    return true;
  }
};

template <int Dim>
std::array<long long, Dim> plus(std::array<long long, Dim> a, const std::array<long long, Dim>& b) {
  for (int d = 0; d < Dim; ++d) a[d] += b[d];
  return a;
}

// Whether the colour is the same over the box of half-width reach about
// each point (then every colour gradient there is zero): a separable
// running minimum and maximum.
template <int Dim>
std::vector<char> uniform_about(const Block<Dim>& block, const std::vector<double>& c, long long reach) {
  std::vector<double> lo = c, hi = c;
  for (int axis = 0; axis < Dim; ++axis) {
    std::vector<double> lo_next = lo, hi_next = hi;
    std::size_t stride = 1;
    for (int d = Dim - 1; d > axis; --d) stride *= static_cast<std::size_t>(block.count[d]);
    for (std::size_t k = 0; k < c.size(); ++k) {
      const long long at = block.point(k)[axis] - block.first[axis];
      for (long long s = -reach; s <= reach; ++s) {
        if (s == 0 || at + s < 0 || at + s >= block.count[axis]) continue;
        const std::size_t j = static_cast<std::size_t>(static_cast<long long>(k) + s * static_cast<long long>(stride));
        lo_next[k] = std::min(lo_next[k], lo[j]), hi_next[k] = std::max(hi_next[k], hi[j]);
      }
    }
    lo.swap(lo_next), hi.swap(hi_next);
  }
  std::vector<char> uniform(c.size());
  for (std::size_t k = 0; k < c.size(); ++k) uniform[k] = lo[k] == hi[k];
  return uniform;
}

}  // namespace surface_detail

// The interface's normal and curvature at each of `points` (lattice
// indices, each in [0, cells[d])) of a lattice of spacing dx periodic with
// cells[d] points along each axis, whose colour at a point is colour(i)
// (i wrapped into the lattice). h: the flow's smoothing length.
template <int Dim, class Colour>
std::vector<InterfacePoint<Dim>> interface_geometry(const std::vector<std::array<long long, Dim>>& points,
                                                    const std::array<long long, Dim>& cells, double dx, double h,
                                                    const Colour& colour) {
  using namespace surface_detail;
  std::vector<InterfacePoint<Dim>> result(points.size());
  if (points.empty()) return result;
  const Stencil<Dim> flow = stencil<Dim>(h, dx), wide = stencil<Dim>(kCurvatureKernelRatio * h, dx),
                     smooth = stencil<Dim>(kCurvatureSmoothingRatio * h, dx);
  double V = 1;
  for (int d = 0; d < Dim; ++d) V *= dx;
  // kappa is wanted within smooth.reach of a point, the wide normals within
  // wide.reach of those, the colour within wide.reach of these.
  const long long margin = smooth.reach + 2 * wide.reach;
  Block<Dim> block;
  for (int d = 0; d < Dim; ++d) {
    long long lo = points[0][d], hi = points[0][d];
    for (const auto& p : points) lo = std::min(lo, p[d]), hi = std::max(hi, p[d]);
    block.first[d] = lo - margin;
    block.count[d] = hi - lo + 1 + 2 * margin;
  }
  const std::size_t size = block.size();
  std::vector<double> c(size);
  for (std::size_t k = 0; k < size; ++k) {
    auto i = block.point(k);
    for (int d = 0; d < Dim; ++d) i[d] = ((i[d] % cells[d]) + cells[d]) % cells[d];
    c[k] = colour(i);
  }
  const std::vector<char> uniform = uniform_about<Dim>(block, c, wide.reach);
  // The wide normals and Morris's filter.
  std::vector<Vec<Dim>> unit(size, Vec<Dim>::zero());
  std::vector<double> length(size, 0.0);
  const double least = kNormalFilter / (kCurvatureKernelRatio * h);
  for (std::size_t k = 0; k < size; ++k) {
    const auto i = block.point(k);
    if (uniform[k] || !block.holds(i, wide.reach)) continue;
    Vec<Dim> n = Vec<Dim>::zero();
    for (std::size_t s = 0; s < wide.offsets.size(); ++s)
      n += colour_gradient_share<Dim>(V, c[k], c[block.index(plus<Dim>(i, wide.offsets[s]))], wide.r[s], wide.F[s]);
    const double norm = std::sqrt(dot(n, n));
    if (!(norm > least)) continue;
    length[k] = norm;
    unit[k] = (1.0 / norm) * n;
  }
  // kappa where the normal counts: its divergence over the neighbours whose normal counts.
  std::vector<double> kappa(size, 0.0);
  for (std::size_t k = 0; k < size; ++k) {
    const auto i = block.point(k);
    if (length[k] == 0 || !block.holds(i, 2 * wide.reach)) continue;
    double divergence = 0, shepard = V * wide.W0;
    for (std::size_t s = 0; s < wide.offsets.size(); ++s) {
      const std::size_t b = block.index(plus<Dim>(i, wide.offsets[s]));
      if (length[b] == 0) continue;
      divergence += normal_divergence_share<Dim>(V, unit[k], unit[b], wide.r[s], wide.F[s]);
      shepard += V * wide.W[s];
    }
    kappa[k] = curvature_from_sums(divergence, shepard);
  }
  for (std::size_t a = 0; a < points.size(); ++a) {
    const auto& i = points[a];
    const std::size_t k = block.index(i);
    InterfacePoint<Dim>& out = result[a];
    out.normal = Vec<Dim>::zero();
    for (std::size_t s = 0; s < flow.offsets.size(); ++s)
      out.normal += colour_gradient_share<Dim>(V, c[k], c[block.index(plus<Dim>(i, flow.offsets[s]))], flow.r[s],
                                               flow.F[s]);
    out.curvature = kappa[k];
    if (dot(out.normal, out.normal) == 0) continue;
    double sum = V * smooth.W0 * length[k] * kappa[k], weight = V * smooth.W0 * length[k];
    for (std::size_t s = 0; s < smooth.offsets.size(); ++s) {
      const std::size_t b = block.index(plus<Dim>(i, smooth.offsets[s]));
      if (length[b] == 0) continue;
      sum += V * smooth.W[s] * length[b] * kappa[b], weight += V * smooth.W[s] * length[b];
    }
    out.smoothed_curvature = weight > 0 ? sum / weight : 0.0;
  }
  return result;
}

}  // namespace poresph
