// The time loop allocates nothing: once the particle arrays, the halo
// buffers and the lists have grown to size, a step (neighbour-list rebuilds
// and ghost exchanges included) makes no heap allocation and no Kokkos
// allocation. Counted by replacing the global operator new and through the
// Kokkos Tools allocation callback. CTest runs this on 1 and 2 ranks.
#include <Kokkos_Core.hpp>
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "Scenes.hpp"
#include "app/Simulation.hpp"
#include "geometry/Grains.hpp"

namespace {
std::atomic<long long> heap_allocations{0};
std::atomic<long long> kokkos_allocations{0};
}  // namespace

// Not inlined: where GCC inlines both the replaced new and delete into a
// caller it pairs the malloc with a free behind an operator new and warns
// of a mismatch (-Wmismatched-new-delete) that the replacement makes right.
[[gnu::noinline]] void* operator new(std::size_t size) {
  ++heap_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
[[gnu::noinline]] void* operator new[](std::size_t size) { return operator new(size); }
[[gnu::noinline]] void operator delete(void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace poresph {
namespace {

extern "C" void count_kokkos_allocation(Kokkos_Profiling_SpaceHandle, const char*, const void*, uint64_t) {
  ++kokkos_allocations;
}
extern "C" void no_op_init(int, uint64_t, uint32_t, Kokkos_Profiling_KokkosPDeviceInfo*) {}

// Steps `warm_up` times, then counts allocations over `steps` more steps.
template <class Sim>
void expect_allocation_free_steps(Sim& sim, int warm_up, int steps, bool moving = true) {
  for (int s = 0; s < warm_up; ++s) sim.step();
  const long long rebuilds_before = sim.neighbour_rebuilds();
  // Kokkos 3.4 calls the tools only when an init callback is registered.
  Kokkos::Tools::Experimental::set_init_callback(no_op_init);
  Kokkos::Tools::Experimental::set_allocate_data_callback(count_kokkos_allocation);
  const long long heap_before = heap_allocations, kokkos_before = kokkos_allocations;
  for (int s = 0; s < steps; ++s) sim.step();
  const long long heap = heap_allocations - heap_before, kokkos = kokkos_allocations - kokkos_before;
  Kokkos::Tools::Experimental::set_allocate_data_callback(nullptr);
  Kokkos::Tools::Experimental::set_init_callback(nullptr);
  if (moving) {
    EXPECT_GT(sim.neighbour_rebuilds(), rebuilds_before) << "the counted steps should include list rebuilds";
  }
  EXPECT_EQ(heap, 0) << "heap allocations in " << steps << " steps";
  EXPECT_EQ(kokkos, 0) << "Kokkos allocations in " << steps << " steps";
}

// The counter itself works: a View and a vector are seen.
TEST(Allocation, CountersSeeAllocations) {
  Kokkos::Tools::Experimental::set_init_callback(no_op_init);
  Kokkos::Tools::Experimental::set_allocate_data_callback(count_kokkos_allocation);
  const long long heap_before = heap_allocations, kokkos_before = kokkos_allocations;
  {
    Kokkos::View<double*> view("counted", 10);
    std::vector<int> vector(10);
    EXPECT_EQ(vector.size(), view.extent(0));
  }
  Kokkos::Tools::Experimental::set_allocate_data_callback(nullptr);
  Kokkos::Tools::Experimental::set_init_callback(nullptr);
  EXPECT_GE(heap_allocations - heap_before, 1);
  EXPECT_EQ(kokkos_allocations - kokkos_before, 1);
}

TEST(Allocation, StepsOfAStirredPeriodicBoxAllocateNothing) {
  auto scene = testing::periodic_box(2, 24);
  scene.resummation_interval = 7;
  scene.particle_motion = ParticleMotion::Lagrangian;
  Simulation<2, Kokkos::DefaultHostExecutionSpace> sim(scene);
  // A uniform drift (which viscosity does not damp) carries particles
  // across process boundaries and through list rebuilds; noise on top.
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sim.particles().v);
  for (int i = 0; i < sim.particles().owned; ++i) v(i, 0) += 0.05, v(i, 1) += 0.02;
  Kokkos::deep_copy(sim.particles().v, v);
  testing::randomise_velocities(sim.particles(), 0.01, 11);
  expect_allocation_free_steps(sim, 100, 100);
}

TEST(Allocation, StepsOfAGrainCellWithShiftingAllocateNothing) {
  auto scene = testing::periodic_box(2, 24);
  scene.grains = grains_from_list({0.0, 0.0, 0.2, 0.5, 0.5, 0.15}, 2);
  scene.shifting_coefficient = 2.0;
  scene.body_force = {0.01, 0.0, 0};
  scene.particle_motion = ParticleMotion::Lagrangian;
  Simulation<2, Kokkos::DefaultHostExecutionSpace> sim(scene);
  testing::randomise_velocities(sim.particles(), 0.05, 12);
  expect_allocation_free_steps(sim, 100, 100);
}

// The default: fixed particles, convection, wall pressure from the fluid.
TEST(Allocation, StepsOfAFixedGrainCellAllocateNothing) {
  auto scene = testing::periodic_box(2, 24);
  scene.grains = grains_from_list({0.0, 0.0, 0.2, 0.5, 0.5, 0.15}, 2);
  scene.body_force = {0.01, 0.0, 0};
  ASSERT_EQ(scene.particle_motion, ParticleMotion::Fixed);
  Simulation<2, Kokkos::DefaultHostExecutionSpace> sim(scene);
  testing::randomise_velocities(sim.particles(), 0.05, 12);
  expect_allocation_free_steps(sim, 100, 100, false);
}

}  // namespace
}  // namespace poresph
