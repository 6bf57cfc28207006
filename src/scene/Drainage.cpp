#include "scene/Drainage.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iomanip>
#include <queue>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "geometry/DistanceTransform.hpp"

namespace poresph {

namespace {

// The lattice index of (i, j, k) moved by one point along `axis` (step +1
// or -1), wrapped across a periodic face; -1 past a closed one.
long long step_along(const DrainageLattice& lattice, long long n, int axis, int step, bool wrap) {
  std::array<long long, 3> at{{n % lattice.shape[0], (n / lattice.shape[0]) % lattice.shape[1],
                               n / (lattice.shape[0] * lattice.shape[1])}};
  at[axis] += step;
  if (at[axis] < 0 || at[axis] >= lattice.shape[axis]) {
    if (!wrap) return -1;
    at[axis] = (at[axis] + lattice.shape[axis]) % lattice.shape[axis];
  }
  return at[0] + lattice.shape[0] * (at[1] + lattice.shape[1] * at[2]);
}

// pore_radius, with the lattice open (not closed by solid) at both ends of
// `open_axis` where it is not periodic: a sample's faces on its reservoirs.
std::vector<double> pore_radius_open_at(const DrainageLattice& lattice, int open_axis) {
  if (static_cast<long long>(lattice.fluid.size()) != lattice.size())
    throw std::logic_error("pore_radius: the fluid flags do not cover the lattice");
  // A closed axis is bounded by solid: one layer of it on either side.
  std::array<long long, 3> padded = lattice.shape, first{};
  for (int d = 0; d < lattice.dimension; ++d)
    if (!lattice.periodic[d] && d != open_axis) padded[d] += 2, first[d] = 1;
  std::vector<char> solid(static_cast<size_t>(padded[0] * padded[1] * padded[2]), 1);
  for (long long k = 0; k < lattice.shape[2]; ++k)
    for (long long j = 0; j < lattice.shape[1]; ++j)
      for (long long i = 0; i < lattice.shape[0]; ++i)
        solid[static_cast<size_t>(i + first[0] + padded[0] * (j + first[1] + padded[1] * (k + first[2])))] =
            !lattice.fluid[static_cast<size_t>(i + lattice.shape[0] * (j + lattice.shape[1] * k))];
  const auto squared = squared_distance_transform(padded, lattice.dimension, lattice.periodic, solid);
  std::vector<double> radius(lattice.fluid.size(), 0.0);
  for (long long k = 0; k < lattice.shape[2]; ++k)
    for (long long j = 0; j < lattice.shape[1]; ++j)
      for (long long i = 0; i < lattice.shape[0]; ++i) {
        const size_t n = static_cast<size_t>(i + lattice.shape[0] * (j + lattice.shape[1] * k));
        const double d2 =
            squared[static_cast<size_t>(i + first[0] + padded[0] * (j + first[1] + padded[1] * (k + first[2])))];
        // No solid anywhere: every ball fits; the cell's width bounds it.
        if (lattice.fluid[n]) radius[n] = std::isfinite(d2) ? std::sqrt(d2) - 0.5 : HUGE_VAL;
      }
  return radius;
}
}  // namespace

std::vector<double> pore_radius(const DrainageLattice& lattice) { return pore_radius_open_at(lattice, -1); }

namespace {

bool on_layer(const DrainageLattice& lattice, long long n, int axis, long long layer) {
  const std::array<long long, 3> at{{n % lattice.shape[0], (n / lattice.shape[0]) % lattice.shape[1],
                                     n / (lattice.shape[0] * lattice.shape[1])}};
  return at[axis] == layer;
}

// Whether the non-wetting phase enters at point n: the lattice layers next
// to the inlet's face (with trapping, the low one only: the high one is
// the wetting phase's outlet).
bool at_inlet(const DrainageLattice& lattice, long long n, const DrainageInlet& inlet) {
  return on_layer(lattice, n, inlet.axis, 0) ||
         (!inlet.trapping && on_layer(lattice, n, inlet.axis, lattice.shape[inlet.axis] - 1));
}

// Each fluid point's reach radius: the largest r at which it is the centre
// of a ball that reaches it from the inlet through centres of balls of
// radius r, i.e. the widest path to it, the least pore radius along the
// path made largest (a Dijkstra search on the bottleneck). From anywhere:
// its pore radius. 0 where no path leads.
std::vector<double> reach_radius(const DrainageLattice& lattice, const std::vector<double>& radius,
                                 const DrainageInlet& inlet) {
  if (inlet.anywhere) return radius;
  const long long size = lattice.size();
  std::vector<double> reach(radius.size(), 0.0);
  std::priority_queue<std::pair<double, long long>> front;
  for (long long n = 0; n < size; ++n)
    if (lattice.fluid[n] && at_inlet(lattice, n, inlet)) reach[n] = radius[n], front.push({radius[n], n});
  while (!front.empty()) {
    const auto [bottleneck, n] = front.top();
    front.pop();
    if (bottleneck < reach[n]) continue;  // a wider path came first
    for (int d = 0; d < lattice.dimension; ++d)
      for (int step : {-1, 1}) {
        const long long m = step_along(lattice, n, d, step, lattice.periodic[d] && d != inlet.axis);
        if (m < 0 || !lattice.fluid[m]) continue;
        const double through = std::min(bottleneck, radius[m]);
        if (through > reach[m]) reach[m] = through, front.push({through, m});
      }
  }
  return reach;
}

// Adds to `drained` the balls of radius r about the points whose reach is r or more.
void add_balls(const DrainageLattice& lattice, const std::vector<double>& reach, double r, std::vector<char>& drained) {
  std::vector<char> centre(reach.size(), 0);
  for (size_t n = 0; n < reach.size(); ++n) centre[n] = lattice.fluid[n] && reach[n] >= r;
  const auto to_centre = squared_distance_transform(lattice.shape, lattice.dimension, lattice.periodic, centre);
  const double within = r * r * (1 + 1e-12);
  for (size_t n = 0; n < reach.size(); ++n)
    if (lattice.fluid[n] && to_centre[n] <= within) drained[n] = 1;
}

double largest_radius(const DrainageLattice& lattice, const std::vector<double>& radius) {
  double largest = 0;
  for (size_t n = 0; n < radius.size(); ++n)
    if (lattice.fluid[n]) largest = std::max(largest, radius[n]);
  // No solid at all: a ball as wide as the cell.
  if (!std::isfinite(largest)) {
    largest = 0;
    for (int d = 0; d < lattice.dimension; ++d) largest = std::max(largest, 0.5 * double(lattice.shape[d]));
  }
  return largest;
}

// The radii of the drainage's steps, largest first: from the largest pore
// radius down to half a spacing, at most kDrainageSteps + 1 of them and at
// least a quarter of a spacing apart, and `also` (> 0) among them.
std::vector<double> drainage_ladder(const DrainageLattice& lattice, const std::vector<double>& radius,
                                    double also = 0) {
  constexpr int kDrainageSteps = 100;
  const double largest = largest_radius(lattice, radius);
  const double step = std::max(0.25, (largest - 0.5) / kDrainageSteps);
  std::vector<double> ladder;
  for (int k = 0; largest - k * step > 0.5; ++k) ladder.push_back(largest - k * step);
  ladder.push_back(0.5);
  if (also > 0 && std::find(ladder.begin(), ladder.end(), also) == ladder.end()) {
    ladder.push_back(also);
    std::sort(ladder.begin(), ladder.end(), std::greater<double>());
  }
  return ladder;
}

// The drainage as it goes, step by step: the points drained so far and,
// with trapping, the wetting phase trapped so far. With trapping the cell
// is a sample between two reservoirs: nothing wraps across the inlet's
// face (balls included), and the faces are open. Trapped wetting phase
// stays (it cannot leave, and the non-wetting phase cannot squeeze it), so
// the balls of later steps fit in the pore space less it: the pore radius
// and the reach are remade on that space whenever it shrinks, from the
// start (wetting phase no path joins to the outlet is trapped before any
// ball comes).
class DrainageSweep {
 public:
  DrainageSweep(const DrainageLattice& lattice, const std::vector<double>& radius, const DrainageInlet& inlet)
      : open_(lattice), inlet_(inlet), drained_(radius.size(), 0) {
    if (inlet_.trapping) {
      open_.periodic[inlet_.axis] = false;
      trap();
      reach_ = reach_radius(open_, pore_radius_open_at(open_, inlet_.axis), inlet_);
    } else {
      reach_ = reach_radius(lattice, radius, inlet);
    }
  }

  // The points drained once the balls of radius r are added (kept apart).
  std::vector<char> with_balls(double r) const {
    auto drained = drained_;
    add_balls(open_, reach_, r, drained);
    return drained;
  }
  // Adds them; with trapping, the wetting phase the outlet no longer reaches is trapped.
  void advance(double r) {
    drained_ = with_balls(r);
    if (inlet_.trapping && trap()) reach_ = reach_radius(open_, pore_radius_open_at(open_, inlet_.axis), inlet_);
  }
  const std::vector<char>& drained() const { return drained_; }

 private:
  // The wetting phase (open, not drained) that no path of wetting phase
  // joins to the outlet, the lattice layer at the high side of the inlet's
  // face, leaves the open pore space. Whether any did.
  bool trap() {
    const long long size = open_.size(), outlet = open_.shape[inlet_.axis] - 1;
    std::vector<char> joined(drained_.size(), 0);
    std::vector<long long> front;
    auto wetting = [&](long long n) { return open_.fluid[n] && !drained_[n]; };
    for (long long n = 0; n < size; ++n)
      if (wetting(n) && on_layer(open_, n, inlet_.axis, outlet)) joined[n] = 1, front.push_back(n);
    while (!front.empty()) {
      const long long n = front.back();
      front.pop_back();
      for (int d = 0; d < open_.dimension; ++d)
        for (int step : {-1, 1}) {
          const long long m = step_along(open_, n, d, step, open_.periodic[d] && d != inlet_.axis);
          if (m >= 0 && wetting(m) && !joined[m]) joined[m] = 1, front.push_back(m);
        }
    }
    bool trapped = false;
    for (long long n = 0; n < size; ++n)
      if (wetting(n) && !joined[n]) open_.fluid[n] = 0, trapped = true;
    return trapped;
  }

  DrainageLattice open_;  // the fluid points not trapped
  DrainageInlet inlet_;
  std::vector<double> reach_;
  std::vector<char> drained_;
};

}  // namespace

std::vector<char> drained_points(const DrainageLattice& lattice, const std::vector<double>& radius, double r,
                                 const DrainageInlet& inlet) {
  DrainageSweep sweep(lattice, radius, inlet);
  for (double step : drainage_ladder(lattice, radius, r))
    if (step > r) sweep.advance(step);
  return sweep.with_balls(r);
}

double drained_saturation(const DrainageLattice& lattice, const std::vector<char>& drained) {
  long long fluid = 0, filled = 0;
  for (size_t n = 0; n < drained.size(); ++n) fluid += lattice.fluid[n] != 0, filled += drained[n] != 0;
  return fluid > 0 ? static_cast<double>(filled) / static_cast<double>(fluid) : 0.0;
}

namespace {
// The curve (drainage_curve), and the points drained at the first of its
// steps that `kept` accepts (empty if none does): one sweep for both.
template <class Keep>
std::vector<DrainageStep> curve_keeping(const DrainageLattice& lattice, const std::vector<double>& radius,
                                        const DrainageInlet& inlet, double also, const Keep& kept,
                                        std::vector<char>& kept_points) {
  DrainageSweep sweep(lattice, radius, inlet);
  std::vector<DrainageStep> curve;
  for (double step : drainage_ladder(lattice, radius, also)) {
    sweep.advance(step);
    curve.push_back({step, drained_saturation(lattice, sweep.drained())});
    if (kept_points.empty() && kept(curve.back())) kept_points = sweep.drained();
  }
  return curve;
}
}  // namespace

std::vector<DrainageStep> drainage_curve(const DrainageLattice& lattice, const std::vector<double>& radius,
                                         const DrainageInlet& inlet, double also) {
  std::vector<char> none;
  return curve_keeping(lattice, radius, inlet, also, [](const DrainageStep&) { return false; }, none);
}

DrainageStep drain_to_saturation(const DrainageLattice& lattice, const std::vector<double>& radius,
                                 double saturation, const DrainageInlet& inlet) {
  DrainageStep reached;
  std::vector<char> points;
  const auto curve = curve_keeping(
      lattice, radius, inlet, 0,
      [&](const DrainageStep& step) { return step.saturation >= saturation ? (reached = step, true) : false; }, points);
  return points.empty() ? DrainageStep{0.0, curve.back().saturation} : reached;
}

DrainagePlacement place_by_drainage(const PhaseConfig::Drainage& rule, const DrainageLattice& lattice, double dx) {
  const DrainageInlet inlet{rule.inlet_axis, rule.inlet_anywhere, rule.trapping};
  const auto radius = pore_radius(lattice);
  DrainagePlacement placed;
  // The step placed is a row of the curve: the given radius (a step of its
  // own), or the first step that reaches the target saturation
  // (drain_to_saturation's, and drained_points' there).
  const bool by_saturation = rule.saturation > 0;
  const double given = by_saturation ? 0 : rule.radius / dx;  // in spacings
  double r = given;
  placed.curve = curve_keeping(
      lattice, radius, inlet, given,
      [&](const DrainageStep& step) {
        const bool here = by_saturation ? step.saturation >= rule.saturation : step.radius == given;
        if (here) r = step.radius, placed.saturation = step.saturation;
        return here;
      },
      placed.drained);
  if (by_saturation && placed.drained.empty()) {
    std::ostringstream msg;
    msg << std::setprecision(6) << "Phases/Phase 1/Drainage/Saturation = " << rule.saturation
        << " is not reached: drainage from the inlet fills at most " << placed.curve.back().saturation
        << " of the fluid (the rest is pore space no path from the inlet reaches"
        << (rule.trapping ? ", or wetting phase trapped" : "") << "); lower it, or set Inlet";
    throw std::invalid_argument(msg.str());
  }
  placed.radius = r * dx;
  placed.curvature = drainage_curvature(lattice.dimension, rule.contact_angle, placed.radius);
  placed.capillary_pressure = rule.surface_tension * placed.curvature;
  for (auto& step : placed.curve) step.radius *= dx;
  return placed;
}

}  // namespace poresph
