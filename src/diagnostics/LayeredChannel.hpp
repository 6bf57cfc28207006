#pragma once
// Steady layered two-phase Poiseuille flow between plates at y = 0 and
// y = H: fluid A (dynamic viscosity mu_A) in 0 <= y < a, fluid B (mu_B)
// in a <= y <= H, both driven along x by the same force per unit volume G
// (rho F). In each layer mu u'' = -G, so the shear stress tau = mu u' is
// one straight line across both, tau = G (y0 - y), continuous at the
// interface. No slip at the plates and the velocity continuous at y = a:
//   u_A(y) = G (y0 y - y^2/2) / mu_A,
//   u_B(y) = G (y0 (y - H) - (y^2 - H^2)/2) / mu_B,
//   y0 = (a^2/mu_A + (H^2 - a^2)/mu_B) / (2 (a/mu_A + (H - a)/mu_B)),
// the point of zero stress (H/2 for mu_A = mu_B). The fluxes per unit depth
// are the integrals of each layer's parabola, and a layer's Darcy k, its
// superficial velocity (flux / H) times its viscosity over G, is over the
// single-phase k = H^2/12 its relative permeability:
//   k_r,A = 12 (y0 a^2/2 - a^3/6) / H^3,
//   k_r,B = 12 ((H - y0) b^2/2 - b^3/6) / H^3, b = H - a,
// independent of G and of the viscosities but through y0.
namespace poresph {

struct LayeredChannel {
  double width;      // H
  double interface;  // a
  double mu_lower, mu_upper;
  double force;  // G, per unit volume (Pa/m)

  double zero_stress() const {
    const double a = interface, H = width;
    return (a * a / mu_lower + (H * H - a * a) / mu_upper) / (2 * (a / mu_lower + (H - a) / mu_upper));
  }
  double velocity(double y) const {
    const double y0 = zero_stress(), H = width;
    if (y < interface) return force * (y0 * y - 0.5 * y * y) / mu_lower;
    return force * (y0 * (y - H) - 0.5 * (y * y - H * H)) / mu_upper;
  }
  // The largest velocity of the profile: at y0 (in whichever layer holds it).
  double peak() const { return velocity(zero_stress()); }
  double lower_relative_permeability() const {
    const double a = interface, H = width, y0 = zero_stress();
    return 12 * (y0 * a * a / 2 - a * a * a / 6) / (H * H * H);
  }
  double upper_relative_permeability() const {
    const double b = width - interface, H = width, y0 = zero_stress();
    return 12 * ((H - y0) * b * b / 2 - b * b * b / 6) / (H * H * H);
  }
};

}  // namespace poresph
