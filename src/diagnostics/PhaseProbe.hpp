#pragma once
// Two fluids (the Phases sublist): at the end of the stage, each phase's
// saturation (the fraction of the fluid volume it holds), its superficial
// velocity along the driven axis (its volume flux over the cell's whole
// volume) and, given Phases/Single Phase Permeability, its relative
// permeability k_r = (U_p mu_p / (rho_p |F|)) / k, for summary.json.
#include <Kokkos_Core.hpp>

#include <memory>
#include <string>
#include <vector>

#include "core/Particles.hpp"
#include "diagnostics/Observer.hpp"
#include "diagnostics/StageSetting.hpp"

namespace poresph {

// Volume and flux of each phase's fluid particles on this process: the
// volume of a fixed particle is m / rho0 of its phase (dx^N on the lattice).
template <class ExecSpace, class ParticleSet>
PhaseSums phase_sums(const ParticleSet& P, int phase, double rho0, int axis) {
  const auto kind = P.kind;
  const auto which = P.phase;
  const auto m = P.m;
  const auto v = P.v;
  PhaseSums sums;
  const auto policy = Kokkos::RangePolicy<ExecSpace>(ExecSpace(), 0, P.owned);
  static const std::string volume_label = "poresph::phase_volume", flux_label = "poresph::phase_flux";
  Kokkos::parallel_reduce(
      volume_label, policy,
      KOKKOS_LAMBDA(int i, double& sum) { sum += kind(i) == kFluid && which(i) == phase ? m(i) / rho0 : 0.0; },
      sums.volume);
  Kokkos::parallel_reduce(
      flux_label, policy,
      KOKKOS_LAMBDA(int i, double& sum) {
        sum += kind(i) == kFluid && which(i) == phase ? m(i) / rho0 * v(i, axis) : 0.0;
      },
      sums.flux);
  return sums;
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
    fluid += s.volume;
    sums.push_back(s);
  }
  const double force = body_force_magnitude(scene), k = scene.single_phase_permeability;
  std::vector<PhaseMeasure> measures;
  for (size_t p = 0; p < sums.size(); ++p) {
    PhaseMeasure m;
    m.name = scene.phases[p].name;
    m.axis = axis;
    m.saturation = sums[p].volume / fluid;
    m.superficial_velocity = sums[p].flux / cell;
    // The phase's own Darcy k (its viscous pull against the force on it, per
    // unit volume rho_p |F|): mu_p / (rho_p |F|) = nu_p / |F| at rho_p.
    m.has_relative_permeability = k > 0 && force > 0;
    if (m.has_relative_permeability)
      m.relative_permeability = m.superficial_velocity * scene.phases[p].kinematic_viscosity / force / k;
    measures.push_back(m);
  }
  return measures;
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
  void at_end(Sim& sim) override { measures_ = measure_phases(sim, scene_, axis_); }
  void report(StageObservations& o) const override { o.phases = measures_; }

 private:
  const SceneConfig& scene_;
  int axis_;
  std::vector<PhaseMeasure> measures_;
};

}  // namespace poresph
