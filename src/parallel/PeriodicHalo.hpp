#pragma once
// Periodic images on one process, made the way the paper's parallel
// algorithm makes ghosts (section 5): first every particle within the
// support width of a face in x is copied to the other side, then in y,
// copying also what the x stage made (that is how corners arrive), then z.
// The shift travels with each copy. This is the exchange a process that spans
// a whole periodic direction does with itself.
#include <Kokkos_Core.hpp>

#include <array>
#include <sstream>
#include <stdexcept>

#include "core/Particles.hpp"
#include "core/Vec.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
class PeriodicHalo {
 public:
  using MemorySpace = typename ExecSpace::memory_space;

  PeriodicHalo() = default;
  PeriodicHalo(const Vec<Dim>& lo, const Vec<Dim>& hi, const std::array<bool, Dim>& periodic, double width)
      : lo_(lo), hi_(hi), periodic_(periodic), width_(width) {
    for (int d = 0; d < Dim; ++d) {
      // One image per side is enough only if the cell is at least as wide as the support.
      if (periodic_[d] && hi_[d] - lo_[d] < width_) {
        std::ostringstream msg;
        msg << "periodic cell side " << d << " (" << hi_[d] - lo_[d]
            << ") is narrower than the kernel support 3h (" << width_ << ")";
        throw std::invalid_argument(msg.str());
      }
    }
  }

  // Puts owned particles that left the cell through a periodic face back in.
  void wrap(const ExecSpace& space, const Particles<Dim, MemorySpace>& P) const {
    const auto x = P.x;
    const auto lo = lo_, hi = hi_;
    const auto periodic = periodic_;
    Kokkos::parallel_for(
        "poresph::PeriodicHalo::wrap", Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned),
        KOKKOS_LAMBDA(int i) {
          for (int d = 0; d < Dim; ++d) {
            if (!periodic[d]) continue;
            x(i, d) = wrap_coordinate(x(i, d), lo[d], hi[d]);
          }
        });
  }

  // Replaces all ghosts by fresh images of the current particles.
  void build(const ExecSpace& space, Particles<Dim, MemorySpace>& P) const {
    P.ghosts = 0;
    for (int d = 0; d < Dim; ++d) {
      if (!periodic_[d]) continue;
      const int sources = P.total();
      const double low_face = lo_[d] + width_, high_face = hi_[d] - width_;
      const double length = hi_[d] - lo_[d];
      int images = 0;
      {
        const auto x = P.x;
        Kokkos::parallel_reduce(
            "poresph::PeriodicHalo::count", Kokkos::RangePolicy<ExecSpace>(space, 0, sources),
            KOKKOS_LAMBDA(int i, int& n) { n += (x(i, d) < low_face) + (x(i, d) >= high_face); }, images);
      }
      P.reserve(sources + images);
      const auto Q = P;  // views after any growth
      Kokkos::parallel_scan(
          "poresph::PeriodicHalo::copy", Kokkos::RangePolicy<ExecSpace>(space, 0, sources),
          KOKKOS_LAMBDA(int i, int& offset, bool final) {
            const bool near_low = Q.x(i, d) < low_face, near_high = Q.x(i, d) >= high_face;
            if (final) {
              double shift[Dim] = {};
              int slot = sources + offset;
              if (near_low) {
                shift[d] = length;
                copy_as_ghost(Q, i, slot++, shift);
              }
              if (near_high) {
                shift[d] = -length;
                copy_as_ghost(Q, i, slot, shift);
              }
            }
            offset += near_low + near_high;
          });
      P.ghosts += images;
    }
    space.fence();
  }

  // Maps a coordinate into [lo, hi); robust to the rounding of x + length.
  KOKKOS_INLINE_FUNCTION static double wrap_coordinate(double x, double lo, double hi) {
    const double length = hi - lo;
    if (x >= hi) x -= length;
    else if (x < lo) {
      x += length;
      if (x >= hi) x = lo;
    }
    return x;
  }

 private:
  Vec<Dim> lo_{}, hi_{};
  std::array<bool, Dim> periodic_{};
  double width_ = 0.0;
};

}  // namespace poresph
