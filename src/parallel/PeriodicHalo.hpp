#pragma once
// Periodic images on one process, made the way the paper's parallel
// algorithm makes ghosts (section 5): first every particle within the
// support width of a face in x is copied to the other side, then in y,
// copying also what the x stage made (that is how corners arrive), then z.
// The shift travels with each copy. This is the exchange a process that spans
// a whole periodic direction does with itself.
//
// build() makes the ghosts (after positions were wrapped into the cell);
// update() refreshes their fields in place between builds, from the owned
// particle each ghost images and the total shift it carries, so that
// neighbour lists built over the ghosts stay valid.
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
  // The start-of-step position moves with the particle: a wrap in the middle
  // of a step must not be undone by the corrector.
  void wrap(const ExecSpace& space, const Particles<Dim, MemorySpace>& P) const {
    const auto x = P.x, x_start = P.x_start;
    const auto lo = lo_, hi = hi_;
    const auto periodic = periodic_;
    Kokkos::parallel_for(
        "poresph::PeriodicHalo::wrap", Kokkos::RangePolicy<ExecSpace>(space, 0, P.owned),
        KOKKOS_LAMBDA(int i) {
          for (int d = 0; d < Dim; ++d) {
            if (!periodic[d]) continue;
            const double wrapped = wrap_coordinate(x(i, d), lo[d], hi[d]);
            x_start(i, d) += wrapped - x(i, d);
            x(i, d) = wrapped;
          }
        });
  }

  // Replaces all ghosts by fresh images of the current particles.
  void build(const ExecSpace& space, Particles<Dim, MemorySpace>& P) {
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
      if (static_cast<int>(root_.extent(0)) < sources + images - P.owned) {
        Kokkos::resize(root_, sources + images - P.owned + 64);
        Kokkos::resize(shift_, sources + images - P.owned + 64);
      }
      const auto Q = P;  // views after any growth
      const auto root = root_;
      const auto total_shift = shift_;
      const int owned = P.owned;
      Kokkos::parallel_scan(
          "poresph::PeriodicHalo::copy", Kokkos::RangePolicy<ExecSpace>(space, 0, sources),
          KOKKOS_LAMBDA(int i, int& offset, bool final) {
            const bool near_low = Q.x(i, d) < low_face, near_high = Q.x(i, d) >= high_face;
            if (final) {
              int slot = sources + offset;
              for (int side = 0; side < 2; ++side) {
                if (!(side == 0 ? near_low : near_high)) continue;
                double shift[Dim] = {};
                shift[d] = side == 0 ? length : -length;
                copy_as_ghost(Q, i, slot, shift);
                // Ghosts of ghosts (corners) record the owned particle and the summed shift.
                const int g = slot - owned;
                root(g) = i < owned ? i : root(i - owned);
                for (int e = 0; e < Dim; ++e) total_shift(g, e) = (i < owned ? 0.0 : total_shift(i - owned, e)) + shift[e];
                ++slot;
              }
            }
            offset += near_low + near_high;
          });
      P.ghosts += images;
    }
    space.fence();
  }

  // Copies position (shifted), velocity, density and pressure fields of every ghost's
  // owned particle into the ghost; the set of ghosts stays as built.
  void update(const ExecSpace& space, const Particles<Dim, MemorySpace>& P) const {
    const auto Q = P;
    const auto root = root_;
    const auto total_shift = shift_;
    const int owned = P.owned;
    Kokkos::parallel_for(
        "poresph::PeriodicHalo::update", Kokkos::RangePolicy<ExecSpace>(space, owned, P.total()),
        KOKKOS_LAMBDA(int slot) {
          const int g = slot - owned, from = root(g);
          for (int d = 0; d < Dim; ++d) {
            Q.x(slot, d) = Q.x(from, d) + total_shift(g, d);
            Q.v(slot, d) = Q.v(from, d);
          }
          Q.rho(slot) = Q.rho(from);
          Q.p(slot) = Q.p(from);
          Q.pressure_term(slot) = Q.pressure_term(from);
          Q.inverse_density(slot) = Q.inverse_density(from);
        });
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
  Kokkos::View<int*, MemorySpace> root_{"PeriodicHalo::root", 0};              // owned particle a ghost images
  Kokkos::View<double* [Dim], MemorySpace> shift_{"PeriodicHalo::shift", 0};  // and the shift it carries
};

}  // namespace poresph
