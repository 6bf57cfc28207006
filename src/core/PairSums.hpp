#pragma once
// Per-particle sums over neighbour pairs that both ends of a pair add to.
// The half neighbour list (core/NeighbourList.hpp) evaluates a pair once and
// adds to both particles, so two threads may add to the same particle at the
// same time. Each thread therefore adds into its own copy of the sums, picked
// by Kokkos's UniqueToken of global scope (the thread's id, a thread-local
// variable on OpenMP; 0 on Serial), and take() adds the copies up in a fixed
// order: no atomics, and the same sums bit for bit from run to run. Cost:
// copies x particles x components doubles, allocated when the particle count
// grows, never in a step; take() leaves each copy zero for the next loop.
//
// With the first copy in the rates (fixed particles, app/Simulation.cpp),
// that copy is the particles' own d rho/dt, dv/dt and wall drag, which the
// loop's finish overwrites anyway: a process of one thread then holds no
// array of its own (40 bytes a particle in 3D). Those rates are zeroed
// before a loop adds into them (clear_rates), and a loop that must leave
// them as they are adds nothing to fluid particles (PairLoopOptions::
// fluid_ends). The copies are summed in the same order either way.
#include <Kokkos_Core.hpp>

#include <cstddef>
#include <stdexcept>
#include <string>

namespace poresph {

template <int Dim, class ExecSpace>
class PairSums {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  // Global, not the default Instance scope: Kokkos 3.4's Instance token on
  // OpenMP asks the OpenMP runtime three times per acquire (omp_get_level,
  // omp_get_num_threads, omp_get_thread_num), once per particle here: about
  // a tenth of the step. Its size is the thread count Kokkos started with.
  using Token = Kokkos::Experimental::UniqueToken<ExecSpace, Kokkos::Experimental::UniqueTokenScope::Global>;

  // In 3D only. In 2D a particle's sums are one vector of four doubles,
  // and with them in the rates GCC contracts the pair loop's sums into
  // multiply-adds differently (problem III's k changed in its 14th digit);
  // 2D scenes keep sums of their own (32 bytes a particle).
  static constexpr bool kRatesAsFirstCopy = Dim == 3;

  PairSums() = default;
  // first_copy_in_rates (3D; ignored in 2D): components 0 (d rho/dt), 1 to Dim (dv/dt) and, if
  // there is one more, Dim + 1 (the wall drag) of the first copy are the
  // particles' drhodt, dvdt and wall_drag (with_rates).
  explicit PairSums(int components, bool first_copy_in_rates = false)
      : components_(components), in_rates_(kRatesAsFirstCopy && first_copy_in_rates) {
    if (kRatesAsFirstCopy && components > kMaxComponents) throw std::invalid_argument("PairSums: too many components");
  }

  bool first_copy_in_rates() const { return in_rates_; }

  // These sums with their first copy in P's rates (the Views P holds now;
  // a copy of the handles, taken again by each loop). Without
  // first_copy_in_rates, the sums as they are.
  template <class Particles>
  PairSums with_rates(const Particles& P) const {
    PairSums bound = *this;
    if (in_rates_) bound.drho_ = P.drhodt, bound.acceleration_ = P.dvdt, bound.own_ = P.wall_drag;
    bound.point_first_copy();
    return bound;
  }

  // Before a loop adds into the rates: components [0, count) of the first
  // copy zero for particles [0, n). Nothing without first_copy_in_rates
  // (the copies are zero already).
  void clear_rates(const ExecSpace& space, int n, int count) const {
    if (!in_rates_) return;
    const PairSums sums = *this;
    const int components = count < kMaxComponents ? count : kMaxComponents;
    static const std::string label = "poresph::PairSums::clear_rates";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space, 0, n), KOKKOS_LAMBDA(int i) {
          for (int c = 0; c < components; ++c) sums.at(0, i, c) = 0.0;
        });
  }

  // Room for particles [0, n); new room is zero. Outside the time loop's
  // steady state only: it allocates when n grows beyond the capacity, by a
  // quarter more with room_to_grow (moving particles migrate), else to n.
  void reserve(int n, bool room_to_grow = true) {
    if (n <= capacity_) return;
    capacity_ = room_to_grow ? n + n / 4 + 16 : n;
    // A fresh View, not Kokkos::resize: every slot in use is zero between loops.
    copies_ = token_.size();
    const int stored = in_rates_ ? copies_ - 1 : copies_;
    values_ = stored > 0 ? Values("PairSums", stored, capacity_, components_) : Values();
    point_first_copy();
  }

  // Inside a kernel: acquire a copy per particle visited, add, release.
  KOKKOS_INLINE_FUNCTION int acquire() const { return token_.acquire(); }
  KOKKOS_INLINE_FUNCTION void release(int copy) const { token_.release(copy); }
  KOKKOS_FORCEINLINE_FUNCTION void add(int copy, int i, int component, double value) const {
    at(copy, i, component) += value;
  }

  // After the loop: particle i's total of one component over the copies,
  // which are reset to zero.
  KOKKOS_INLINE_FUNCTION double take(int i, int component) const {
    double total = 0.0;
    for (int copy = 0; copy < copies_; ++copy) {
      double& value = at(copy, i, component);
      total += value;
      value = 0.0;
    }
    return total;
  }

 private:
  using Values = Kokkos::View<double***, Kokkos::LayoutRight, MemorySpace>;

  // In 3D the first copy is found through a start and a stride per
  // component (first_, stride_), in the rates or in values_ alike: no test
  // of the mode in the loop, which a branch per sum had slowed to 0.66 of
  // its speed (the simple cubic array at 40 a side), even where unused.
  KOKKOS_FORCEINLINE_FUNCTION double& at(int copy, int i, int component) const {
    if constexpr (kRatesAsFirstCopy) {
      if (copy == 0) return first_[component][static_cast<std::ptrdiff_t>(i) * stride_[component]];
      return values_(copy - (in_rates_ ? 1 : 0), i, component);
    } else {
      return values_(copy, i, component);
    }
  }

  // first_ and stride_ from the Views held now.
  void point_first_copy() {
    if constexpr (kRatesAsFirstCopy) {
      for (int c = 0; c < components_ && c < kMaxComponents; ++c) {
        if (!in_rates_) {
          first_[c] = values_.data() ? values_.data() + c : nullptr;
          stride_[c] = components_;
        } else if (c == 0) {
          first_[c] = drho_.data(), stride_[c] = 1;
        } else if (c <= Dim) {
          first_[c] = acceleration_.data() ? acceleration_.data() + (c - 1) * acceleration_.stride(1) : nullptr;
          stride_[c] = static_cast<std::ptrdiff_t>(acceleration_.stride(0));
        } else {
          first_[c] = own_.data(), stride_[c] = 1;
        }
      }
    }
  }

  Token token_;
  int components_ = 0;
  int copies_ = 0;
  int capacity_ = 0;
  bool in_rates_ = false;
  Values values_;
  // The first copy with first_copy_in_rates (with_rates).
  Kokkos::View<double*, MemorySpace> drho_, own_;
  Kokkos::View<double* [Dim], MemorySpace> acceleration_;
  // In 3D, where each component of the first copy begins, and the step
  // from one particle to the next (at, point_first_copy).
  // The most a scene's terms have: d rho/dt, dv/dt, the wall drag and the
  // shifting gradients (Dim + Dim^2).
  static constexpr int kMaxComponents = kRatesAsFirstCopy ? 2 + 2 * Dim + Dim * Dim : 1;
  double* first_[kMaxComponents] = {};
  std::ptrdiff_t stride_[kMaxComponents] = {};
};

}  // namespace poresph
