#pragma once
// Start-up channel flow between walls y = 0 and y = L (METHOD.md): plane
// Poiseuille flow under a body force F plus Couette flow from the walls'
// speeds. The equation is linear, so the two series add.
#include <algorithm>
#include <cmath>

namespace poresph {

struct ChannelFlow {
  double width;           // L
  double nu;              // kinematic viscosity
  double body_force;      // F along x
  double lower_velocity;  // wall at y = 0
  double upper_velocity;  // wall at y = L

  // Start-up Poiseuille flow from rest, walls at rest.
  double poiseuille(double y, double t) const {
    constexpr double pi = 3.14159265358979323846;
    const double L = width;
    double v = body_force / (2 * nu) * y * (L - y);
    for (int n = 0; n < 100000; ++n) {
      const double k = 2 * n + 1;
      const double decay = std::exp(-k * k * pi * pi * nu * t / (L * L));
      const double term = 4 * body_force * L * L / (nu * pi * pi * pi * k * k * k) * std::sin(k * pi * y / L) * decay;
      v -= term;
      if (decay / (k * k * k) < 1e-17) break;
    }
    return v;
  }

  // Start-up Couette flow from rest: lower wall at rest, upper at speed 1.
  double couette_unit(double y, double t) const {
    constexpr double pi = 3.14159265358979323846;
    const double L = width;
    double v = y / L;
    for (int n = 1; n < 100000; ++n) {
      const double decay = std::exp(-n * n * pi * pi * nu * t / (L * L));
      v += 2.0 / (n * pi) * ((n % 2) ? -1.0 : 1.0) * std::sin(n * pi * y / L) * decay;
      if (decay / n < 1e-17) break;
    }
    return v;
  }

  // v_x(y, t): walls started impulsively at t = 0 from fluid at rest.
  // A moving lower wall is the Couette problem mirrored in y.
  double velocity(double y, double t) const {
    return lower_velocity * couette_unit(width - y, t) + upper_velocity * couette_unit(y, t) + poiseuille(y, t);
  }

  // Largest |v_x| of the steady profile, the scale errors are quoted against.
  double steady_peak() const {
    double peak = 0;
    for (int k = 0; k <= 2000; ++k) {
      const double y = width * k / 2000.0;
      const double v = lower_velocity + (upper_velocity - lower_velocity) * y / width +
                       body_force / (2 * nu) * y * (width - y);
      peak = std::max(peak, std::abs(v));
    }
    return peak;
  }
};

struct ProfileSample {
  double requested_time;  // as asked in Diagnostics/Profile Sample Times (or the end)
  double time;            // the step's time at which it was taken
  double error;           // max |v_x - series| / v_max over fluid particles
};

}  // namespace poresph
