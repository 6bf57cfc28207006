#pragma once
// Steady layered two-phase Poiseuille flow between plates at y = 0 and
// y = H: fluid A (dynamic viscosity mu_A) in 0 <= y < a, fluid B (mu_B)
// in a <= y <= H, driven along x by forces per unit volume G_A = s_A G and
// G_B = s_B G (shares s of one force G: both 1 when the force acts on both
// fluids, one of them 0 when it acts on one alone, Phases/Driven Phase).
// In each layer mu u'' = -G_layer, so the shear stress tau = mu u' is a
// straight line in each, tau_A = C_A - G_A y and tau_B = C_B - G_B y,
// continuous at the interface: C_B = C_A + (G_B - G_A) a. No slip at the
// plates:
//   u_A(y) = (C_A y - G_A y^2/2) / mu_A,
//   u_B(y) = (C_B (y - H) - G_B (y^2 - H^2)/2) / mu_B,
// and the velocity continuous at y = a fixes C_A:
//   C_A (a/mu_A + b/mu_B) = G_A a^2 / (2 mu_A) + (G_B (H^2 - a^2)/2 - (G_B - G_A) a b) / mu_B,
// b = H - a. With one force on both, C_A = G y0, y0 the point of zero
// stress (H/2 for mu_A = mu_B). The fluxes per unit depth are the layers'
// integrals,
//   Q_A = (C_A a^2/2 - G_A a^3/6) / mu_A,
//   Q_B = ((G_B H - C_B) b^2/2 - G_B b^3/6) / mu_B,
// and a layer's Darcy k, its superficial velocity Q / H times its
// viscosity over G, is over the single-phase k = H^2/12 its relative
// permeability k_r = 12 Q mu / (G H^3): with one force on both, a function
// of the viscosities through y0 alone; with one layer driven, the other
// layer's k_r is its viscous coupling to the first.
#include <algorithm>
#include <cmath>

namespace poresph {

struct LayeredChannel {
  double width;      // H
  double interface;  // a
  double mu_lower, mu_upper;
  double force;              // G, per unit volume (Pa/m)
  double lower_share = 1.0;  // G_A / G
  double upper_share = 1.0;  // G_B / G

  double lower_force() const { return lower_share * force; }
  double upper_force() const { return upper_share * force; }
  double lower_stress_constant() const {  // C_A
    const double a = interface, H = width, b = H - a, GA = lower_force(), GB = upper_force();
    return (GA * a * a / (2 * mu_lower) + (GB * (H * H - a * a) / 2 - (GB - GA) * a * b) / mu_upper) /
           (a / mu_lower + b / mu_upper);
  }
  double upper_stress_constant() const { return lower_stress_constant() + (upper_force() - lower_force()) * interface; }
  // Where the stress of one force on both layers vanishes: the profile's peak.
  double zero_stress() const { return lower_stress_constant() / force; }
  double velocity(double y) const {
    const double H = width;
    if (y < interface) return (lower_stress_constant() * y - 0.5 * lower_force() * y * y) / mu_lower;
    return (upper_stress_constant() * (y - H) - 0.5 * upper_force() * (y * y - H * H)) / mu_upper;
  }
  // The largest speed of the profile: where a layer's stress vanishes, or
  // at the interface (a driven layer's stress may not vanish inside it).
  double peak() const {
    double best = std::abs(velocity(interface));
    if (lower_force() != 0) {
      const double y = lower_stress_constant() / lower_force();
      if (y > 0 && y < interface) best = std::max(best, std::abs(velocity(y)));
    }
    if (upper_force() != 0) {
      const double y = upper_stress_constant() / upper_force();
      if (y >= interface && y < width) best = std::max(best, std::abs(velocity(y)));
    }
    return best;
  }
  double lower_flux() const {  // Q_A per unit depth
    const double a = interface;
    return (lower_stress_constant() * a * a / 2 - lower_force() * a * a * a / 6) / mu_lower;
  }
  double upper_flux() const {  // Q_B per unit depth
    const double b = width - interface;
    return ((upper_force() * width - upper_stress_constant()) * b * b / 2 - upper_force() * b * b * b / 6) / mu_upper;
  }
  double lower_relative_permeability() const { return relative_permeability(lower_flux(), mu_lower); }
  double upper_relative_permeability() const { return relative_permeability(upper_flux(), mu_upper); }

 private:
  double relative_permeability(double flux, double mu) const {
    return 12 * flux * mu / (force * width * width * width);
  }
};

}  // namespace poresph
