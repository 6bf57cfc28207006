#pragma once
// Quasi-static drainage by the morphological rule of Hilpert & Miller
// (2001, "Pore-morphology-based simulation of drainage in totally wetting
// porous media", Adv. Water Resour. 24, 243): at a capillary pressure
// Pc = (dim - 1) sigma cos(theta) / r, the non-wetting phase fills every
// ball of radius r that fits in the pore space and whose centre can reach
// the non-wetting reservoir through centres of such balls. The wetting
// phase keeps the rest (corners, films, throats narrower than 2r). It
// drains wherever the rule lets the balls in, unless trapping is asked
// for: then wetting phase cut off from its outlet stays (DrainageInlet).
//
// Everything is measured on the lattice of fixed particles, in spacings:
// a point's pore radius is its distance to the nearest lattice point that
// holds no fluid particle, less half a spacing (exact for a wall halfway
// between two lattice points, as channel walls and image faces lie), and
// balls are sets of lattice points. The scene's solid enters only through
// which lattice points are fluid, so grains, images and walls are treated
// alike. Saturations are shares of fluid points (fixed particles all have
// one volume).
#include <array>
#include <cmath>
#include <vector>

#include "scene/SceneConfig.hpp"

namespace poresph {

// The particle lattice, whole: fluid[n] with n = i + shape[0] (j + shape[1] k).
struct DrainageLattice {
  int dimension = 2;
  std::array<long long, 3> shape{{1, 1, 1}};
  std::array<bool, 3> periodic{{true, true, true}};
  std::vector<char> fluid;

  long long size() const { return shape[0] * shape[1] * shape[2]; }
};

// Where the non-wetting phase comes from: the cell's face across `axis`
// (both lattice layers next to it: across a periodic face the two sides
// meet there), or anywhere (every ball that fits is filled). With
// trapping, the cell is a sample between two reservoirs: the non-wetting
// phase enters at the first lattice layer along `axis` (next to x = 0 for
// x), the wetting phase leaves at the last (next to x = L), nothing joins
// or wraps across that face, and wetting phase that no path of wetting
// phase joins to the outlet is trapped: it stays, and the non-wetting
// phase never fills it (not with anywhere).
struct DrainageInlet {
  int axis = 0;
  bool anywhere = false;
  bool trapping = false;
};

// Each lattice point's pore radius in spacings (the largest ball about it
// that holds only fluid points, to half a spacing); 0 at non-fluid points.
std::vector<double> pore_radius(const DrainageLattice& lattice);

// The points the non-wetting phase fills once the ball radius has come
// down to r (spacings): those of the balls of every step of the drainage
// from the largest pore radius down to r (drainage_curve with r among its
// steps) and of r itself. Drainage only adds: a point filled at a larger radius stays
// filled. (In the continuum the balls of radius r alone hold those of any
// larger radius; on the lattice, whose balls' centres and rims are lattice
// points, not always: a film of wetting phase can appear at one step and
// go at the next.)
std::vector<char> drained_points(const DrainageLattice& lattice, const std::vector<double>& radius, double r,
                                 const DrainageInlet& inlet);

// The share of fluid points that `drained` marks.
double drained_saturation(const DrainageLattice& lattice, const std::vector<char>& drained);

struct DrainageStep {
  double radius = 0;      // spacings
  double saturation = 0;  // of the non-wetting phase
};

// The drainage step at which the non-wetting phase first fills at least
// `saturation` of the fluid points: the first step of the curve
// (drainage_curve) that does, its radius (spacings) and saturation; so
// the phase placed there is a row of the curve. radius = 0 when no step
// reaches it (pore space the inlet cannot reach, or trapped wetting phase).
DrainageStep drain_to_saturation(const DrainageLattice& lattice, const std::vector<double>& radius,
                                 double saturation, const DrainageInlet& inlet);

// The drainage curve: the saturation at each step of the drainage, its
// radius (spacings) falling from the largest pore radius to half a
// spacing (every fluid point a centre) by a quarter of a spacing, or by
// 1/100 of the range where that is more, largest first; with `also` > 0,
// that radius is a step too (the phase placed at a given radius is then
// a row of the curve).
std::vector<DrainageStep> drainage_curve(const DrainageLattice& lattice, const std::vector<double>& radius,
                                         const DrainageInlet& inlet, double also = 0);

// The rule's Young-Laplace law both ways: the curvature (dim - 1) cos(theta)
// / r of the interface that balls of radius r leave (theta in degrees,
// through the wetting phase), and the radius at which sigma times it is Pc.
inline double drainage_curvature(int dimension, double contact_angle, double radius) {
  return (dimension - 1) * std::cos(contact_angle * std::acos(-1.0) / 180) / radius;
}
inline double drainage_radius(int dimension, double sigma, double contact_angle, double capillary_pressure) {
  return sigma * drainage_curvature(dimension, contact_angle, 1.0) / capillary_pressure;
}

// A phase placed by the rule (PhaseConfig::Drainage) on a lattice of
// spacing dx: the points it fills, the radius (m) and saturation there,
// the interface's curvature (dim - 1) cos(theta) / r (1/m) and the
// capillary pressure sigma times that (0 without sigma), and the curve.
struct DrainagePlacement {
  std::vector<char> drained;
  double radius = 0, saturation = 0, curvature = 0, capillary_pressure = 0;
  std::vector<DrainageStep> curve;  // radius in m
};
DrainagePlacement place_by_drainage(const PhaseConfig::Drainage& rule, const DrainageLattice& lattice, double dx);

}  // namespace poresph
