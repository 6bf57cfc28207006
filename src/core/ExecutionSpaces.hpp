#pragma once
// The execution spaces this Kokkos build has. Code templated on the space is
// instantiated for each through PORESPH_FOR_EACH_EXECUTION_SPACE, and tests
// run on each: Serial always, OpenMP where Kokkos was built with it.
//
// Kernel labels are function-local `static const std::string`s: Kokkos takes
// the label as a std::string, and one built from a literal longer than the
// small-string buffer would allocate at every launch of every step.
#include <Kokkos_Core.hpp>

#include <string>

#ifdef KOKKOS_ENABLE_OPENMP
#define PORESPH_FOR_EACH_EXECUTION_SPACE(MACRO) MACRO(Kokkos::Serial) MACRO(Kokkos::OpenMP)
#else
#define PORESPH_FOR_EACH_EXECUTION_SPACE(MACRO) MACRO(Kokkos::Serial)
#endif

namespace poresph {

template <class ExecSpace>
std::string backend_name() {
  return ExecSpace::name();
}

}  // namespace poresph
