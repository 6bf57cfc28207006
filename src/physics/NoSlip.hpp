#pragma once
// No-slip surfaces through boundary particles (Morris et al. 1997; METHOD.md).
// For the viscous term only, boundary particle B seen from fluid particle a
// moves with u_B = u_w - (d_B / d_a)(u_a - u_w): the fluid velocity relative
// to the surface, mirrored through the tangent plane at the foot of a's
// normal and scaled by the distances to that plane. Then
//   v_aB = u_a - u_B = (1 + d_B / d_a) (u_a - u_w).
#include <Kokkos_Core.hpp>

#include "core/Math.hpp"
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

}  // namespace poresph
