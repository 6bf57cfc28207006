#pragma once
// particles.csv (Output/Final Particles CSV): every particle's id, kind,
// position, velocity, density and pressure (and phase, with two fluids) at
// the end of a run, one row a particle, gathered on rank 0 (perf/plot_velocity.py draws it).
#include <Kokkos_Core.hpp>

#include <cmath>
#include <cstdio>
#include <string>

#include "io/Summary.hpp"

namespace poresph {

// The owned particles' state as CSV, for plots: one row a particle.
template <int Dim, class Sim>
void write_particles_csv(const Sim& sim, const std::string& path) {
  const auto& P = sim.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.v);
  auto rho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.rho);
  auto p = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.p);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.kind);
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.id);
  const auto& scene = sim.scene();
  const bool phases = scene.has_phases();
  auto phase = Kokkos::create_mirror_view(P.phase);
  if (phases) Kokkos::deep_copy(phase, P.phase);
  std::string header = "id,kind";
  for (int d = 0; d < Dim; ++d) header += std::string(",") + "xyz"[d];
  for (int d = 0; d < Dim; ++d) header += std::string(",v") + "xyz"[d];
  // A moving interface: each particle's phase field phi after its phase.
  const bool colours = P.has_colour;
  auto colour = Kokkos::create_mirror_view(P.colour);
  if (colours) Kokkos::deep_copy(colour, P.colour);
  header += phases ? (colours ? ",rho,p,phase,phi\n" : ",rho,p,phase\n") : ",rho,p\n";
  std::string text;
  char buffer[64];
  for (int i = 0; i < P.owned; ++i) {
    text += std::to_string(id(i)) + "," + std::to_string(kind(i));
    for (int d = 0; d < Dim; ++d) {
      // Positions stay unwrapped between neighbour-list rebuilds: wrap for output.
      double xd = x(i, d);
      if (scene.periodic[d]) xd -= scene.cell_size[d] * std::floor(xd / scene.cell_size[d]);
      std::snprintf(buffer, sizeof buffer, ",%.10g", xd);
      text += buffer;
    }
    for (int d = 0; d < Dim; ++d) std::snprintf(buffer, sizeof buffer, ",%.10g", v(i, d)), text += buffer;
    std::snprintf(buffer, sizeof buffer, ",%.12g,%.10g", rho(i), p(i));
    text += buffer;
    if (phases) text += "," + std::to_string(int(phase(i)));
    if (colours) std::snprintf(buffer, sizeof buffer, ",%.12g", colour(i)), text += buffer;
    text += "\n";
  }
  const std::string all = sim.communicator().gather_text(text);
  if (sim.communicator().rank() == 0) write_file_atomically(path, header + all);
}

}  // namespace poresph
