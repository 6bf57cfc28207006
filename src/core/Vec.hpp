#pragma once
// A fixed-size vector for kernels: the dimension is a compile-time constant,
// so a 2D build carries two components and no branch on the dimension. Its
// operations are force-inlined: in a kernel as large as the pair loop
// (physics/PairDriver.hpp) GCC 12 otherwise leaves some as calls, and the
// vectors they return go through memory.
#include <Kokkos_Core.hpp>

namespace poresph {

template <int Dim>
struct Vec {
  double c[Dim];

  KOKKOS_FORCEINLINE_FUNCTION static Vec zero() {
    Vec r{};
    for (int d = 0; d < Dim; ++d) r.c[d] = 0.0;
    return r;
  }
  KOKKOS_FORCEINLINE_FUNCTION double& operator[](int d) { return c[d]; }
  KOKKOS_FORCEINLINE_FUNCTION double operator[](int d) const { return c[d]; }

  KOKKOS_FORCEINLINE_FUNCTION Vec& operator+=(const Vec& o) {
    for (int d = 0; d < Dim; ++d) c[d] += o.c[d];
    return *this;
  }
  KOKKOS_FORCEINLINE_FUNCTION Vec& operator-=(const Vec& o) {
    for (int d = 0; d < Dim; ++d) c[d] -= o.c[d];
    return *this;
  }
};

template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION Vec<Dim> operator+(Vec<Dim> a, const Vec<Dim>& b) { return a += b; }
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION Vec<Dim> operator-(Vec<Dim> a, const Vec<Dim>& b) { return a -= b; }
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION Vec<Dim> operator*(double s, Vec<Dim> a) {
  for (int d = 0; d < Dim; ++d) a.c[d] *= s;
  return a;
}
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION double dot(const Vec<Dim>& a, const Vec<Dim>& b) {
  double s = 0.0;
  for (int d = 0; d < Dim; ++d) s += a.c[d] * b.c[d];
  return s;
}

// Row i of an (n x Dim) View as a Vec.
template <int Dim, class View>
KOKKOS_FORCEINLINE_FUNCTION Vec<Dim> row(const View& v, int i) {
  Vec<Dim> r;
  for (int d = 0; d < Dim; ++d) r.c[d] = v(i, d);
  return r;
}
template <int Dim, class View>
KOKKOS_FORCEINLINE_FUNCTION void set_row(const View& v, int i, const Vec<Dim>& r) {
  for (int d = 0; d < Dim; ++d) v(i, d) = r.c[d];
}

// Angular quantities: about z in 2D (one component), a vector in 3D.
template <int Dim>
constexpr int spin_components() {
  return Dim == 2 ? 1 : 3;
}

// omega x r.
template <int Dim>
KOKKOS_INLINE_FUNCTION void spin_cross(const double* omega, const double* r, double* out) {
  if constexpr (Dim == 2) {
    out[0] = -omega[0] * r[1];
    out[1] = omega[0] * r[0];
  } else {
    out[0] = omega[1] * r[2] - omega[2] * r[1];
    out[1] = omega[2] * r[0] - omega[0] * r[2];
    out[2] = omega[0] * r[1] - omega[1] * r[0];
  }
}

// r x F: the torque (one component about z in 2D).
template <int Dim>
KOKKOS_INLINE_FUNCTION void moment_of(const double* r, const double* F, double* out) {
  if constexpr (Dim == 2) {
    out[0] = r[0] * F[1] - r[1] * F[0];
  } else {
    out[0] = r[1] * F[2] - r[2] * F[1];
    out[1] = r[2] * F[0] - r[0] * F[2];
    out[2] = r[0] * F[1] - r[1] * F[0];
  }
}

}  // namespace poresph
