#pragma once
// Speed of sound and time-step rules of the weakly compressible method
// (Morris et al. 1997; METHOD.md).
#include <algorithm>
#include <cmath>
#include <limits>

namespace poresph {

// c^2 = max(V^2/delta, nu V/(delta L), a L/delta): the smallest sound speed
// that keeps the density variation near delta for flows of velocity scale V,
// length scale L and body acceleration a.
inline double sound_speed_squared_from_scales(double velocity, double length, double acceleration, double nu,
                                              double delta) {
  return std::max({velocity * velocity / delta, nu * velocity / (delta * length), acceleration * length / delta});
}

struct TimeStepLimits {
  double acoustic;  // 0.25 h / c
  double viscous;   // 0.125 h^2 / nu
  double force;     // 0.25 sqrt(h / |F|)
  double contact = std::numeric_limits<double>::infinity();  // the shortest grain collision over 40 (ContactLaw.hpp)
  double capillary = std::numeric_limits<double>::infinity();  // a moving interface: capillary_time_step
  double smallest() const { return std::min({acoustic, viscous, force, contact, capillary}); }
};

inline TimeStepLimits time_step_limits(double h, double sound_speed, double nu, double body_force_norm) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  return {sound_speed > 0 ? 0.25 * h / sound_speed : inf, nu > 0 ? 0.125 * h * h / nu : inf,
          body_force_norm > 0 ? 0.25 * std::sqrt(h / body_force_norm) : inf};
}

// The capillary wave limit of a moving interface with surface tension
// sigma, 0.25 sqrt(rho h^3 / (2 pi sigma)) (Brackbill, Kothe & Zemach 1992;
// Morris 2000).
inline double capillary_time_step(double h, double density, double sigma) {
  constexpr double pi = 3.14159265358979323846;
  return sigma > 0 ? 0.25 * std::sqrt(density * h * h * h / (2 * pi * sigma)) : std::numeric_limits<double>::infinity();
}

}  // namespace poresph
