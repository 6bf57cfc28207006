#pragma once
// The DG preconditioner's last step: the wide Laplacian's cycle sharpened.
//
// On a lattice without grains the symbol of DG over the wide Laplacian's,
// rho(k), is 1 on smooth modes, and the pattern weights set it at the 2^Dim
// corners of the Brillouin zone; between the corners it falls steeply,
// because the SPH gradient averages across its direction over the kernel's
// support: along the diagonal k = (t, t, t) pi in 3D, rho is 0.18 at t = 0.4
// and 0.007 at t = 0.65 (perf/steady_study/dg_symbol.py). The wide
// Laplacian's inverse alone leaves those modes too small by as much. The
// sharpening multiplies the cycle's result by
//   prod_d (1 + beta sin^2(k_d / 2)),
// 1 on smooth modes and growing towards high wavenumbers in every direction
// at once, where rho falls: one three-point stencil per axis,
// (1 - beta/4 delta_d^2) with delta_d^2 the second difference along axis d,
// on the whole lattice, solid points held at zero (a Dirichlet wall, as
// the wide Laplacian's). Over the zone it narrows the spread of rho times
// the factor between its 1 % and 99 % quantiles from 1.1e4 to 320 in 3D at
// beta = 4, and from 160 to 28 in 2D at beta = 2 (h = dx); the steady solver
// takes the beta that measured fewest inner iterations (SteadySolver).
#include <array>
#include <utility>
#include <vector>

namespace poresph {

// values over the lattice of `shape` points (x fastest, periodic along every
// axis), 0 off the unknowns; active 1 on the points that hold an unknown and
// 0 elsewhere; scratch: a buffer (resized here). On return values holds the
// sharpened field, again 0 off the unknowns.
template <int Dim>
void sharpen_lattice(std::vector<float>& values, std::vector<float>& scratch, const std::array<int, Dim>& shape,
                     const std::vector<float>& active, double beta) {
  const float centre = static_cast<float>(1.0 + 0.5 * beta), side = static_cast<float>(-0.25 * beta);
  scratch.resize(values.size());
  // Along x (stride 1), by lines: the interior of a line in one loop the
  // compiler vectorises, its two ends (whose neighbours wrap around) apart.
  // The general loop below runs its innermost loop once a point there (3 %
  // of problem III's solve at 0.0025 L in perf record).
  const long long n0 = shape[0], lines = static_cast<long long>(values.size()) / n0;
  auto point = [&](long long at, long long below, long long above) {
    scratch[at] = active[at] * (centre * values[at] + side * (values[below] + values[above]));
  };
  float* __restrict__ out = scratch.data();
  const float* __restrict__ in = values.data();
  const float* __restrict__ mask = active.data();
  for (long long line = 0; line < lines; ++line) {
    const long long first = line * n0, last = first + n0 - 1;
    point(first, n0 == 1 ? first : last, n0 == 1 ? first : first + 1);
    for (long long at = first + 1; at < last; ++at)
      out[at] = mask[at] * (centre * in[at] + side * (in[at - 1] + in[at + 1]));
    if (n0 > 1) point(last, last - 1, first);
  }
  std::swap(values, scratch);
  long long stride = n0;  // between neighbours along axis d
  for (int d = 1; d < Dim; ++d) {
    const long long n = shape[d], block = n * stride, blocks = static_cast<long long>(values.size()) / block;
    for (long long b = 0; b < blocks; ++b)
      for (long long c = 0; c < n; ++c) {
        const long long at = b * block + c * stride;
        const long long below = b * block + (c == 0 ? n - 1 : c - 1) * stride;
        const long long above = b * block + (c == n - 1 ? 0 : c + 1) * stride;
        for (long long j = 0; j < stride; ++j)
          scratch[at + j] = active[at + j] * (centre * values[at + j] + side * (values[below + j] + values[above + j]));
      }
    std::swap(values, scratch);
    stride = block;
  }
}

}  // namespace poresph
