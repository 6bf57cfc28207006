#pragma once
// The execution spaces typed tests run on (Cabana-style per-backend tests).
#include <Kokkos_Core.hpp>
#include <gtest/gtest.h>

namespace poresph::testing {
#ifdef KOKKOS_ENABLE_OPENMP
using ExecutionSpaces = ::testing::Types<Kokkos::Serial, Kokkos::OpenMP>;
#else
using ExecutionSpaces = ::testing::Types<Kokkos::Serial>;
#endif
}  // namespace poresph::testing
