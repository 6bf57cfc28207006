#pragma once
// The steady fixed-particle equations as a nonlinear system F(y) = 0, with
// the time loop's own operators (docs/steady_solver.md).
//
// Unknowns, per owned fluid particle: its velocity v and q = (c / rho0) rho,
// the density in units that make the momentum and continuity rows alike
// (d v / dt = -c grad q + ..., d q / dt = -c div v + ...). Residual rows:
//   F_v = (dv/dt - kappa v) / (1 + kappa dt),  F_q = (c / rho0) d rho / dt,
// kappa the wall drag kept apart from dv/dt (physics/PredictorCorrector.hpp).
// Dividing by 1 + kappa dt changes no solution; it keeps the rows of points a
// hair from a surface (kappa up to 1e6 / dt) from swamping every norm.
// Boundary particles and the rows of other kinds are zero: the boundary's
// velocity and pressure follow from the fluid inside the rate evaluation.
//
// Jacobian products are central differences of the rates,
// (F(y + d w) - F(y - d w)) / 2d: exact for the quadratic convective term,
// and second order in d for the pressure term's p / rho^2, so the steady
// state solved for is the time loop's.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "app/Simulation.hpp"
#include "solver/Fgmres.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
class SteadySystem {
 public:
  using Sim = Simulation<Dim, ExecSpace>;
  using MemorySpace = typename ExecSpace::memory_space;
  using View = Kokkos::View<double*, MemorySpace>;
  using RateTerms = typename Sim::RateTerms;

  SteadySystem(Sim& sim, const ExecSpace& space)
      : sim_(sim), space_(space), ops_{space, sim.communicator()}, owned_(sim.particles().owned) {
    const auto& derived = sim.derived();
    const double rho0 = sim.scene().density;
    to_q_ = derived.sound_speed / rho0;
    drag_time_ = sim.time_step();
    velocity_scale_ = derived.velocity_scale > 0 ? derived.velocity_scale : 1.0;
    base_v_ = View("steady_base_v", owned_ * Dim);
    base_q_ = View("steady_base_q", owned_);
    residual_v_ = View("steady_residual_v", owned_ * Dim);
    residual_q_ = View("steady_residual_q", owned_);
    scratch_v_ = View("steady_scratch_v", owned_ * Dim);
    scratch_q_ = View("steady_scratch_q", owned_);
    for (auto& base : partial_) base = {View("steady_partial_v", owned_ * Dim), View("steady_partial_q", owned_)};
    fluid_ = View("steady_fluid", owned_);
    const auto kind = sim.particles().kind;
    const auto fluid = fluid_;
    static const std::string label = "poresph::steady::fluid_mask";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, owned_),
        KOKKOS_LAMBDA(int i) { fluid(i) = kind(i) == kFluid ? 1.0 : 0.0; });
    space_.fence();
    take_state();
  }

  int owned() const { return owned_; }
  long long fluid_particles() const { return sim_.fluid_particles(); }
  const KrylovVectors<ExecSpace>& vectors() const { return ops_; }
  // 1 on owned fluid particles, 0 on the others.
  const View& fluid_mask() const { return fluid_; }
  // The residual at the current state, velocity rows (i * Dim + d) and density rows.
  const View& residual_v() const { return residual_v_; }
  const View& residual_q() const { return residual_q_; }
  long long rate_evaluations() const { return evaluations_; }
  // Evaluations of a part of the pair terms (apply() with RateTerms other than All).
  long long partial_rate_evaluations() const { return partial_evaluations_; }

  // The simulation's current state becomes the one products are taken at.
  void take_state() {
    const auto P = sim_.particles();
    const auto bv = base_v_, bq = base_q_;
    const double to_q = to_q_;
    static const std::string label = "poresph::steady::take_state";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, owned_), KOKKOS_LAMBDA(int i) {
          for (int d = 0; d < Dim; ++d) bv(i * Dim + d) = P.v(i, d);
          bq(i) = to_q * P.rho(i);
        });
    space_.fence();
    evaluate(residual_v_, residual_q_);
    for (auto& base : partial_) base.current = false;
    linear_products_ = sim_.take_linear_state();
  }
  // Whether the products of the pressure term alone and of continuity alone
  // are the simulation's exact linear ones (lattice rows on every process),
  // not forward differences.
  bool linear_products() const { return linear_products_ && !differenced_partials_; }
  // Differences of one-term pair loops from now on, also on lattice rows
  // (the path of lists that are not: tests compare the two).
  void difference_partial_products() { differenced_partials_ = true; }

  // y += (dv, dq) on fluid particles, into the simulation; the residual there.
  void move_state(const View& dv, const View& dq) {
    set_state(1.0, &dv, &dq);
    take_state();
  }

  // (out_v, out_q) = J (wv, wq) at the current state; a null wv or wq is
  // zero. Central differences; Accuracy::Forward takes one rate evaluation
  // instead of two, F(y + d w) - F(y), first order in d: enough for a
  // preconditioner, whose products need only be near J's. terms: the
  // pressure gradient alone (G, velocity rows of a density w), the
  // continuity alone (D, density rows of a velocity w), the velocity
  // block (A, velocity rows of a velocity w; the density rows zero) or its
  // Stokes part (RateTerms::Viscous: A without convection): each a
  // difference of a pair loop with those terms only (Simulation::
  // compute_rates(RateTerms)); G, D and, with one fluid, the Stokes part
  // (and A without convection) the exact linear products where there are
  // (linear_products()). With one term, an output of extent 0 is not
  // wanted: the linear products leave it out (the zero density rows of G
  // and velocity rows of D, which the DG products never read), the
  // differences take a scratch vector for it.
  enum class Accuracy { Central, Forward };
  void apply(const View* wv, const View* wq, const View& wanted_v, const View& wanted_q,
             Accuracy accuracy = Accuracy::Central, RateTerms terms = RateTerms::All) {
    const bool velocity_terms = terms == RateTerms::Velocity || terms == RateTerms::Viscous;
    if (linear_products() && (terms == RateTerms::Pressure || terms == RateTerms::Continuity ||
                              (velocity_terms && sim_.linear_velocity_products(terms)))) {
      apply_linear(wv, wq, wanted_v, wanted_q, terms);
      ++partial_evaluations_;
      return;
    }
    if (terms == RateTerms::All && (wanted_v.extent(0) == 0 || wanted_q.extent(0) == 0))
      throw std::logic_error("SteadySystem::apply: every output is wanted with all the terms");
    const View out_v = wanted_v.extent(0) > 0 ? wanted_v : scratch_v_;
    const View out_q = wanted_q.extent(0) > 0 ? wanted_q : scratch_q_;
    const double size = std::sqrt((wv ? ops_.dot(*wv, *wv) : 0.0) + (wq ? ops_.dot(*wq, *wq) : 0.0));
    if (!(size > 0)) {
      ops_.fill(out_v, 0.0);
      ops_.fill(out_q, 0.0);
      return;
    }
    // A perturbation of 1e-4 of the velocity scale per unknown, on average.
    const double n = static_cast<double>(sim_.fluid_particles()) * (Dim + 1);
    const double step = 1e-4 * velocity_scale_ * std::sqrt(n) / size;
    if (terms != RateTerms::All) {
      PartialBase& base = partial_[static_cast<int>(terms) - 1];
      if (accuracy == Accuracy::Central) {
        set_state(-step, wv, wq);
        evaluate(base.v, base.q, terms);
        base.current = false;  // holds F(y - d w), not F(y)
      } else if (!base.current) {  // F of these terms at the state, once per state
        evaluate(base.v, base.q, terms);
        base.current = true;
      }
      const double scale = accuracy == Accuracy::Central ? 0.5 / step : 1.0 / step;
      set_state(step, wv, wq);
      evaluate(out_v, out_q, terms);
      ops_.update(-scale, base.v, scale, out_v);
      ops_.update(-scale, base.q, scale, out_q);
      if (velocity_terms) ops_.fill(out_q, 0.0);  // its density rows are not the block's
      set_state(0.0, nullptr, nullptr);
      return;
    }
    set_state(step, wv, wq);
    evaluate(out_v, out_q);
    if (accuracy == Accuracy::Forward) {
      ops_.update(-1.0 / step, residual_v_, 1.0 / step, out_v);
      ops_.update(-1.0 / step, residual_q_, 1.0 / step, out_q);
    } else {
      set_state(-step, wv, wq);
      evaluate(scratch_v_, scratch_q_);
      ops_.update(-0.5 / step, scratch_v_, 0.5 / step, out_v);
      ops_.update(-0.5 / step, scratch_q_, 0.5 / step, out_q);
    }
    set_state(0.0, nullptr, nullptr);  // back to the state, for whatever reads the simulation next
  }

  // The diagonal of the velocity block dF_v/dv, by probing: particles whose
  // colours agree are perturbed together, one colour and one component at a
  // time, each probe a forward difference by default (the diagonal is the
  // preconditioner's, and a forward difference is near enough at half the
  // cost: it differs from J's by about 1e-5, relative). Along an axis of N
  // points the colour is the index modulo M, M at least the distance (in
  // spacings) at which the kernel's gradient vanishes, and the N - qM points
  // past the last whole block of M each have a colour of their own: two
  // points of one colour are then M or more apart across the periodic end
  // too, whatever N is. Of the M from that least to twice it, the one with
  // the fewest colours (M plus the points left over); a divisor of N on a
  // tie. Without the leftover colours a lattice of a prime number of points
  // a side had N colours along each axis: N^Dim products (23 a side in 3D:
  // over a minute of set-up, against 2.7 s at 24).
  // terms: RateTerms::Velocity (A's diagonal) or Viscous (its Stokes part's).
  View velocity_diagonal(Accuracy accuracy = Accuracy::Forward, RateTerms terms = RateTerms::Velocity) {
    const double dx = sim_.scene().particle_spacing;
    const double cutoff = 3.0 * sim_.derived().smoothing_length;
    int modulus[Dim], whole[Dim], per_axis[Dim];
    long long colours = 1;
    for (int d = 0; d < Dim; ++d) {
      const int points = static_cast<int>(std::lround(sim_.scene().cell_size[d] / dx));
      const int least = std::max(1, static_cast<int>(std::ceil(cutoff / dx - 1e-9)));
      modulus[d] = std::min(least, points);
      int fewest = modulus[d] + points % modulus[d];
      for (int m = least + 1; m <= std::min(2 * least, points); ++m)
        if (m + points % m < fewest || (m + points % m == fewest && points % m == 0)) {
          modulus[d] = m;
          fewest = m + points % m;
        }
      whole[d] = points / modulus[d] * modulus[d];  // points in whole blocks
      per_axis[d] = modulus[d] + (points - whole[d]);
      colours *= per_axis[d];
    }
    View diagonal("steady_velocity_diagonal", owned_ * Dim);
    View probe("steady_probe", owned_ * Dim), response("steady_response", owned_ * Dim);
    View response_q("steady_response_q", owned_);
    const auto x = sim_.particles().x;
    const auto fluid = fluid_;
    for (long long colour = 0; colour < colours; ++colour) {
      for (int component = 0; component < Dim; ++component) {
        static const std::string label_probe = "poresph::steady::diagonal_probe";
        Kokkos::parallel_for(
            label_probe, Kokkos::RangePolicy<ExecSpace>(space_, 0, owned_), KOKKOS_LAMBDA(int i) {
              long long c = 0;
              for (int d = Dim - 1; d >= 0; --d) {
                const long long index = static_cast<long long>(x(i, d) / dx);
                const long long along = index < whole[d] ? index % modulus[d] : modulus[d] + (index - whole[d]);
                c = c * per_axis[d] + along;
              }
              for (int d = 0; d < Dim; ++d) probe(i * Dim + d) = (c == colour && d == component) ? fluid(i) : 0.0;
            });
        space_.fence();
        apply(&probe, nullptr, response, response_q, accuracy, terms);
        static const std::string label_take = "poresph::steady::diagonal_take";
        Kokkos::parallel_for(
            label_take, Kokkos::RangePolicy<ExecSpace>(space_, 0, owned_), KOKKOS_LAMBDA(int i) {
              if (probe(i * Dim + component) != 0) diagonal(i * Dim + component) = response(i * Dim + component);
            });
        space_.fence();
      }
    }
    return diagonal;
  }

 private:
  // What a velocity row of F is divided by dv/dt - kappa v into: 1 + kappa
  // dt (see the top of the file), 0 on rows that are not fluid.
  KOKKOS_INLINE_FUNCTION static double velocity_row_weight(double fluid, double kappa, double dt) {
    return fluid / (1.0 + kappa * dt);
  }

  // apply() of the pressure term alone (G: velocity rows of wq, the density
  // rows zero), of continuity alone (D: density rows of wv, the velocity
  // rows zero) or of the velocity block (A: velocity rows of wv, the wall
  // drag's -kappa wv added, the density rows zero) by the simulation's
  // linear products: the forward difference's limit, exact to rounding.
  // kappa is the particles' wall_drag as the last pair loop left it: with
  // fixed particles' 1/rho0 it is the same at every state.
  void apply_linear(const View* wv, const View* wq, const View& out_v, const View& out_q, RateTerms terms) {
    using Rows = typename Sim::Rows;
    const auto P = sim_.particles();
    const auto fluid = fluid_;
    const double to_q = to_q_, dt = drag_time_;
    const bool drag = P.has_surfaces;
    if (terms == RateTerms::Pressure) {
      // p = c^2 rho = (c^2 / to_q) q
      const double c = sim_.derived().sound_speed, to_p = c * c / to_q;
      const View dp = scratch_q_;
      if (wq) ops_.update(to_p, *wq, 0.0, dp);
      else ops_.fill(dp, 0.0);
      sim_.pressure_product(dp, Rows(out_v.data(), owned_, Dim));
      static const std::string label = "poresph::steady::linear_gradient_rows";
      Kokkos::parallel_for(
          label, Kokkos::RangePolicy<ExecSpace>(space_, 0, owned_), KOKKOS_LAMBDA(int i) {
            const double weight = velocity_row_weight(fluid(i), drag ? P.wall_drag(i) : 0.0, dt);
            for (int d = 0; d < Dim; ++d) out_v(i * Dim + d) = fluid(i) != 0 ? out_v(i * Dim + d) * weight : 0.0;
          });
      space_.fence();
      ops_.fill(out_q, 0.0);
      return;
    }
    if (terms == RateTerms::Velocity || terms == RateTerms::Viscous) {
      if (wv) {
        const View w = *wv;
        sim_.velocity_product(Rows(w.data(), owned_, Dim), Rows(out_v.data(), owned_, Dim));
        static const std::string label = "poresph::steady::linear_velocity_rows";
        Kokkos::parallel_for(
            label, Kokkos::RangePolicy<ExecSpace>(space_, 0, owned_), KOKKOS_LAMBDA(int i) {
              const double kappa = drag ? P.wall_drag(i) : 0.0;
              const double weight = velocity_row_weight(fluid(i), kappa, dt);
              for (int d = 0; d < Dim; ++d)
                out_v(i * Dim + d) = fluid(i) != 0 ? weight * (out_v(i * Dim + d) - kappa * w(i * Dim + d)) : 0.0;
            });
        space_.fence();
      } else {
        ops_.fill(out_v, 0.0);
      }
      ops_.fill(out_q, 0.0);
      return;
    }
    if (wv) {
      sim_.continuity_product(Rows(wv->data(), owned_, Dim), out_q);
      static const std::string label = "poresph::steady::linear_divergence_rows";
      Kokkos::parallel_for(
          label, Kokkos::RangePolicy<ExecSpace>(space_, 0, owned_),
          KOKKOS_LAMBDA(int i) { out_q(i) = fluid(i) != 0 ? out_q(i) * (fluid(i) * to_q) : 0.0; });
      space_.fence();
    } else {
      ops_.fill(out_q, 0.0);
    }
    ops_.fill(out_v, 0.0);
  }

  // The simulation's fluid state to y + step (wv, wq).
  void set_state(double step, const View* dv, const View* dq) {
    const auto P = sim_.particles();
    const auto bv = base_v_, bq = base_q_, fluid = fluid_;
    const bool has_v = dv != nullptr, has_q = dq != nullptr;
    const View wv = has_v ? *dv : View(), wq = has_q ? *dq : View();
    const double from_q = 1.0 / to_q_;
    static const std::string label = "poresph::steady::set_state";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, owned_), KOKKOS_LAMBDA(int i) {
          if (fluid(i) == 0) return;
          for (int d = 0; d < Dim; ++d) P.v(i, d) = bv(i * Dim + d) + (has_v ? step * wv(i * Dim + d) : 0.0);
          P.rho(i) = (bq(i) + (has_q ? step * wq(i) : 0.0)) * from_q;
        });
    space_.fence();
  }

  // F at the simulation's state (of the given terms only: see apply()).
  void evaluate(const View& out_v, const View& out_q, RateTerms terms = RateTerms::All) {
    sim_.compute_rates(terms);
    ++(terms == RateTerms::All ? evaluations_ : partial_evaluations_);
    const auto P = sim_.particles();
    const auto fluid = fluid_;
    const bool drag = P.has_surfaces;
    const double to_q = to_q_, dt = drag_time_;
    static const std::string label = "poresph::steady::residual";
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(space_, 0, owned_), KOKKOS_LAMBDA(int i) {
          const double kappa = drag ? P.wall_drag(i) : 0.0;
          const double weight = velocity_row_weight(fluid(i), kappa, dt);
          for (int d = 0; d < Dim; ++d) out_v(i * Dim + d) = weight * (P.dvdt(i, d) - kappa * P.v(i, d));
          out_q(i) = fluid(i) * to_q * P.drhodt(i);
        });
    space_.fence();
  }

  Sim& sim_;
  ExecSpace space_;
  KrylovVectors<ExecSpace> ops_;
  int owned_;
  double to_q_ = 1, drag_time_ = 0, velocity_scale_ = 1;
  long long evaluations_ = 0, partial_evaluations_ = 0;
  bool linear_products_ = false, differenced_partials_ = false;
  View base_v_, base_q_, residual_v_, residual_q_, scratch_v_, scratch_q_, fluid_;
  // F of each part of the terms at the state, by RateTerms less one.
  struct PartialBase {
    View v, q;
    bool current = false;
  };
  PartialBase partial_[4];  // Pressure, Continuity, Velocity, Viscous
};

}  // namespace poresph
