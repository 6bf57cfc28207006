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
#include <Kokkos_Core.hpp>

namespace poresph {

template <class ExecSpace>
class PairSums {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  // Global, not the default Instance scope: Kokkos 3.4's Instance token on
  // OpenMP asks the OpenMP runtime three times per acquire (omp_get_level,
  // omp_get_num_threads, omp_get_thread_num), once per particle here: about
  // a tenth of the step. Its size is the thread count Kokkos started with.
  using Token = Kokkos::Experimental::UniqueToken<ExecSpace, Kokkos::Experimental::UniqueTokenScope::Global>;

  PairSums() = default;
  explicit PairSums(int components) : components_(components) {}

  // Room for particles [0, n); new room is zero. Outside the time loop's
  // steady state only: it allocates when n grows beyond the capacity, by a
  // quarter more with room_to_grow (moving particles migrate), else to n.
  void reserve(int n, bool room_to_grow = true) {
    if (n <= capacity_) return;
    capacity_ = room_to_grow ? n + n / 4 + 16 : n;
    // A fresh View, not Kokkos::resize: every slot in use is zero between loops.
    copies_ = token_.size();
    values_ = Kokkos::View<double***, Kokkos::LayoutRight, MemorySpace>("PairSums", copies_, capacity_, components_);
  }

  // Inside a kernel: acquire a copy per particle visited, add, release.
  KOKKOS_INLINE_FUNCTION int acquire() const { return token_.acquire(); }
  KOKKOS_INLINE_FUNCTION void release(int copy) const { token_.release(copy); }
  KOKKOS_INLINE_FUNCTION void add(int copy, int i, int component, double value) const {
    values_(copy, i, component) += value;
  }

  // After the loop: particle i's total of one component over the copies,
  // which are reset to zero.
  KOKKOS_INLINE_FUNCTION double take(int i, int component) const {
    double total = 0.0;
    for (int copy = 0; copy < copies_; ++copy) {
      total += values_(copy, i, component);
      values_(copy, i, component) = 0.0;
    }
    return total;
  }

 private:
  Token token_;
  int components_ = 0;
  int copies_ = 0;
  int capacity_ = 0;
  Kokkos::View<double***, Kokkos::LayoutRight, MemorySpace> values_;
};

}  // namespace poresph
