#pragma once
// What a run leaves behind for people and for the next run: HDF5 field files
// with their XDMF descriptions (particles as points, the gridded view as an
// image), and checkpoints that `--restart` continues from. Every file is
// written under a temporary name and renamed when complete.
#include <Kokkos_Core.hpp>

#include <array>
#include <cstdio>
#include <stdexcept>
#include <type_traits>
#include <string>
#include <vector>

#include "app/Simulation.hpp"
#include "io/Hdf5File.hpp"
#include "io/Summary.hpp"
#include "io/Xdmf.hpp"

namespace poresph {

// Owned rows of a View as a contiguous host array (View layouts may pad).
template <class View>
auto owned_rows(const View& view, int owned) {
  using Value = typename View::non_const_value_type;
  const int columns = View::rank == 2 ? static_cast<int>(view.extent(1)) : 1;
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view);
  std::vector<Value> rows(static_cast<size_t>(owned) * columns);
  for (int i = 0; i < owned; ++i)
    for (int c = 0; c < columns; ++c) {
      if constexpr (View::rank == 2) rows[static_cast<size_t>(i) * columns + c] = host(i, c);
      else rows[i] = host(i);
    }
  return rows;
}

// Writes rows back into the first rows of a View.
template <class View, class Value>
void load_rows(const View& view, const std::vector<Value>& rows) {
  auto host = Kokkos::create_mirror_view(view);
  const int columns = View::rank == 2 ? static_cast<int>(view.extent(1)) : 1;
  const size_t count = rows.size() / columns;
  Kokkos::deep_copy(host, view);
  for (size_t i = 0; i < count; ++i)
    for (int c = 0; c < columns; ++c) {
      if constexpr (View::rank == 2) host(i, c) = rows[i * columns + c];
      else host(i) = rows[i];
    }
  Kokkos::deep_copy(view, host);
}

// Field files fields_<step>.h5 in the output directory, with particles.xmf
// and (with a grid) grid.xmf describing all of them as one time series.
template <int Dim, class ExecSpace>
class FieldWriter {
 public:
  FieldWriter(const SceneConfig& scene, const std::string& output_dir, const std::string& suffix)
      : scene_(scene), dir_(output_dir), suffix_(suffix) {}

  // Frames written before a restart, so that the descriptions keep them.
  void add_earlier_frames(const std::vector<double>& steps, const std::vector<double>& times, long long particles) {
    for (size_t k = 0; k < steps.size(); ++k) add_frame(static_cast<long long>(steps[k]), times[k], particles);
  }
  const std::vector<double>& frame_steps() const { return steps_; }
  const std::vector<double>& frame_times() const { return times_; }

  void write(Simulation<Dim, ExecSpace>& sim) {
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
            double value = rows[static_cast<size_t>(i) * Dim + d];
            // Positions stay unwrapped between neighbour-list rebuilds: wrap for output.
            if (wrap && scene_.periodic[d])
              value -= scene_.cell_size[d] * std::floor(value / scene_.cell_size[d]);
            out[static_cast<size_t>(i) * 3 + d] = value;
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
      if (!scene_.grid_points.empty()) write_grid(file, block, grid_values);
    });
    add_frame(sim.steps(), sim.time(), total);
    if (comm.rank() == 0) {
      write_file_atomically(dir_ + "/particles" + suffix_ + ".xmf", xdmf_time_series("particles", particle_frames_));
      if (!scene_.grid_points.empty())
        write_file_atomically(dir_ + "/grid" + suffix_ + ".xmf", xdmf_time_series("grid", grid_frames_));
    }
  }

 private:
  std::string file_name(long long step) const {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "fields%s_%09lld.h5", suffix_.c_str(), step);
    return buffer;
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
    }
    particle_frames_.push_back(frame);
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
  std::vector<XdmfFrame> particle_frames_, grid_frames_;
};

// What a checkpoint holds besides the particles: where the run stands.
struct RunState {
  int drive_axis = -1;                     // the body-force direction being run (tensor runs), or -1
  std::vector<double> completed_columns;   // k columns of axes already run: axis, k_0j .. k_(D-1)j, steady
  std::vector<double> steady_times, steady_values;  // the steady-state detector's window
  double steady_first_time = 0;
  std::vector<double> frame_steps, frame_times;     // field files so far
  double max_density_variation = 0, max_density_drift = 0;
  double particles_inside_grains = 0, max_grain_penetration = 0;
  double grain_surface_corrections = 0, max_corrected_depth = 0;

  // f(name, member) for every member but drive_axis: the checkpoint writes
  // and reads the same list, each under its attribute name.
  template <class State, class F>
  static void for_each_attribute(State& state, F&& f) {
    f("completed_columns", state.completed_columns);
    f("steady_times", state.steady_times);
    f("steady_values", state.steady_values);
    f("steady_first_time", state.steady_first_time);
    f("frame_steps", state.frame_steps);
    f("frame_times", state.frame_times);
    f("max_density_variation", state.max_density_variation);
    f("max_density_drift", state.max_density_drift);
    f("particles_inside_grains", state.particles_inside_grains);
    f("max_grain_penetration", state.max_grain_penetration);
    f("grain_surface_corrections", state.grain_surface_corrections);
    f("max_corrected_depth", state.max_corrected_depth);
  }
};

// checkpoint.h5: every owned field by its label, the positions at the last
// neighbour-list build, the boxes and rows of each process, the step, and
// the run state. rates_valid = false for the state rewound after a failure.
template <int Dim, class ExecSpace>
void write_checkpoint(const Simulation<Dim, ExecSpace>& sim, const std::string& path, const RunState& state,
                      const std::string& parameters_xml, bool rates_valid) {
  const auto& P = sim.particles();
  const auto& comm = sim.communicator();
  const int n = P.owned;
  write_hdf5_atomically(path, comm.comm(), [&](Hdf5File& file) {
    file.set_attribute("format", std::string("poresph checkpoint 1"));
    file.set_attribute("poresph_version", std::string(PORESPH_VERSION));
    file.set_attribute("dimension", static_cast<long long>(Dim));
    file.set_attribute("step", sim.steps());
    file.set_attribute("time", sim.time());
    file.set_attribute("ranks", static_cast<long long>(comm.size()));
    file.set_attribute("rates_valid", static_cast<long long>(rates_valid));
    file.set_attribute("parameters", parameters_xml);
    std::vector<double> boxes;
    for (int r = 0; r < comm.size(); ++r)
      for (int d = 0; d < Dim; ++d)
        boxes.push_back(sim.decomposition().box(r).lo[d]), boxes.push_back(sim.decomposition().box(r).hi[d]);
    file.set_attribute("boxes", boxes);
    file.set_attribute("drive_axis", static_cast<long long>(state.drive_axis));
    RunState::for_each_attribute(state, [&](const char* name, const auto& value) { file.set_attribute(name, value); });
    const long long rows = n;
    file.write_rows("rank_rows", &rows, 1, 0);
    P.for_each_owned_field([&](const auto& view) {
      const auto values = owned_rows(view, n);
      file.write_rows(view.label(), values.data(), n, std::decay_t<decltype(view)>::rank == 2 ? Dim : 0);
    });
    if (rates_valid) {
      const auto values = owned_rows(sim.positions_at_build(), n);
      file.write_rows("x_at_build", values.data(), n, Dim);
    }
  });
}

// A checkpoint's description, read by every process before the particles.
struct CheckpointInfo {
  int dimension = 0;
  long long step = 0;
  double time = 0;
  int ranks = 0;
  bool rates_valid = false;
  std::vector<double> boxes;  // lo, hi per direction per rank
  std::string parameters;
  RunState state;
};

inline CheckpointInfo read_checkpoint_info(const std::string& path, MPI_Comm comm) {
  Hdf5File file(path, Hdf5File::Mode::Read, comm);
  CheckpointInfo info;
  if (file.string_attribute("format") != "poresph checkpoint 1")
    throw std::runtime_error(path + " is not a PoreSPH checkpoint");
  info.dimension = static_cast<int>(file.integer_attribute("dimension"));
  info.step = file.integer_attribute("step");
  info.time = file.double_attribute("time");
  info.ranks = static_cast<int>(file.integer_attribute("ranks"));
  info.rates_valid = file.integer_attribute("rates_valid") != 0;
  info.boxes = file.double_array_attribute("boxes");
  info.parameters = file.string_attribute("parameters");
  auto& st = info.state;
  st.drive_axis = static_cast<int>(file.integer_attribute("drive_axis"));
  RunState::for_each_attribute(st, [&](const char* name, auto& value) {
    if constexpr (std::is_same_v<std::decay_t<decltype(value)>, double>) value = file.double_attribute(name);
    else value = file.double_array_attribute(name);
  });
  return info;
}

// The saved boxes if the checkpoint was written by as many processes as
// this run has (the run then continues bit for bit); none otherwise.
template <int Dim>
std::vector<Box<Dim>> checkpoint_boxes(const CheckpointInfo& info, int ranks) {
  std::vector<Box<Dim>> boxes;
  if (info.ranks != ranks) return boxes;
  for (int r = 0; r < ranks; ++r) {
    Box<Dim> b;
    for (int d = 0; d < Dim; ++d) b.lo[d] = info.boxes[(r * Dim + d) * 2], b.hi[d] = info.boxes[(r * Dim + d) * 2 + 1];
    boxes.push_back(b);
  }
  return boxes;
}

// Loads the particles of a checkpoint into `sim` (made with Start::Empty) and
// resumes it. On the same number of processes each reads the rows it wrote;
// otherwise each reads an equal share and particles then go to their owners.
template <int Dim, class ExecSpace>
void load_checkpoint(Simulation<Dim, ExecSpace>& sim, const std::string& path, const CheckpointInfo& info) {
  const auto& comm = sim.communicator();
  Hdf5File file(path, Hdf5File::Mode::Read, comm.comm());
  const bool same_layout = info.ranks == comm.size();
  const auto all_rows = file.read_rows<long long>("rank_rows", 0, info.ranks);
  long long total = 0, first = 0, count = 0;
  for (int r = 0; r < info.ranks; ++r) {
    if (same_layout && r < comm.rank()) first += all_rows[r];
    total += all_rows[r];
  }
  if (same_layout) {
    count = all_rows[comm.rank()];
  } else {
    first = total * comm.rank() / comm.size();
    count = total * (comm.rank() + 1) / comm.size() - first;
  }
  auto& P = sim.particles();
  P.reserve(static_cast<int>(count));
  P.owned = static_cast<int>(count);
  P.ghosts = 0;
  P.for_each_owned_field([&](const auto& view) {
    using Value = typename std::decay_t<decltype(view)>::non_const_value_type;
    if (!file.has(view.label()))
      throw std::runtime_error(path + " has no field '" + view.label() +
                               "': it was written by a scene without walls, grains or shifting that this one has");
    load_rows(view, file.read_rows<Value>(view.label(), first, count));
  });
  typename Simulation<Dim, ExecSpace>::ParticleSet::Vector x_at_build;
  if (same_layout && info.rates_valid) {
    x_at_build = decltype(x_at_build)("checkpoint_x_at_build", count);
    load_rows(x_at_build, file.read_rows<double>("x_at_build", first, count));
  }
  sim.resume(info.step, x_at_build, info.rates_valid);
}

}  // namespace poresph
