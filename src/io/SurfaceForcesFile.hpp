#pragma once
// surface_forces.csv: the fluid's force on the solid at the end of a stage
// (diagnostics/SurfaceLoads.hpp), one row a grain with its torque about its
// centre, then the plane walls' and an image's totals, and the fluid's mass
// times the body force, which the surfaces hold up at a steady state. A
// scene without surfaces has none.
#include <cstdio>
#include <memory>
#include <string>

#include "diagnostics/Observer.hpp"
#include "diagnostics/StageSetting.hpp"
#include "diagnostics/SurfaceLoads.hpp"
#include "io/Summary.hpp"

namespace poresph {

// The file's text: header and rows (forces in N, per metre of depth in 2D;
// torques in N m, per metre in 2D, about the axis out of the plane).
template <int Dim>
std::string surface_forces_csv(const SurfaceLoads<Dim> &loads, const std::vector<Grain> &grains) {
  constexpr int kT = spin_components<Dim>();
  std::string text = "surface,index";
  for (int d = 0; d < Dim; ++d) text += std::string(",force_") + "xyz"[d];
  if (kT == 1)
    text += ",torque";
  else
    for (int c = 0; c < kT; ++c) text += std::string(",torque_") + "xyz"[c];
  for (int d = 0; d < Dim; ++d) text += std::string(",centre_") + "xyz"[d];
  text += ",radius\n";
  char buffer[64];
  auto row = [&](const std::string &surface, const std::string &index, const double *force, const double *torque,
                 const Grain *grain) {
    text += surface + "," + index;
    for (int d = 0; d < Dim; ++d) std::snprintf(buffer, sizeof buffer, ",%.17g", force[d]), text += buffer;
    for (int c = 0; c < kT; ++c) {
      if (torque)
        std::snprintf(buffer, sizeof buffer, ",%.17g", torque[c]), text += buffer;
      else
        text += ",";
    }
    for (int d = 0; d < Dim; ++d) {
      if (grain)
        std::snprintf(buffer, sizeof buffer, ",%.17g", grain->centre[d]), text += buffer;
      else
        text += ",";
    }
    if (grain)
      std::snprintf(buffer, sizeof buffer, ",%.17g\n", grain->radius), text += buffer;
    else
      text += ",\n";
  };
  for (size_t g = 0; g < loads.grain_force.size(); ++g)
    row("grain", std::to_string(g), loads.grain_force[g].data(), loads.grain_torque[g].data(), &grains[g]);
  row("walls", "", loads.walls.data(), nullptr, nullptr);
  row("image", "", loads.image.data(), nullptr, nullptr);
  row("body_force_on_fluid", "", loads.body_force_on_fluid.data(), nullptr, nullptr);
  return text;
}

template <int Dim, class Sim>
class SurfaceForcesFile : public Observer<Sim> {
 public:
  explicit SurfaceForcesFile(const std::string &path) : path_(path) {}

  static std::unique_ptr<Observer<Sim>> make(const StageSetting<Sim> &s) {
    if (!s.sim.particles().has_surfaces) return nullptr;
    return std::make_unique<SurfaceForcesFile>(s.output_dir + "/surface_forces" + s.suffix + ".csv");
  }
  bool writes() const override { return true; }

  void at_end(Sim &sim) override {
    const SurfaceLoads<Dim> loads = sim.surface_loads();
    if (sim.communicator().rank() == 0)
      write_file_atomically(path_, surface_forces_csv<Dim>(loads, sim.scene().grains));
  }

 private:
  std::string path_;
};

}  // namespace poresph
