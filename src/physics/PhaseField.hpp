#pragma once
// A moving interface between two fluids on fixed particles: a phase field
// phi (1 in phase 1, 0 in phase 0) on the lattice the particles sit on,
// carried by the SPH velocity and kept a layer of width epsilon by the
// conservative Allen-Cahn equation (Chiu & Lin 2011, J. Comput. Phys. 230,
// 185):
//   d phi/dt + div(u phi) = div(gamma (epsilon grad phi - phi (1 - phi) n)),   n = grad phi / |grad phi|,
// whose flat layer at rest is phi = 1 / (1 + exp(-s / epsilon)), s the
// distance across it along n (towards phase 1).
//
// Finite volumes on the lattice: each Allen-Cahn flux crosses a face
// between two fluid points and moves phi from one to the other; no flux
// crosses a face into the solid. The advection is u . grad(phi) with each
// face's velocity (the mean of its points'): the SPH velocity is not
// free of divergence on the lattice's faces, and div(u phi) would pile
// phi up in a phase's bulk where it converges (0.46 over 1 in a
// capillary rise); u . grad(phi) leaves the bulk alone. What it makes or
// loses of sum(phi) is given back each step within the layer, in
// proportion to phi (1 - phi) (a Lagrange multiplier of the amount, as
// Kim, Lee & Choi 2014 do for the Allen-Cahn equation), so sum(phi) over
// the fluid changes by round-off alone.
//
// Wetting: the contact angle theta, measured through phase 0 (as
// Phases/Phase 1/Drainage/Contact Angle), fixes the interface's normal at a
// solid face: n . n_w = cos(theta), n_w the face's normal into the fluid.
// Each solid may wet at its own angle (Phases/Contact Angles): the field
// then holds cos(theta) per solid lattice point, and a face into the solid
// takes its solid point's; beyond a wall (a lattice end that does not wrap)
// the settings' angle holds.
// A solid neighbour of a fluid point a is seen by a's differences with the
// value of the layer that meets the wall at that angle: the layer's
// distance s = epsilon ln(phi / (1 - phi)) grows by n . (x_solid - x_a) =
// -dx cos(theta) from a to it, so phi_solid = profile(s_a - dx cos(theta)),
// exact for a flat layer at rest (the linear form phi_a - dx cos(theta)
// phi_a (1 - phi_a) / epsilon, the surface-energy condition of Jacqmin
// 2000, is its first term; a cap at 30 degrees crept further with it:
// docs/method.md). At theta = 90 degrees it is a mirror of a.
//
// The sharpening's phi (1 - phi) on a face is taken from the layer's
// distance s = epsilon ln(phi / (1 - phi)) averaged over the face's two
// points, 1/4 (1 - tanh^2(s / 2 epsilon)), not from the mean of phi (the
// accurate conservative diffuse interface of Jain 2022, J. Comput. Phys.
// 469, 111529): s is linear across the layer, phi is not, so the face's
// weight is the profile's at the face and the flat layer is nearly a
// discrete rest state in every direction; from the mean of phi a cap of
// the update alone squares towards the lattice's axes (docs/method.md).
// The normals are those of grad s, which the layer's profile does not bend.
//
// The surface force is the continuum surface force sigma kappa grad phi
// (Brackbill, Kothe & Zemach 1992), kappa = -div n, with grad phi the
// interface's delta function; at a solid face n's normal component is the
// wetting condition's, which is what pulls a contact line to its angle.
// Its grad phi is the SPH operator the pressure term applies, sum_b V_b
// (phi_a + phi_b) grad_a W_ab over the kernel's support on the lattice, a
// solid point b (or one beyond a wall) taking the fluid's phi extrapolated
// to it as a wall's pressure is (its Shepard mean): a uniform kappa is then
// balanced exactly by a pressure sigma kappa phi, and what drives spurious
// currents is kappa's variation alone.
//
// Host vectors on the whole lattice of the cell: each process holds all of
// it and advances it alike (app/Simulation.cpp gathers the velocities).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/Kernel.hpp"
#include "core/Vec.hpp"

namespace poresph {

struct PhaseFieldSettings {
  double width = 0;              // epsilon (m)
  double mobility = 0;           // gamma (m/s)
  double cos_contact_angle = 0;  // cos(theta), theta through phase 0
  double smoothing_length = 0;   // h of the kernel whose pressure term the surface force meets (m); 0: the spacing
};

// The layer's value a distance s from its middle along n (towards phase 1).
inline double phase_field_profile(double s, double width) { return 1.0 / (1.0 + std::exp(-s / width)); }

// The value a solid neighbour of a fluid point holding phi takes in its
// differences: the flat layer through the point, met by the wall at theta,
// one spacing on into the wall.
inline double wetting_neighbour_value(double phi, double dx, double width, double cos_contact_angle) {
  const double p = std::clamp(phi, 0.0, 1.0);
  return p / (p + (1 - p) * std::exp(dx * cos_contact_angle / width));
}
inline double wetting_neighbour_value(double phi, double dx, const PhaseFieldSettings& s) {
  return wetting_neighbour_value(phi, dx, s.width, s.cos_contact_angle);
}

template <int Dim>
class LatticePhaseField {
 public:
  using Index = std::array<long long, Dim>;

  // cells: lattice points per axis; periodic: whether an axis wraps (else
  // beyond its ends is solid); fluid: per point (x fastest), 1 for fluid;
  // solid_cos: per point, cos(theta) of a solid point's own angle (fluid
  // points' entries unread), or empty: settings.cos_contact_angle on every solid.
  LatticePhaseField(const Index& cells, const std::array<bool, Dim>& periodic, double dx,
                    const PhaseFieldSettings& settings, std::vector<char> fluid, std::vector<double> solid_cos = {})
      : cells_(cells), dx_(dx), settings_(settings), fluid_(std::move(fluid)), solid_cos_(std::move(solid_cos)) {
    if (!(dx > 0) || !(settings.width > 0) || !(settings.mobility >= 0))
      throw std::invalid_argument("LatticePhaseField: the spacing and the width must be positive, the mobility >= 0");
    const std::size_t n = size();
    if (fluid_.size() != n) throw std::invalid_argument("LatticePhaseField: one fluid flag per lattice point");
    if (!solid_cos_.empty() && solid_cos_.size() != n)
      throw std::invalid_argument("LatticePhaseField: one cos(theta) per lattice point, or none");
    phi_.assign(n, 0.0);
    neighbours_.assign(n * 2 * Dim, -1);
    for (std::size_t k = 0; k < n; ++k) {
      if (!fluid_[k]) continue;
      fluid_points_.push_back(k);
      const Index i = point(k);
      for (int d = 0; d < Dim; ++d)
        for (int side = 0; side < 2; ++side) {
          Index j = i;
          j[d] += side ? 1 : -1;
          if (j[d] < 0 || j[d] >= cells_[d]) {
            if (!periodic[d]) continue;
            j[d] = (j[d] + cells_[d]) % cells_[d];
          }
          const std::size_t m = index(j);
          const auto at = static_cast<long long>(m);
          neighbours_[slot(k, d, side)] = fluid_[m] ? at : kSolidPoint - at;
        }
    }
    make_force_stencil(periodic);
  }

  std::size_t size() const {
    std::size_t n = 1;
    for (int d = 0; d < Dim; ++d) n *= static_cast<std::size_t>(cells_[d]);
    return n;
  }
  std::size_t index(const Index& i) const {
    std::size_t k = 0;
    for (int d = Dim - 1; d >= 0; --d) k = k * static_cast<std::size_t>(cells_[d]) + static_cast<std::size_t>(i[d]);
    return k;
  }
  Index point(std::size_t k) const {
    Index i{};
    for (int d = 0; d < Dim; ++d) i[d] = static_cast<long long>(k % cells_[d]), k /= cells_[d];
    return i;
  }
  bool fluid(std::size_t k) const { return fluid_[k] != 0; }
  // cos(theta) of solid point k's wetting (the settings' without per-solid angles).
  double solid_cos(std::size_t k) const { return solid_cos_.empty() ? settings_.cos_contact_angle : solid_cos_[k]; }
  const PhaseFieldSettings& settings() const { return settings_; }

  // phi at each lattice point (only the fluid points' mean anything).
  std::vector<double>& values() { return phi_; }
  const std::vector<double>& values() const { return phi_; }

  // The sum of phi over the fluid points: conserved by advance().
  double amount() const {
    double sum = 0;
    for (std::size_t k : fluid_points_) sum += phi_[k];
    return sum;
  }

  // The longest explicit step of the Allen-Cahn fluxes: half of the
  // diffusion limit dx^2 / (2 Dim gamma epsilon) and of the sharpening's
  // dx / gamma.
  double stable_step() const {
    const double gamma = settings_.mobility;
    if (!(gamma > 0)) return 1e300;
    return 0.5 * std::min(dx_ * dx_ / (2 * Dim * gamma * settings_.width), dx_ / gamma);
  }

  // phi over dt, with the velocity at each lattice point (fluid points
  // read), in as many equal explicit sub-steps as stable_step() asks.
  void advance(double dt, const std::vector<Vec<Dim>>& velocity) {
    const int substeps = std::max(1, static_cast<int>(std::ceil(dt / stable_step() - 1e-12)));
    const double h = dt / substeps;
    std::vector<double>& change = change_;  // only the fluid points' entries are read
    change.resize(phi_.size());
    for (int s = 0; s < substeps; ++s) {
      const std::vector<Vec<Dim>>& n = normals();
      for (std::size_t a : fluid_points_) change[a] = 0.0;
      for (std::size_t a : fluid_points_)
        for (int d = 0; d < Dim; ++d) {
          const long long b = neighbours_[slot(a, d, 1)];
          if (b < 0) continue;  // a face into the solid: no flux
          const auto c = static_cast<std::size_t>(b);
          const double flux = allen_cahn_flux(a, c, d, n);
          change[a] -= flux, change[c] += flux;
          // Advection in the form u . grad(phi), the face's share to each side.
          const double carried = 0.5 * (velocity[a][d] + velocity[c][d]) * 0.5 * (phi_[c] - phi_[a]);
          change[a] -= carried, change[c] -= carried;
        }
      const double scale = h / dx_;
      double before = 0, after = 0, weights = 0;
      for (std::size_t a : fluid_points_) {
        before += phi_[a];
        phi_[a] += scale * change[a];
        after += phi_[a];
        weights += layer_weight(phi_[a]);
      }
      // The advection's share of sum(phi) that a velocity with divergence
      // made or lost, given back within the layer (where phi (1 - phi) > 0):
      // the bulk keeps 0 and 1, and sum(phi) is kept to round-off.
      if (weights > 0)
        for (std::size_t a : fluid_points_) phi_[a] += (before - after) * layer_weight(phi_[a]) / weights;
    }
  }

  // The surface force sigma kappa grad phi (N/m^3) at each lattice point
  // (zero at solid points), grad phi by the pressure term's operator
  // (pressure_gradient), valid until the next call.
  const std::vector<Vec<Dim>>& surface_force(double sigma) const {
    std::vector<Vec<Dim>>& force = force_;
    force.resize(phi_.size(), Vec<Dim>::zero());  // its solid points' entries stay zero
    const std::vector<Vec<Dim>>& n = normals();
    extrapolate_to_walls();
    for (std::size_t a : fluid_points_) {
      // Where phi (1 - phi) is below 1e-10 the layer's profile puts every
      // phi of the stencil within e^(3h / epsilon) times that of 0 or 1: a
      // force of that order next to the layer's is not summed.
      if (!(layer_weight(phi_[a]) > 1e-10)) {
        force[a] = Vec<Dim>::zero();
        continue;
      }
      double divergence = 0;
      for (int d = 0; d < Dim; ++d)
        for (int side = 0; side < 2; ++side) {
          const long long b = neighbours_[slot(a, d, side)];
          // At a solid face the wetting condition's n . n_w = cos(theta),
          // n_w = -e_d on the upper side and +e_d on the lower.
          const double face = b >= 0 ? face_normal(n[a], n[static_cast<std::size_t>(b)], d)
                                     : (side ? -1.0 : 1.0) * wetting_cos(b);
          divergence += side ? face : -face;
        }
      const double kappa = -divergence / dx_;
      force[a] = kappa != 0 ? (sigma * kappa) * pressure_gradient(a) : Vec<Dim>::zero();
    }
    return force;
  }

  // grad phi at fluid point a by central differences, a solid neighbour
  // taking the wetting value of its angle. Beside a flat stretch of solid (a solid
  // neighbour across one axis only) the component along the wall's normal
  // n_w is the smaller of that difference and the geometric condition's
  // cot(theta) |grad_t phi| (Ding & Spelt 2007; the tangential part from
  // the other axes' differences): each is exact for a flat layer meeting
  // the wall at theta, the first for the layer's profile at rest, the
  // second for any profile. Measured on drops on a wall (docs/method.md):
  // the first alone let a drop at 30 degrees spread on past its angle, the
  // second alone put a drop at 150 degrees at 160; the smaller of the two
  // settles both.
  Vec<Dim> gradient(std::size_t a) const {
    return wall_gradient(a, [&](long long b) {
      return b >= 0 ? phi_[static_cast<std::size_t>(b)]
                    : wetting_neighbour_value(phi_[a], dx_, settings_.width, wetting_cos(b));
    });
  }

  // phi on the padded lattice for pressure_gradient(): the fluid points'
  // own (periodic copies in the padding), and at each solid point or point
  // beyond a wall that a fluid point's stencil reaches, the Shepard mean of
  // the fluid's about it (sum_f phi_f W / sum_f W), as a wall's pressure is
  // extrapolated (physics/WallPressure.hpp): then the pressure sigma kappa
  // phi that the surface force asks for is what the wall takes from the
  // fluid. Valid until phi changes.
  void extrapolate_to_walls() const {
    for (std::size_t p = 0; p < padded_source_.size(); ++p)
      padded_phi_[p] = padded_source_[p] >= 0 ? phi_[static_cast<std::size_t>(padded_source_[p])] : 0.0;
    for (std::size_t q : wall_points_) {
      double sum = 0, weights = 0;
      for (const StencilOffset& o : stencil_) {
        const std::size_t f = q + static_cast<std::size_t>(o.step);  // unsigned wrap-around adds a negative step
        if (padded_source_[f] < 0) continue;
        sum += padded_phi_[f] * o.weight, weights += o.weight;
      }
      padded_phi_[q] = weights > 0 ? sum / weights : 0.0;
    }
  }

  // grad phi at fluid point a by the pressure term's SPH operator,
  // sum_b V (phi_a + phi_b) grad_a W_ab over the kernel's support, as the
  // last extrapolate_to_walls() left phi.
  Vec<Dim> pressure_gradient(std::size_t a) const {
    const std::size_t p = padded_index(point(a));
    Vec<Dim> g = Vec<Dim>::zero();
    for (const StencilOffset& o : stencil_)
      g += (phi_[a] + padded_phi_[p + static_cast<std::size_t>(o.step)]) * o.volume_gradient;
    return g;
  }

 private:
  // neighbours_ of a face into a solid lattice point m: kSolidPoint - m; beyond a wall: -1.
  static constexpr long long kSolidPoint = -2;

  // cos(theta) of the solid across a face whose neighbours_ entry is b < 0.
  double wetting_cos(long long b) const {
    if (solid_cos_.empty() || b == -1) return settings_.cos_contact_angle;
    return solid_cos_[static_cast<std::size_t>(kSolidPoint - b)];
  }

  // phi is held this far inside (0, 1) for the layer's distance s: the
  // bulk's s is then flat, and so its normal zero.
  static constexpr double kLeastLayer = 1e-12;

  // The central differences of a field at fluid point a, value(b) the
  // value across face b (a solid neighbour's too), and beside a flat
  // stretch of solid (a solid neighbour across one axis only) the component
  // along the wall's normal n_w the smaller of that difference and the
  // geometric condition's cot(theta) |grad_t| (the tangential part from the
  // other axes' differences).
  template <class Value>
  Vec<Dim> wall_gradient(std::size_t a, const Value& value) const {
    Vec<Dim> g = Vec<Dim>::zero();
    int wall_axis = -1, walls = 0;
    long long wall_face = -1;
    for (int d = 0; d < Dim; ++d) {
      const long long up = neighbours_[slot(a, d, 1)], down = neighbours_[slot(a, d, 0)];
      if ((up < 0) != (down < 0)) wall_axis = d, ++walls, wall_face = up < 0 ? up : down;
      g[d] = (value(up) - value(down)) / (2 * dx_);
    }
    if (walls == 1) {
      double tangential = 0;
      for (int e = 0; e < Dim; ++e)
        if (e != wall_axis) tangential += g[e] * g[e];
      const double c = wetting_cos(wall_face), s = std::sqrt(std::max(1e-12, 1 - c * c));
      // d phi / d n_w = cot(theta) |grad_t phi|; n_w = +e_d with the solid below, -e_d above.
      const double along_normal = c / s * std::sqrt(tangential);
      const double geometric = neighbours_[slot(a, wall_axis, 0)] < 0 ? along_normal : -along_normal;
      if (std::fabs(geometric) < std::fabs(g[wall_axis])) g[wall_axis] = geometric;
    }
    return g;
  }

  // grad s at fluid point a, s = epsilon ln(phi / (1 - phi)) the layer's
  // distance, a solid neighbour's s_a - dx cos(theta) (the wetting value
  // above, in s), with the same rule beside a flat stretch of solid; from
  // the distances normals() keeps.
  Vec<Dim> distance_gradient(std::size_t a) const {
    return wall_gradient(a, [&](long long b) {
      return b >= 0 ? distance_[static_cast<std::size_t>(b)] : distance_[a] - dx_ * wetting_cos(b);
    });
  }

  // The kernel's support on the lattice: each offset o with 0 < |o| dx <
  // 3h, as a step in the padded lattice's index, with V grad_a W_ab for
  // b = a + o (x_a - x_b = -o dx) and W(|o| dx).
  struct StencilOffset {
    long long step;
    Vec<Dim> volume_gradient;
    double weight;
  };

  // The padded lattice: twice the kernel's reach more on each side (copies
  // across periodic ends, points beyond walls), so that a stencil about any
  // point it reaches stays inside. Its points' sources, and the non-fluid
  // points that some fluid point's stencil reaches.
  void make_force_stencil(const std::array<bool, Dim>& periodic) {
    const QuinticKernel<Dim> kernel(settings_.smoothing_length > 0 ? settings_.smoothing_length : dx_);
    const auto reach = static_cast<long long>(std::ceil(kernel.cutoff / dx_ - 1e-9));
    std::size_t padded_points = 1;
    padding_ = 2 * reach;
    for (int d = 0; d < Dim; ++d) {
      padded_cells_[d] = cells_[d] + 2 * padding_;
      padded_points *= static_cast<std::size_t>(padded_cells_[d]);
    }
    double volume = 1;
    for (int d = 0; d < Dim; ++d) volume *= dx_;
    Index o{};
    o.fill(-reach);
    while (true) {
      double r2 = 0;
      long long step = 0;
      for (int d = Dim - 1; d >= 0; --d) r2 += static_cast<double>(o[d] * o[d]), step = step * padded_cells_[d] + o[d];
      const double r = std::sqrt(r2) * dx_;
      if (r2 > 0 && r < kernel.cutoff) {
        StencilOffset s{step, Vec<Dim>::zero(), kernel.value(r)};
        for (int d = 0; d < Dim; ++d) s.volume_gradient[d] = -volume * kernel.derivative_over_r(r) * o[d] * dx_;
        stencil_.push_back(s);
      }
      int d = 0;
      while (d < Dim && ++o[d] > reach) o[d] = -reach, ++d;
      if (d == Dim) break;
    }
    // Each padded point's lattice point (periodic ends wrapped), -1 where
    // that is solid or beyond a wall.
    padded_source_.assign(padded_points, -1);
    for (std::size_t p = 0; p < padded_points; ++p) {
      std::size_t rest = p;
      Index j{};
      bool beyond = false;
      for (int d = 0; d < Dim; ++d) {
        j[d] = static_cast<long long>(rest % static_cast<std::size_t>(padded_cells_[d])) - padding_;
        rest /= static_cast<std::size_t>(padded_cells_[d]);
        if (j[d] < 0 || j[d] >= cells_[d]) {
          if (!periodic[d]) beyond = true;
          j[d] = (j[d] % cells_[d] + cells_[d]) % cells_[d];
        }
      }
      if (!beyond && fluid_[index(j)]) padded_source_[p] = static_cast<long long>(index(j));
    }
    std::vector<char> reached(padded_points, 0);
    for (std::size_t a : fluid_points_) {
      const std::size_t p = padded_index(point(a));
      for (const StencilOffset& s : stencil_) {
        const std::size_t q = p + static_cast<std::size_t>(s.step);
        if (padded_source_[q] < 0 && !reached[q]) reached[q] = 1, wall_points_.push_back(q);
      }
    }
    padded_phi_.assign(padded_points, 0.0);
  }

  std::size_t padded_index(const Index& i) const {
    std::size_t k = 0;
    for (int d = Dim - 1; d >= 0; --d)
      k = k * static_cast<std::size_t>(padded_cells_[d]) + static_cast<std::size_t>(i[d] + padding_);
    return k;
  }

  std::size_t slot(std::size_t k, int d, int side) const {
    return k * 2 * Dim + static_cast<std::size_t>(2 * d + side);
  }

  static double layer_weight(double phi) { return std::max(0.0, phi * (1 - phi)); }

  // A gradient of s shorter than this is no interface: its direction is round-off.
  static constexpr double kLeastGradient = 1e-8;

  // The unit normal at each fluid point (zero where there is no interface),
  // valid until the next call; the solid points' entries are never read.
  const std::vector<Vec<Dim>>& normals() const {
    std::vector<Vec<Dim>>& n = normals_;
    n.resize(phi_.size());
    distance_.resize(phi_.size());
    odds_.resize(phi_.size());
    for (std::size_t a : fluid_points_) {
      const double p = std::clamp(phi_[a], kLeastLayer, 1 - kLeastLayer);
      odds_[a] = (1 - p) / p;
      distance_[a] = -settings_.width * std::log(odds_[a]);
    }
    for (std::size_t a : fluid_points_) {
      const Vec<Dim> g = distance_gradient(a);
      const double norm = std::sqrt(dot(g, g));
      n[a] = norm > kLeastGradient ? (1.0 / norm) * g : Vec<Dim>::zero();
    }
    return n;
  }

  // Component d of the unit normal on the face between two points: the
  // direction of the sum of theirs.
  static double face_normal(const Vec<Dim>& na, const Vec<Dim>& nb, int d) {
    const Vec<Dim> m = na + nb;
    const double norm = std::sqrt(dot(m, m));
    return norm > 1e-12 ? m[d] / norm : 0.0;
  }

  // phi's Allen-Cahn flux (phi m/s) from a to b = a + e_d across their
  // face: the diffusion and the sharpening, whose phi (1 - phi) is the
  // profile's at the face's distance (the mean of its points' s).
  double allen_cahn_flux(std::size_t a, std::size_t b, int d, const std::vector<Vec<Dim>>& n) const {
    // phi (1 - phi) of the profile at the face's s, r / (1 + r)^2 with r =
    // exp(-s / epsilon) there: the geometric mean of the points' odds.
    const double r = std::sqrt(odds_[a] * odds_[b]);
    const double layer = r / ((1 + r) * (1 + r));
    const double slope = (phi_[b] - phi_[a]) / dx_;
    return -settings_.mobility * (settings_.width * slope - layer * face_normal(n[a], n[b], d));
  }

  Index cells_;
  double dx_;
  PhaseFieldSettings settings_;
  std::vector<char> fluid_;
  std::vector<std::size_t> fluid_points_;
  std::vector<double> solid_cos_;  // per lattice point (solid points read), or empty
  // Per fluid point and face: the fluid neighbour's index; a solid one's as kSolidPoint - index; -1 beyond a wall.
  std::vector<long long> neighbours_;
  std::vector<double> phi_;
  // The surface force's SPH operator: its stencil on the padded lattice,
  // the padded points' sources, the solid points and points beyond a wall
  // that it reaches, and phi on the padded lattice (extrapolate_to_walls).
  std::vector<StencilOffset> stencil_;
  long long padding_ = 0;
  Index padded_cells_{};
  std::vector<long long> padded_source_;  // per padded point: its fluid point's index, or -1
  std::vector<std::size_t> wall_points_;  // padded points that are not fluid, in some fluid point's stencil
  mutable std::vector<double> padded_phi_;
  // Work arrays of the lattice's size, kept from call to call: made anew
  // each step they cost more than the update (pages mapped and unmapped).
  mutable std::vector<Vec<Dim>> normals_, force_;
  // s of each fluid point and its odds (1 - phi) / phi = exp(-s / epsilon),
  // as normals() last found them.
  mutable std::vector<double> distance_, odds_;
  std::vector<double> change_;
};

}  // namespace poresph
