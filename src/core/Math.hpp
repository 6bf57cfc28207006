#pragma once
// Math functions callable in kernels: Kokkos 3.x keeps them in
// Kokkos::Experimental, Kokkos 4 in Kokkos.
#include <Kokkos_Core.hpp>

namespace poresph::math {
#if KOKKOS_VERSION >= 40000
using Kokkos::cos;
using Kokkos::exp;
using Kokkos::expm1;
using Kokkos::fabs;
using Kokkos::floor;
using Kokkos::sqrt;
#else
using Kokkos::Experimental::cos;
using Kokkos::Experimental::exp;
using Kokkos::Experimental::expm1;
using Kokkos::Experimental::fabs;
using Kokkos::Experimental::floor;
using Kokkos::Experimental::sqrt;
#endif
}  // namespace poresph::math
