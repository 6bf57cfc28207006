#pragma once
// Field files fields[_x]_<step>.h5 of a run, written collectively by every
// process (io/Hdf5File.hpp), with particles.xmf and grid.xmf describing all
// of them as one time series for ParaView (io/Xdmf.hpp). Every file is
// written under a temporary name and renamed when complete. When grains
// move, each file also holds the grains (group /grains: centre, velocity,
// spin, radius, the fluid's and the contacts' force on each, its contacts),
// which grains.xmf describes as points with vectors: ParaView's Glyph
// filter, scaled by radius, draws them as discs or spheres.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/Particles.hpp"
#include "io/Hdf5File.hpp"
#include "scene/SceneConfig.hpp"
#include "io/Summary.hpp"
#include "io/ViewRows.hpp"
#include "io/Xdmf.hpp"
#include "physics/GridInterpolation.hpp"

namespace poresph {

// Field files fields_<step>.h5 in the output directory, with particles.xmf
// and (with a grid) grid.xmf describing all of them as one time series.
template <int Dim>
class FieldWriter {
 public:
  FieldWriter(const SceneConfig& scene, const std::string& output_dir, const std::string& suffix)
      : scene_(scene), dir_(output_dir), suffix_(suffix) {}

  // Frames written before a restart, so that the descriptions keep them.
  void add_earlier_frames(const std::vector<double>& steps, const std::vector<double>& times, long long particles) {
    for (size_t k = 0; k < steps.size(); ++k) add_frame(static_cast<long long>(steps[k]), times[k], particles);
  }
  // The file name of the frame at `step` (fields[_x]_<step>.h5).
  std::string file_name(long long step) const {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "fields%s_%09lld.h5", suffix_.c_str(), step);
    return buffer;
  }
  const std::vector<double>& frame_steps() const { return steps_; }
  const std::vector<double>& frame_times() const { return times_; }

  // The frame of a simulation's current state (app/Simulation.hpp); at the
  // step of the last frame listed (a steady solve continued), its file anew.
  template <class Sim>
  void write(Sim& sim) {
    const auto& P = sim.particles();
    const auto& comm = sim.communicator();
    const int n = P.owned;
    const long long total = sim.fluid_particles() + sim.boundary_particles();
    std::vector<double> grid_values;
    GridBlock<Dim> block;
    if (!scene_.grid_points.empty()) block = sim.interpolate_to_grid(scene_.grid_points, grid_values);
    auto wants = [&](const char* field) {
      for (const auto& f : scene_.fields)
        if (f == field) return true;
      return false;
    };
    const std::string name = file_name(sim.steps());
    write_hdf5_atomically(dir_ + "/" + name, comm.comm(), [&](Hdf5File& file) {
      file.set_attribute("time", sim.time());
      file.set_attribute("step", sim.steps());
      // Vectors with three components, z = 0 in 2D: what ParaView expects of points and vectors.
      auto as_3d = [&](const auto& view, bool wrap) {
        const auto rows = owned_rows(view, n);
        std::vector<double> out(static_cast<size_t>(n) * 3, 0.0);
        for (int i = 0; i < n; ++i)
          for (int d = 0; d < Dim; ++d) {
            const double value = rows[static_cast<size_t>(i) * Dim + d];
            // Positions stay unwrapped between neighbour-list rebuilds: wrap for output.
            out[static_cast<size_t>(i) * 3 + d] = wrap ? wrapped(value, d) : value;
          }
        return out;
      };
      file.write_rows("position", as_3d(P.x, true).data(), n, 3);
      if (wants("velocity")) file.write_rows("velocity", as_3d(P.v, false).data(), n, 3);
      if (wants("density")) file.write_rows("density", owned_rows(P.rho, n).data(), n, 0);
      if (wants("pressure")) file.write_rows("pressure", owned_rows(P.p, n).data(), n, 0);
      if (wants("kind")) file.write_rows("kind", owned_rows(P.kind, n).data(), n, 0);
      if (wants("grain")) file.write_rows("grain", owned_rows(sim.grain_ids(), n).data(), n, 0);
      if (wants("id")) file.write_rows("id", owned_rows(P.id, n).data(), n, 0);
      if (wants("phase")) file.write_rows("phase", fluid_phases(P, n).data(), n, 0);
      if (wants("colour")) file.write_rows("colour", owned_rows(P.colour, n).data(), n, 0);
      if (!scene_.grid_points.empty()) write_grid(file, block, grid_values);
      if (scene_.moving_grains()) write_grains(file, sim.rigid_grains().bodies(), comm.rank() == 0);
    });
    if (steps_.empty() || steps_.back() != static_cast<double>(sim.steps())) add_frame(sim.steps(), sim.time(), total);
    if (comm.rank() == 0) describe();
  }

  // On one process: particles.xmf, grid.xmf and grains.xmf describe
  // exactly the frames listed (none: no description), as after a restart
  // that removed the frames written past its checkpoint.
  void describe() {
    const std::string particles = dir_ + "/particles" + suffix_ + ".xmf", grid = dir_ + "/grid" + suffix_ + ".xmf",
                      grains = dir_ + "/grains" + suffix_ + ".xmf";
    if (particle_frames_.empty()) {
      for (const std::string& name : {particles, grid, grains}) std::remove(name.c_str());
      return;
    }
    write_file_atomically(particles, xdmf_time_series("particles", particle_frames_));
    if (!scene_.grid_points.empty()) write_file_atomically(grid, xdmf_time_series("grid", grid_frames_));
    else std::remove(grid.c_str());
    if (scene_.moving_grains()) write_file_atomically(grains, xdmf_time_series("grains", grain_frames_));
    else std::remove(grains.c_str());
  }

 private:
  // Each owned particle's phase for the field files: a fluid particle's
  // phase, -1 for a boundary particle (which belongs to no phase).
  template <class ParticleSet>
  static std::vector<int> fluid_phases(const ParticleSet& P, int n) {
    auto phase = owned_rows(P.phase, n);
    const auto kind = owned_rows(P.kind, n);
    for (int i = 0; i < n; ++i)
      if (kind[i] != kFluid) phase[i] = -1;
    return phase;
  }

  // A coordinate along d wrapped into the cell where d is periodic.
  double wrapped(double value, int d) const {
    return scene_.periodic[d] ? value - scene_.cell_size[d] * std::floor(value / scene_.cell_size[d]) : value;
  }

  // Grid arrays are stored slowest direction first (z, y, x), as XDMF reads
  // them; a 2D grid is one layer of a 3D one (ParaView's XDMF reader cannot
  // read vectors on a 2D mesh). `fill` is what the missing z takes.
  std::vector<long long> grid_shape(const std::vector<long long>& per_direction, long long fill) const {
    std::vector<long long> shape(per_direction.rbegin(), per_direction.rend());
    if (Dim == 2) shape.insert(shape.begin(), fill);
    return shape;
  }

  void write_grid(Hdf5File& file, const GridBlock<Dim>& block, const std::vector<double>& values) {
    std::vector<long long> global, offset, count;
    for (int d = 0; d < Dim; ++d)
      global.push_back(scene_.grid_points[d]), offset.push_back(block.first[d]), count.push_back(block.count[d]);
    const auto g = grid_shape(global, 1), o = grid_shape(offset, 0), c = grid_shape(count, 1);
    const long long nodes = block.nodes();
    std::vector<double> velocity(nodes * 3, 0.0), pressure(nodes), solid(nodes);
    for (long long k = 0; k < nodes; ++k) {
      for (int d = 0; d < Dim; ++d) velocity[k * 3 + d] = values[k * (Dim + 2) + d];
      pressure[k] = values[k * (Dim + 2) + Dim];
      solid[k] = values[k * (Dim + 2) + Dim + 1];
    }
    auto with_components = [](std::vector<long long> shape, long long n) {
      shape.push_back(n);
      return shape;
    };
    file.write_block("grid_velocity", with_components(g, 3), with_components(o, 0), with_components(c, 3),
                     velocity.data());
    file.write_block("grid_pressure", g, o, c, pressure.data());
    file.write_block("grid_solid", g, o, c, solid.data());
  }

  // The grains' state, written by the first process alone (every process
  // holds it all): vectors of three components, as the particles'.
  template <class Bodies>
  void write_grains(Hdf5File& file, const Bodies& bodies, bool writer) {
    const long long n = writer ? static_cast<long long>(bodies.size()) : 0;
    std::vector<double> centre(n * 3, 0.0), velocity(n * 3, 0.0), spin(n * 3, 0.0), radius(n),
        fluid_force(n * 3, 0.0), contact_force(n * 3, 0.0);
    std::vector<int> contacts(n);
    for (long long g = 0; g < n; ++g) {
      const auto& b = bodies[g];
      for (int d = 0; d < Dim; ++d) {
        centre[g * 3 + d] = wrapped(b.centre[d], d);
        velocity[g * 3 + d] = b.velocity[d];
        fluid_force[g * 3 + d] = b.fluid_force[d];
        contact_force[g * 3 + d] = b.contact_force[d];
      }
      for (size_t k = 0; k < b.spin.size(); ++k) spin[g * 3 + (b.spin.size() == 1 ? 2 : k)] = b.spin[k];
      radius[g] = b.radius;
      contacts[g] = b.contacts;
    }
    file.write_rows("grains/centre", centre.data(), n, 3);
    file.write_rows("grains/velocity", velocity.data(), n, 3);
    file.write_rows("grains/spin", spin.data(), n, 3);
    file.write_rows("grains/radius", radius.data(), n, 0);
    file.write_rows("grains/fluid_force", fluid_force.data(), n, 3);
    file.write_rows("grains/contact_force", contact_force.data(), n, 3);
    file.write_rows("grains/contacts", contacts.data(), n, 0);
  }

  void add_frame(long long step, double time, long long particles) {
    steps_.push_back(static_cast<double>(step));
    times_.push_back(time);
    const std::string file = file_name(step);
    XdmfFrame frame;
    frame.time = time;
    frame.file = file;
    frame.mesh.count = particles;
    frame.mesh.positions = "/position";
    const std::vector<long long> scalar{particles}, vector{particles, 3};
    for (const auto& f : scene_.fields) {
      if (f == "velocity") frame.attributes.push_back({"velocity", "/velocity", vector, true, false, 8});
      if (f == "density") frame.attributes.push_back({"density", "/density", scalar, false, false, 8});
      if (f == "pressure") frame.attributes.push_back({"pressure", "/pressure", scalar, false, false, 8});
      if (f == "kind") frame.attributes.push_back({"kind", "/kind", scalar, false, true, 4});
      if (f == "grain") frame.attributes.push_back({"grain", "/grain", scalar, false, true, 4});
      if (f == "id") frame.attributes.push_back({"id", "/id", scalar, false, true, 8});
      if (f == "phase") frame.attributes.push_back({"phase", "/phase", scalar, false, true, 4});
      if (f == "colour") frame.attributes.push_back({"colour", "/colour", scalar, false, false, 8});
    }
    particle_frames_.push_back(frame);
    if (scene_.moving_grains()) {
      const long long n = static_cast<long long>(scene_.grains.size());
      XdmfFrame grains;
      grains.time = time;
      grains.file = file;
      grains.mesh.count = n;
      grains.mesh.positions = "/grains/centre";
      for (const char* name : {"velocity", "spin", "fluid_force", "contact_force"})
        grains.attributes.push_back({name, std::string("/grains/") + name, {n, 3}, true, false, 8});
      grains.attributes.push_back({"radius", "/grains/radius", {n}, false, false, 8});
      grains.attributes.push_back({"contacts", "/grains/contacts", {n}, false, true, 4});
      grain_frames_.push_back(grains);
    }
    if (scene_.grid_points.empty()) return;
    XdmfFrame grid;
    grid.time = time;
    grid.file = file;
    grid.mesh.regular_grid = true;
    std::vector<long long> points;
    std::vector<double> origin, spacing;
    for (int d = 0; d < Dim; ++d) {
      points.push_back(scene_.grid_points[d]);
      spacing.push_back(scene_.cell_size[d] / scene_.grid_points[d]);
      origin.push_back(0.5 * spacing.back());
    }
    grid.mesh.points = grid_shape(points, 1);
    grid.mesh.origin.assign(origin.rbegin(), origin.rend());
    grid.mesh.spacing.assign(spacing.rbegin(), spacing.rend());
    if (Dim == 2) {
      grid.mesh.origin.insert(grid.mesh.origin.begin(), 0.0);
      grid.mesh.spacing.insert(grid.mesh.spacing.begin(), spacing[0]);
    }
    auto vector_shape = grid.mesh.points;
    vector_shape.push_back(3);
    grid.attributes.push_back({"velocity", "/grid_velocity", vector_shape, true, false, 8});
    grid.attributes.push_back({"pressure", "/grid_pressure", grid.mesh.points, false, false, 8});
    grid.attributes.push_back({"solid", "/grid_solid", grid.mesh.points, false, false, 8});
    grid_frames_.push_back(grid);
  }

  SceneConfig scene_;
  std::string dir_, suffix_;
  std::vector<double> steps_, times_;
  std::vector<XdmfFrame> particle_frames_, grid_frames_, grain_frames_;
};

}  // namespace poresph
