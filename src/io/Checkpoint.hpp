#pragma once
// checkpoint.h5, the state `poresph SCENE.xml --restart` continues from:
// every owned particle field by its label, the positions at the last
// neighbour-list build, each process's box and row count, the step, and
// where the run stands (RunState). Small scalars are attributes of the root
// group; everything that can grow (the parameter list, the frames written,
// the steady-state window) is a dataset under run/, because an attribute
// lives in an object header of 64 kB (1,500 inline grains overflowed it).
//
// Two guards against continuing the wrong thing: a fingerprint of what
// defines the physics (cell, spacing, fluid, walls, grains, dimension, the
// derived sound speed and time step), compared with the scene's before any
// work; and a checksum of every dataset's rows (io/Checksum.hpp), checked as
// the particles are read, so that a damaged file is refused, not loaded.
#include <mpi.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "io/Checksum.hpp"
#include "io/Hdf5File.hpp"
#include "io/RunState.hpp"
#include "scene/SceneConfig.hpp"
#include "io/ViewRows.hpp"
#include "parallel/Decomposition.hpp"

namespace poresph {

// The layout of checkpoint.h5; a checkpoint of another layout is refused
// with a message, not read wrongly. 4: the stages' records hold their
// neighbour-list builds and superficial velocity, and the run state the
// steady-state verdict, the channel profile's samples and the builds. 7:
// moving grains' state (run/moving_grains) and grains_history.csv's rows.
constexpr const char* kCheckpointFormat = "poresph checkpoint 8";

// What defines the physics of a run, as "name = value" lines: a checkpoint
// continues only a scene with the same lines. time_step and sound_speed are
// the derived ones (app/Simulation.hpp's derive_parameters).
std::string physics_fingerprint(const SceneConfig& scene, double time_step, double sound_speed);

// A checkpoint's description, read by every process before the particles.
struct CheckpointInfo {
  int dimension = 0;
  long long step = 0;
  double time = 0;
  int ranks = 0;
  bool rates_valid = false;
  std::vector<double> boxes;  // lo, hi per direction per rank
  std::string parameters;
  std::string fingerprint;
  RunState state;
};

// Reads and checks the description (format, checksums of the metadata).
// Throws std::invalid_argument for a file that is not a checkpoint of this
// PoreSPH or is damaged.
CheckpointInfo read_checkpoint_info(const std::string& path, MPI_Comm comm);

// Refuses (std::invalid_argument) a checkpoint whose fingerprint differs from
// `fingerprint`, naming every line that differs with both values.
void check_checkpoint_matches(const CheckpointInfo& info, const std::string& path, const std::string& fingerprint);

namespace checkpoint_detail {

inline long long as_signed(std::uint64_t bits) {
  long long value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// Rows of a global array, and their checksum as the dataset's attribute.
template <class T>
void write_checked(Hdf5File& file, MPI_Comm comm, const std::string& name, const T* data, long long rows,
                   int columns) {
  const long long first = file.write_rows(name, data, rows, columns);
  std::uint64_t sum = row_checksum(data, rows, columns > 0 ? columns : 1, first);
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_UINT64_T, MPI_SUM, comm);
  file.set_dataset_attribute(name, "checksum", as_signed(sum));
}

// Rows [first, first + count), refused if the rows of all processes together
// do not match the checksum written with them.
template <class T>
std::vector<T> read_checked(Hdf5File& file, MPI_Comm comm, const std::string& name, long long first,
                            long long count) {
  // Rows the checkpoint's own record places where the dataset has none: cut
  // short. Agreed before the read, which every process must join.
  const auto shape = file.shape(name);
  int short_rows = shape.empty() || first < 0 || count < 0 || first + count > shape[0];
  MPI_Allreduce(MPI_IN_PLACE, &short_rows, 1, MPI_INT, MPI_MAX, comm);
  if (short_rows) {
    const std::string rows = shape.empty() ? "no" : std::to_string(shape[0]);
    throw std::invalid_argument(file.path() + ": '" + name + "' holds " + rows +
                                " rows, fewer than the checkpoint records: the checkpoint is damaged");
  }
  auto values = file.read_rows<T>(name, first, count);
  const long long per_row = shape.size() == 2 ? shape[1] : 1;
  std::uint64_t sum = row_checksum(values.data(), count, per_row, first);
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_UINT64_T, MPI_SUM, comm);
  if (as_signed(sum) != file.dataset_integer_attribute(name, "checksum"))
    throw std::invalid_argument(file.path() + ": the data of '" + name +
                                "' do not match their checksum: the checkpoint is damaged");
  return values;
}

// Metadata: written by the first process, read whole by every process.
template <class T>
void write_whole(Hdf5File& file, MPI_Comm comm, const std::string& name, const std::vector<T>& values) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  write_checked(file, comm, name, values.data(), rank == 0 ? static_cast<long long>(values.size()) : 0, 0);
}
template <class T>
std::vector<T> read_whole(Hdf5File& file, MPI_Comm comm, const std::string& name) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const long long n = file.shape(name).at(0);
  // Each process checks all of it: only the first one's sum may count.
  auto values = file.read_rows<T>(name, 0, n);
  std::uint64_t sum = rank == 0 ? row_checksum(values.data(), n, 1, 0) : 0;
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_UINT64_T, MPI_SUM, comm);
  if (as_signed(sum) != file.dataset_integer_attribute(name, "checksum"))
    throw std::invalid_argument(file.path() + ": the data of '" + name +
                                "' do not match their checksum: the checkpoint is damaged");
  return values;
}

// The root group's scalar attributes as one checked list.
std::uint64_t scalars_checksum(const std::vector<double>& values);

}  // namespace checkpoint_detail

// Writes checkpoint.h5 of `sim` (an app/Simulation<Dim, ...>). rates_valid =
// false for the state rewound after a failure.
template <int Dim, class Sim>
void write_checkpoint(const Sim& sim, const std::string& path, const RunState& state,
                      const std::string& parameters_xml, const std::string& fingerprint, bool rates_valid) {
  using namespace checkpoint_detail;
  const auto& P = sim.particles();
  const auto& comm = sim.communicator();
  const MPI_Comm c = comm.comm();
  const int n = P.owned;
  write_hdf5_atomically(path, c, [&](Hdf5File& file) {
    file.set_attribute("format", std::string(kCheckpointFormat));
    file.set_attribute("poresph_version", std::string(PORESPH_VERSION));
    std::vector<double> scalars;  // in this order, for their checksum
    auto scalar = [&](const char* name, auto value) {
      file.set_attribute(name, value);
      scalars.push_back(static_cast<double>(value));
    };
    scalar("dimension", static_cast<long long>(Dim));
    scalar("step", sim.steps());
    scalar("time", sim.time());
    scalar("ranks", static_cast<long long>(comm.size()));
    scalar("rates_valid", static_cast<long long>(rates_valid));
    scalar("drive_axis", static_cast<long long>(state.drive_axis));
    RunState::for_each_value(state, [&](const char* name, const auto& value) {
      if constexpr (std::is_same_v<std::decay_t<decltype(value)>, double>) scalar(name, value);
      else write_whole(file, c, std::string("run/") + name, value);
    });
    file.set_attribute("scalars_checksum", as_signed(scalars_checksum(scalars)));
    write_whole(file, c, "run/parameters", std::vector<char>(parameters_xml.begin(), parameters_xml.end()));
    write_whole(file, c, "run/fingerprint", std::vector<char>(fingerprint.begin(), fingerprint.end()));
    std::vector<double> boxes;
    for (int r = 0; r < comm.size(); ++r)
      for (int d = 0; d < Dim; ++d)
        boxes.push_back(sim.decomposition().box(r).lo[d]), boxes.push_back(sim.decomposition().box(r).hi[d]);
    write_whole(file, c, "run/boxes", boxes);
    const long long rows = n;
    write_checked(file, c, "rank_rows", &rows, 1, 0);
    P.for_each_owned_field([&](const auto& view) {
      with_owned_rows(view, n, [&](const auto* values) {
        write_checked(file, c, view.label(), values, n, std::decay_t<decltype(view)>::rank == 2 ? Dim : 0);
      });
    });
    // Moving grains: the fluid's mass their support was made from, then their state.
    if (sim.rigid_grains().moving()) {
      std::vector<double> grains{sim.rigid_grains().fluid_mass()};
      const auto bodies = sim.rigid_grains().state();
      grains.insert(grains.end(), bodies.begin(), bodies.end());
      write_whole(file, c, "run/moving_grains", grains);
    }
    if (rates_valid)
      with_owned_rows(sim.positions_at_build(), n,
                      [&](const double* values) { write_checked(file, c, "x_at_build", values, n, Dim); });
  });
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
// Every array is checked against its checksum as it is read.
template <int Dim, class Sim>
void load_checkpoint(Sim& sim, const std::string& path, const CheckpointInfo& info) {
  using namespace checkpoint_detail;
  const auto& comm = sim.communicator();
  const MPI_Comm c = comm.comm();
  Hdf5File file(path, Hdf5File::Mode::Read, c);
  const bool same_layout = info.ranks == comm.size();
  const auto all_rows = read_checked<long long>(file, c, "rank_rows", comm.rank() == 0 ? 0 : info.ranks,
                                                comm.rank() == 0 ? info.ranks : 0);
  std::vector<long long> rows(info.ranks);
  if (comm.rank() == 0) rows = all_rows;
  MPI_Bcast(rows.data(), info.ranks, MPI_LONG_LONG, 0, c);
  long long total = 0, first = 0, count = 0;
  for (int r = 0; r < info.ranks; ++r) {
    if (same_layout && r < comm.rank()) first += rows[r];
    total += rows[r];
  }
  if (same_layout) {
    count = rows[comm.rank()];
  } else {
    first = total * comm.rank() / comm.size();
    count = total * (comm.rank() + 1) / comm.size() - first;
  }
  auto& P = sim.particles();
  P.reserve(static_cast<int>(count));
  P.owned = static_cast<int>(count);
  P.ghosts = 0;
  // A checkpoint from before levels kept their start: the next level starts
  // from this one's flow alone (app/Simulation.hpp, warm_start).
  if (P.has_level_start && !file.has("v_level_start")) P.has_level_start = false;
  P.for_each_owned_field([&](const auto& view) {
    using Value = typename std::decay_t<decltype(view)>::non_const_value_type;
    if (!file.has(view.label()))
      throw std::invalid_argument(path + " has no field '" + view.label() +
                                  "': it was written by a scene without walls, grains or shifting that this one has, "
                                  "or the file is damaged");
    load_rows(view, read_checked<Value>(file, c, view.label(), first, count));
  });
  if (sim.scene().moving_grains()) {
    if (!file.has("run/moving_grains"))
      throw std::invalid_argument(path + " holds no moving grains' state: it was written by a scene whose grains "
                                  "hold still, or by a PoreSPH that did not keep them");
    const auto grains = read_whole<double>(file, c, "run/moving_grains");
    sim.restore_grains(grains.at(0), std::vector<double>(grains.begin() + 1, grains.end()));
  }
  typename Sim::ParticleSet::Vector x_at_build;
  if (same_layout && info.rates_valid) {
    x_at_build = decltype(x_at_build)("checkpoint_x_at_build", count);
    load_rows(x_at_build, read_checked<double>(file, c, "x_at_build", first, count));
  }
  sim.resume(info.step, x_at_build, info.rates_valid);
}

}  // namespace poresph
