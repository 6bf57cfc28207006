#pragma once
// No-slip surfaces through boundary particles (Morris et al. 1997; METHOD.md).
// For the viscous term only, boundary particle B seen from fluid particle a
// moves with u_B = u_w - (d_B / d_a)(u_a - u_w): the fluid velocity relative
// to the surface, mirrored through the tangent plane at the foot of a's
// normal and scaled by the distances to that plane. Then
//   v_aB = u_a - u_B = (1 + d_B / d_a) (u_a - u_w).
#include <Kokkos_Core.hpp>

#include <string>

#include "core/Math.hpp"
#include "core/NeighbourList.hpp"
#include "core/Particles.hpp"
#include "core/Vec.hpp"

namespace poresph {

// Two unit normals belong to the same stretch of surface when within 60
// degrees of each other.
constexpr double kSameSurface = 0.5;

template <int Dim>
struct SurfaceDistances {
  double fluid;     // d_a: normal distance of the fluid particle to the surface
  double boundary;  // d_B: distance of the boundary particle to the tangent plane (positive inside the solid)
  Vec<Dim> normal;  // unit normal at the foot of a's normal, pointing into the fluid
};

// Distances for boundary particle B (kind, wall_vector, wall_scalar as stored
// in Particles) seen from fluid particle a at r_aB = x_a - x_B. Working from
// r_aB and B's own offset makes the result independent of which periodic
// image of the grain B belongs to. A sampled surface (an image) also reads
// a's own unit normal and distance to its nearest surface (0: not known).
template <int Dim>
KOKKOS_INLINE_FUNCTION SurfaceDistances<Dim> surface_distances(int kind_B, const Vec<Dim>& wall_vector_B,
                                                               double wall_scalar_B, const Vec<Dim>& r_aB,
                                                               const Vec<Dim>& normal_a = Vec<Dim>{},
                                                               double distance_a = 0.0) {
  SurfaceDistances<Dim> s{};
  if (kind_B == kGrainBoundary) {
    // Grain: wall_vector = x_B - centre, wall_scalar = radius R.
    const Vec<Dim> from_centre = r_aB + wall_vector_B;  // x_a - centre
    const double distance = math::sqrt(dot(from_centre, from_centre));
    s.normal = (1.0 / distance) * from_centre;
    s.fluid = distance - wall_scalar_B;
    s.boundary = wall_scalar_B - dot(wall_vector_B, s.normal);
    return s;
  }
  // Sampled surface: a's own foot on the surface and B's distance to the
  // tangent plane there, as on a grain, when a knows its distance and its
  // nearest surface is B's (their normals agree; across a throat they
  // oppose). On a circle or sphere this is the grain's formula exactly.
  if (kind_B == kSampledBoundary && distance_a > 0 && dot(normal_a, wall_vector_B) > kSameSurface) {
    const double boundary = dot(normal_a, r_aB) - distance_a;
    if (boundary > 0) {
      s.normal = normal_a;
      s.fluid = distance_a;
      s.boundary = boundary;
      return s;
    }
  }
  // Plane wall, or the tangent plane at B: wall_vector = unit normal into
  // the fluid, wall_scalar = depth of B.
  s.normal = wall_vector_B;
  s.boundary = wall_scalar_B;
  s.fluid = dot(wall_vector_B, r_aB) - wall_scalar_B;
  return s;
}

// (1 + d_B / d_a) with d_a bounded below (sqrt(3)/4 dx) so that fluid particles
// very close to the surface do not see huge artificial velocities.
template <int Dim>
KOKKOS_INLINE_FUNCTION double no_slip_factor(const SurfaceDistances<Dim>& s, double min_fluid_distance) {
  const double d_a = s.fluid > min_fluid_distance ? s.fluid : min_fluid_distance;
  return 1.0 + s.boundary / d_a;
}

// The factor above for boundary particle `other` (of kind other_kind) as
// fluid particle `self` sees it at r = x_self - x_other, from what Particles
// store of both.
template <int Dim, class MemorySpace>
KOKKOS_INLINE_FUNCTION double no_slip_factor_seen(const Particles<Dim, MemorySpace>& P, int self, int other,
                                                  int other_kind, const Vec<Dim>& r, double min_fluid_distance) {
  Vec<Dim> normal_self{};  // self's own surface: read for a sampled one only
  double distance_self = 0.0;
  if (other_kind == kSampledBoundary) {
    normal_self = row<Dim>(P.wall_vector, self);
    distance_self = P.wall_scalar(self);
  }
  const SurfaceDistances<Dim> s = surface_distances<Dim>(other_kind, row<Dim>(P.wall_vector, other),
                                                         P.wall_scalar(other), r, normal_self, distance_self);
  return no_slip_factor(s, min_fluid_distance);
}

// One end fluid, the other a boundary particle.
KOKKOS_INLINE_FUNCTION bool fluid_boundary_pair(int kind_a, int kind_b) { return (kind_a == kFluid) != (kind_b == kFluid); }

// Fixed particles: the no-slip factor of every entry of the pair list with
// one fluid and one boundary end, computed once after the list is built (the
// distances never change), so that the pair loop reads it for those pairs
// instead of recomputing the surface distances at every stage. Only those
// entries have one: row a's are factors [row_first(a), row_first(a + 1)), in
// the list's order, and the pair loop counts them as it goes
// (fluid_boundary_pair), so
// that a scene pays 8 bytes per fluid-boundary entry and 4 per particle, not
// 8 per entry of the list. And which rows of the list have a boundary
// particle at all: the others take the loop without surfaces.
template <int Dim, class ExecSpace>
class NoSlipFactors {
 public:
  using MemorySpace = typename ExecSpace::memory_space;

  // Whether a pair of these kinds has a factor: one fluid end, one boundary end.
  KOKKOS_INLINE_FUNCTION static bool mixed(int kind_a, int kind_b) { return fluid_boundary_pair(kind_a, kind_b); }

  void build(const ExecSpace& space, const Particles<Dim, MemorySpace>& P, const NeighbourList<Dim, ExecSpace>& list,
             double min_fluid_distance) {
    const int owned = P.owned;
    row_first_ = Kokkos::View<int*, MemorySpace>("NoSlipFactors::row_first", owned + 1);
    if (static_cast<int>(touches_.extent(0)) < owned)
      touches_ = Kokkos::View<bool*, MemorySpace>("NoSlipFactors::touches", owned + owned / 4 + 1);
    const auto row_first = row_first_;
    const auto touches = touches_;
    const auto Q = P;
    // The rows' counts of fluid-boundary entries, then where each row's begin.
    static const std::string label_count = "poresph::NoSlipFactors::count";
    Kokkos::parallel_for(
        label_count, Kokkos::RangePolicy<ExecSpace>(space, 0, owned), KOKKOS_LAMBDA(int a) {
          const int kind_a = Q.kind(a);
          bool touches_surface = kind_a != kFluid;
          int count = 0;
          list.for_each_entry(a, [&](int b, const Vec<Dim>&) {
            const int kind_b = Q.kind(b);
            touches_surface = touches_surface || kind_b != kFluid;
            count += mixed(kind_a, kind_b);
          });
          row_first(a) = count;
          touches(a) = touches_surface;
        });
    int total = 0;
    static const std::string label_scan = "poresph::NoSlipFactors::scan";
    Kokkos::parallel_scan(
        label_scan, Kokkos::RangePolicy<ExecSpace>(space, 0, owned + 1),
        KOKKOS_LAMBDA(int a, int& before, bool final) {
          const int count = a < owned ? row_first(a) : 0;
          if (final) row_first(a) = before;
          before += count;
        },
        total);
    factors_ = Kokkos::View<double*, MemorySpace>("NoSlipFactors", total + 1);
    const auto factors = factors_;
    static const std::string label = "poresph::NoSlipFactors::build";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space, 0, owned), KOKKOS_LAMBDA(int a) {
          const int kind_a = Q.kind(a);
          int next = row_first(a);
          list.for_each_entry(a, [&](int b, const Vec<Dim>& r) {
            const int kind_b = Q.kind(b);
            if (!mixed(kind_a, kind_b)) return;
            factors(next++) = kind_a == kFluid ? no_slip_factor_seen(Q, a, b, kind_b, r, min_fluid_distance)
                                               : no_slip_factor_seen(Q, b, a, kind_a, -1.0 * r, min_fluid_distance);
          });
        });
    space.fence();
    built_ = true;
  }
  void clear() { built_ = false; }
  bool built() const { return built_; }

  // Moving grains: their angular velocities (a row a grain, the grain's
  // spin components), which a fluid particle's view of a turning grain's
  // boundary particle takes (physics/terms/TurningWallTerm.hpp). Empty: none turn.
  void set_grain_spin(const Kokkos::View<double**, Kokkos::LayoutRight, MemorySpace>& spin) { grain_spin_ = spin; }
  KOKKOS_INLINE_FUNCTION bool grains_turn() const { return grain_spin_.extent(0) > 0; }
  KOKKOS_INLINE_FUNCTION const double* grain_spin(int grain) const { return &grain_spin_(grain, 0); }

  // Factor `index`: row_first(a) plus the number of fluid-boundary entries
  // of row a before this one.
  KOKKOS_INLINE_FUNCTION double factor(int index) const { return factors_(index); }
  KOKKOS_INLINE_FUNCTION int row_first(int a) const { return row_first_(a); }
  // Whether owned particle a's row of the list has a boundary particle (a itself or a neighbour).
  KOKKOS_INLINE_FUNCTION bool touches_surface(int a) const { return touches_(a); }

 private:
  Kokkos::View<double*, MemorySpace> factors_;
  Kokkos::View<int*, MemorySpace> row_first_;
  Kokkos::View<bool*, MemorySpace> touches_;
  bool built_ = false;
  Kokkos::View<double**, Kokkos::LayoutRight, MemorySpace> grain_spin_;
};

}  // namespace poresph
