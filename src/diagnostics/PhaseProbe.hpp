#pragma once
// Two fluids (the Phases sublist): at the end of the stage, each phase's
// saturation (the fraction of the fluid volume it holds), its superficial
// velocity along the driven axis (its volume flux over the cell's whole
// volume) and, given Phases/Single Phase Permeability, its relative
// permeability k_r = (U_p mu_p / (rho_p |F|)) / k, and its mass, for
// summary.json; with surface tension and a round phase-1 region (a drop),
// the pressure jump across its surface against Laplace's law and the
// largest speed (the spurious currents of a drop at rest).
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/Kernel.hpp"
#include "core/Particles.hpp"
#include "diagnostics/Observer.hpp"
#include "diagnostics/StageSetting.hpp"
#include "physics/PairTerms.hpp"
#include "scene/SceneConfig.hpp"

namespace poresph {

// One phase's sums over this process's fluid particles, in one pass: the
// volume (of a fixed particle m / rho0 of its phase, dx^N on the lattice),
// the volume flux along an axis, the mass and the volume-weighted pressure
// (PhaseSums, in that order).
template <class ParticleSet>
struct PhaseSumsOf {
  using value_type = double[];
  static constexpr unsigned kValues = 4;
  unsigned value_count = kValues;
  decltype(ParticleSet::kind) kind;
  decltype(ParticleSet::phase) which;
  decltype(ParticleSet::m) m;
  decltype(ParticleSet::v) v;
  decltype(ParticleSet::p) p;
  int phase, axis;
  double rho0;
  KOKKOS_INLINE_FUNCTION void operator()(int i, value_type sums) const {
    if (kind(i) != kFluid || which(i) != phase) return;
    const double volume = m(i) / rho0;
    sums[0] += volume;
    sums[1] += volume * v(i, axis);
    sums[2] += m(i);
    sums[3] += volume * p(i);
  }
};

template <class ExecSpace, class ParticleSet>
PhaseSums phase_sums(const ParticleSet& P, int phase, double rho0, int axis) {
  using Sums = PhaseSumsOf<ParticleSet>;
  const Sums of{Sums::kValues, P.kind, P.phase, P.m, P.v, P.p, phase, axis, rho0};
  double values[Sums::kValues] = {};
  static const std::string label = "poresph::phase_sums";
  Kokkos::parallel_reduce(label, Kokkos::RangePolicy<ExecSpace>(ExecSpace(), 0, P.owned), of, values);
  PhaseSums sums;
  sums.volume = values[0], sums.flux = values[1], sums.mass = values[2], sums.pressure = values[3];
  return sums;
}

// The drop's pressures: the mean p of phase 1 at r < R - 3h and of phase 0
// at r > R + 3h from the region's centre (its nearest image), beyond the
// kernel's reach of the interface; and the largest speed of the fluid.
template <class Sim>
CapillaryMeasure measure_capillary(const Sim& sim, const SceneConfig& scene) {
  constexpr int Dim = Sim::dimension;
  const auto& P = sim.particles();
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  const auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  const auto rho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.rho);
  const auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  const auto phase = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.phase);
  const PhaseConfig& drop = scene.phases[1];
  const double c2 = sim.derived().sound_speed * sim.derived().sound_speed;
  const double reach = kSupportRadiusInH * sim.derived().smoothing_length;
  double sums[4] = {0, 0, 0, 0}, speed = 0;  // inside p and count, outside p and count
  for (int i = 0; i < P.owned; ++i) {
    if (kind(i) != kFluid) continue;
    double at[3] = {0, 0, 0}, v2 = 0;
    for (int d = 0; d < Dim; ++d) at[d] = x(i, d), v2 += v(i, d) * v(i, d);
    speed = std::max(speed, std::sqrt(v2));
    const double r = distance_to_centre(scene, drop, at), p = pressure_from_density(rho(i), c2);
    if (phase(i) == 1 && r < drop.region_radius - reach) sums[0] += p, sums[1] += 1;
    if (phase(i) == 0 && r > drop.region_radius + reach) sums[2] += p, sums[3] += 1;
  }
  CapillaryMeasure c;
  for (double& s : sums) s = sim.communicator().sum(s);
  speed = sim.communicator().max(speed);
  if (!(sums[1] > 0) || !(sums[3] > 0)) return c;  // a drop too small (or too large) for its interior
  c.measured = true;
  c.inside_pressure = sums[0] / sums[1];
  c.outside_pressure = sums[2] / sums[3];
  c.pressure_jump = c.inside_pressure - c.outside_pressure;
  c.laplace_pressure = (Dim - 1) * scene.surface_tension / drop.region_radius;
  c.max_speed = speed;
  double mu = 0;
  for (const auto& p : scene.phases) mu = std::max(mu, p.density * p.kinematic_viscosity);
  c.capillary_number = speed * mu / scene.surface_tension;
  return c;
}

// The phases' measures of a simulation now (summed over processes).
template <class Sim>
std::vector<PhaseMeasure> measure_phases(const Sim& sim, const SceneConfig& scene, int axis) {
  using ExecSpace = typename Sim::ExecutionSpace;
  double cell = 1.0;
  for (int d = 0; d < scene.dimension; ++d) cell *= scene.cell_size[d];
  std::vector<PhaseSums> sums;
  double fluid = 0;
  for (int p = 0; p < static_cast<int>(scene.phases.size()); ++p) {
    PhaseSums s = phase_sums<ExecSpace>(sim.particles(), p, scene.phases[p].density, axis);
    s.volume = sim.communicator().sum(s.volume);
    s.flux = sim.communicator().sum(s.flux);
    s.mass = sim.communicator().sum(s.mass);
    s.pressure = sim.communicator().sum(s.pressure);
    fluid += s.volume;
    sums.push_back(s);
  }
  const double force = driving_force(scene), k = scene.single_phase_permeability;
  std::vector<PhaseMeasure> measures;
  for (size_t p = 0; p < sums.size(); ++p) {
    PhaseMeasure m;
    m.name = scene.phases[p].name;
    m.axis = axis;
    m.saturation = sums[p].volume / fluid;
    m.superficial_velocity = sums[p].flux / cell;
    m.mass = sums[p].mass;
    m.mean_pressure = sums[p].volume > 0 ? sums[p].pressure / sums[p].volume : 0.0;
    m.driven = scene.phase_force_share(static_cast<int>(p)) > 0;
    // The phase's own Darcy k (its viscous pull against the force per unit
    // volume rho |F| on the driven phase, or on each): mu_p / (rho |F|) =
    // nu_p / |F| at one density. With one phase driven, the coupling
    // coefficient k_r,pj of phase p to the driven phase j.
    m.has_relative_permeability = k > 0 && force != 0;
    if (m.has_relative_permeability)
      m.relative_permeability = m.superficial_velocity * scene.phases[p].kinematic_viscosity / force / k;
    if (const auto* field = sim.phase_field()) {  // whole, and the same, on every process
      double dV = 1.0;
      for (int d = 0; d < scene.dimension; ++d) dV *= scene.particle_spacing;
      const double one = field->amount() * dV;
      m.has_phase_field = true;
      m.phase_field_volume = p == 1 ? one : fluid - one;
    }
    measures.push_back(m);
  }
  return measures;
}

// What a drainage placement reports.
inline DrainageMeasure drainage_measure(const DrainagePlacement& placed, const PhaseConfig::Drainage& rule) {
  DrainageMeasure m;
  m.placed = true;
  m.radius = placed.radius, m.saturation = placed.saturation, m.curvature = placed.curvature;
  m.has_capillary_pressure = rule.surface_tension > 0;
  m.capillary_pressure = placed.capillary_pressure;
  m.contact_angle = rule.contact_angle;
  m.inlet = rule.inlet_anywhere ? "anywhere" : std::string(1, "xyz"[rule.inlet_axis]);
  m.curve = placed.curve;
  return m;
}

template <class Sim>
class PhaseProbe : public Observer<Sim> {
 public:
  PhaseProbe(const SceneConfig& scene, int axis) : scene_(scene), axis_(axis) {}
  // A scene with phases; along the force's axis (x without a force: a
  // channel driven by its walls).
  static std::unique_ptr<Observer<Sim>> make(const StageSetting<Sim>& s) {
    if (!s.scene.has_phases()) return nullptr;
    return std::make_unique<PhaseProbe>(s.scene, s.force_axis >= 0 ? s.force_axis : 0);
  }
  void at_end(Sim& sim) override {
    measures_ = measure_phases(sim, scene_, axis_);
    // A drop held where it was put (a moving one beside a solid goes elsewhere).
    const bool drop_in_place =
        !scene_.moving_interface || (!scene_.has_solid() && scene_.walls == WallType::None);
    if (scene_.surface_tension > 0 && scene_.phases[1].round() && drop_in_place)
      capillary_ = measure_capillary(sim, scene_);
    if (scene_.phases[1].drained()) drainage_ = drainage_measure(sim.drainage(), scene_.phases[1].drainage);
  }
  void report(StageObservations& o) const override {
    o.phases = measures_;
    o.capillary = capillary_;
    o.drainage = drainage_;
  }

 private:
  const SceneConfig& scene_;
  int axis_;
  std::vector<PhaseMeasure> measures_;
  CapillaryMeasure capillary_;
  DrainageMeasure drainage_;
};

}  // namespace poresph
